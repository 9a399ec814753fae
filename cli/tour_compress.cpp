// Tour step "compress": the codec at several quantisation depths — size against error.

#include "tour.h"

#include <geom/compress/container/codec.h>
#include <geom/spatial/distance.h>

#include <cmath>
#include <fstream>

namespace geom::cli {

void tour_compress(TourContext& tour) {
  tour.heading("Compression");
  tour.text("`geom compress --bits B`: Edgebreaker-style connectivity coding, parallelogram "
            "prediction and rANS entropy coding. Fewer bits, smaller files, larger error: each "
            "coordinate moves at most half a grid step, so a vertex at most sqrt(3) times that "
            "(the bound below), and the surface no further: every polygon keeps its first "
            "corner, so it is cut into the same triangles. The measured distance stays within it.");
  std::vector<std::vector<std::string>> rows;
  nlohmann::json j = nlohmann::json::array();
  std::vector<SurfaceMesh> decoded;
  std::vector<std::string> labels;
  for (unsigned bits : {6u, 8u, 11u, 14u}) {
    CompressResult c = compress(tour.mesh, {.bits = bits});
    const std::string name = tour.stem + "_" + std::to_string(bits) + "bit.gmc";
    const auto p = tour.path(name);
    std::ofstream(p, std::ios::binary).write(reinterpret_cast<const char*>(c.bytes.data()),
                                            static_cast<std::streamsize>(c.bytes.size()));
    tour.add_file(p, std::to_string(bits) + "-bit compressed mesh");
    DecompressResult d = decompress(c.bytes);
    MeshDistance e = mesh_distance(tour.mesh, d.mesh, {.samples = 20000});
    const double bpv = 8.0 * c.bytes.size() / std::max<std::size_t>(1, tour.mesh.n_vertices());
    rows.push_back({std::to_string(bits), std::to_string(c.bytes.size()), TourContext::number(std::round(bpv * 100) / 100),
                    TourContext::number(std::sqrt(3.0) * c.stats.max_error), TourContext::number(e.hausdorff)});
    j.push_back({{"bits", bits}, {"bytes", c.bytes.size()}, {"bits_per_vertex", bpv},
                 {"error_bound", std::sqrt(3.0) * c.stats.max_error}, {"hausdorff", e.hausdorff}});
    labels.push_back(std::to_string(bits) + " BITS " + std::to_string(c.bytes.size()) + " B");
    decoded.push_back(std::move(d.mesh));
  }
  tour.grid({"bits", "bytes", "bits per vertex", "vertex error bound", "measured Hausdorff"}, rows);
  std::vector<std::pair<std::string, const SurfaceMesh*>> tiles;
  for (std::size_t i = 0; i < decoded.size(); ++i) tiles.emplace_back(labels[i], &decoded[i]);
  tour.preview_montage(tour.stem + "_compress.png", tiles, "decoded at each bit depth");
  tour.record({{"runs", j}});
}

}  // namespace geom::cli
