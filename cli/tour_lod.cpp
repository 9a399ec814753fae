// Tour step "lod": an LOD chain from one collapse sequence, each level with its measured
// Hausdorff and RMS distance to the input.

#include "tour.h"

#include <geom/lod/lod_chain.h>

#include <chrono>

namespace geom::cli {

void tour_lod(TourContext& tour) {
  tour.heading("Levels of detail");
  tour.text("`geom lod` / `geom simplify`: quadric edge collapses (Garland–Heckbert). The error "
            "is measured, not guessed: symmetric Hausdorff and RMS distance to the input by "
            "dense surface sampling on a BVH (`geom compare`), relative to the bounding-box "
            "diagonal.");
  LodChainOptions options;
  options.ratios = {0.5, 0.2, 0.05};
  options.distance.samples = 50000;
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<LodLevel> levels = lod_chain(tour.mesh, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<std::vector<std::string>> rows;
  nlohmann::json j = nlohmann::json::array();
  std::vector<std::pair<std::string, const SurfaceMesh*>> tiles{
      {"INPUT F=" + std::to_string(tour.mesh.n_faces()), &tour.mesh}};
  for (const LodLevel& l : levels) {
    const std::string name = tour.stem + "_lod" + std::to_string(static_cast<int>(l.ratio * 100)) + ".obj";
    tour.write_mesh(name, l.mesh, "LOD at " + TourContext::number(l.ratio) + " of the triangles");
    rows.push_back({TourContext::number(l.ratio), std::to_string(l.faces),
                    TourContext::number(l.error.relative_hausdorff()),
                    TourContext::number(l.error.relative_rms())});
    j.push_back({{"ratio", l.ratio}, {"faces", l.faces}, {"hausdorff_relative", l.error.relative_hausdorff()},
                 {"rms_relative", l.error.relative_rms()}});
    tiles.emplace_back("F=" + std::to_string(l.faces) + " H=" + TourContext::number(
                           std::round(l.error.relative_hausdorff() * 1e5) / 1e5),
                       &l.mesh);
  }
  tour.grid({"ratio", "triangles", "Hausdorff / diagonal", "RMS / diagonal"}, rows);
  tour.text("The whole chain, with its error measurements, took " + TourContext::number(seconds) + " s.");
  tour.preview_montage(tour.stem + "_lod.png", tiles, "an LOD chain with its measured error");
  tour.record({{"levels", j}, {"seconds", seconds}});
}

}  // namespace geom::cli
