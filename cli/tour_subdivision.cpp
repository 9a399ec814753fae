// Tour step "subdivision": Catmull-Clark levels 1-2, and level 1 pushed to the limit surface.

#include "tour.h"

#include <geom/subdivision/subdivision.h>

#include <chrono>

namespace geom::cli {

namespace {

/// Non-manifold input as given: three quads on one edge (a fin), refined as OpenSubdiv
/// refines it. Its level 1 has V + E + F vertices: no vertex was split apart.
nlohmann::json as_given_fin(TourContext& tour) {
  PolygonSoup fin;
  fin.positions = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0.1}, {1, 1, 0}, {-1, 0, 0}, {-1, 1, 0.2},
                   {0, 0, 1}, {0, 1, 1.1}};
  fin.add_face({0, 1, 3, 2});
  fin.add_face({1, 0, 4, 5});
  fin.add_face({0, 1, 7, 6});
  SubdivideOptions o;
  o.levels = 2;
  const SoupSubdivideResult r = subdivide(fin, o);
  tour.text("Non-manifold input is refined as given, as OpenSubdiv refines it: three quads on "
            "one edge come out with " + std::to_string(r.nonmanifold_edges) +
            " non-manifold edge made infinitely sharp, " + std::to_string(r.per_level[1].vertices) +
            " vertices at level 1 (V + E + F = 8 + 10 + 3) and " +
            std::to_string(r.per_level[2].vertices) + " at level 2; the " +
            std::to_string(r.split_vertices) +
            " copies the half-edge core needed are joined again.");
  return {{"nonmanifold_edges", r.nonmanifold_edges},
          {"level1_vertices", r.per_level[1].vertices},
          {"level2_vertices", r.per_level[2].vertices},
          {"split_vertices", r.split_vertices}};
}

}  // namespace

void tour_subdivision(TourContext& tour) {
  tour.heading("Subdivision");
  tour.text("`geom subdivide --levels N [--limit]`: Catmull-Clark with OpenSubdiv's rules (the "
            "same numbers, vertex for vertex). \"Limit move\" is how far the vertices moved "
            "onto the limit surface: the error of the plain level as samples of it.");
  std::vector<std::vector<std::string>> rows;
  std::vector<SurfaceMesh> levels_kept;
  nlohmann::json runs = nlohmann::json::array();
  for (int levels : {1, 2}) {
    for (bool limit : {false, true}) {
      if (levels == 2 && limit) continue;
      SubdivideOptions o;
      o.levels = levels;
      o.limit = limit;
      const auto t0 = std::chrono::steady_clock::now();
      SubdivideResult r = subdivide(tour.mesh, o);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      const std::string name = tour.stem + "_cc" + std::to_string(levels) + (limit ? "_limit" : "") + ".obj";
      tour.write_mesh(name, r.mesh,
                      "Catmull-Clark level " + std::to_string(levels) + (limit ? ", on the limit surface" : ""));
      if (!limit) levels_kept.push_back(r.mesh);
      rows.push_back({std::to_string(levels), limit ? "yes" : "no", std::to_string(r.mesh.n_faces()),
                      TourContext::number(seconds),
                      limit ? TourContext::number(r.limit_max_distance) : "-"});
      runs.push_back({{"levels", levels}, {"limit", limit}, {"faces", r.mesh.n_faces()},
                      {"seconds", seconds}, {"limit_max_distance", r.limit_max_distance}});
    }
  }
  tour.grid({"levels", "limit", "faces", "seconds", "limit move (max)"}, rows);
  std::vector<std::pair<std::string, const SurfaceMesh*>> tiles{
      {"INPUT F=" + std::to_string(tour.mesh.n_faces()), &tour.mesh}};
  for (std::size_t i = 0; i < levels_kept.size(); ++i)
    tiles.emplace_back("LEVEL " + std::to_string(i + 1) + " F=" + std::to_string(levels_kept[i].n_faces()),
                       &levels_kept[i]);
  tour.preview_montage(tour.stem + "_subdivision.png", tiles, "Catmull-Clark levels");
  tour.record({{"runs", runs}, {"as_given", as_given_fin(tour)}});
}

}  // namespace geom::cli
