// Tour step: marching cubes on built-in implicit surfaces (closed, manifold, with the
// Euler characteristic of the true surface) and on the signed distance to a mesh.

#include "tour.h"

#include <geom/isosurface/implicit.h>
#include <geom/isosurface/marching_cubes.h>
#include <geom/isosurface/mesh_sdf.h>

namespace geom::cli {

void tour_isosurface(TourContext& tour) {
  tour.heading("Iso-surfaces");
  tour.text("Marching cubes with face-consistent ambiguity resolution and MC33 interior "
            "tunnels: the output is closed, manifold and oriented whenever the level set is "
            "closed. A closed mesh is an implicit input too (its signed distance, --sdf).");
  struct Shape {
    const char* name;
    ScalarFunction f;
    double half;
    long expected_euler;
  };
  const Shape shapes[] = {{"torus", implicit::Torus{}, 1.0, 0},
                          {"genus3", implicit::Genus3{}, 1.25, -4}};
  std::vector<std::vector<std::string>> rows;
  std::vector<SurfaceMesh> surfaces;
  nlohmann::json j;
  for (const Shape& s : shapes) {
    ScalarGrid grid = sample(s.f, cube_box(s.half, 96));
    MarchingCubesResult r = marching_cubes(grid.view(), {.compute_normals = true});
    const long euler =
        long(r.mesh.n_vertices()) - long(r.mesh.n_edges()) + long(r.mesh.n_faces());
    tour.write_mesh(std::string("isosurface_") + s.name + ".ply", r.mesh,
                    std::string("marching cubes of the ") + s.name + " at 96³");
    surfaces.push_back(r.mesh);
    rows.push_back({s.name, std::to_string(r.stats.triangles), r.stats.closed ? "yes" : "no",
                    std::to_string(euler), std::to_string(s.expected_euler)});
    j[s.name] = {{"triangles", r.stats.triangles},
                 {"closed", r.stats.closed},
                 {"euler_characteristic", euler}};
  }
  // A mesh as an implicit input: the torus mesh's signed distance, contoured at +0.1 (an
  // offset surface, still a torus).
  {
    MeshSdf sdf = signed_distance_grid(surfaces[0], {.resolution = 64, .level = 0.1});
    MarchingCubesResult r = marching_cubes(sdf.grid.view(), {.level = 0.1});
    const long euler =
        long(r.mesh.n_vertices()) - long(r.mesh.n_edges()) + long(r.mesh.n_faces());
    tour.write_mesh("isosurface_torus_offset.ply", r.mesh,
                    "the torus mesh offset by 0.1 through its signed distance at 64³");
    rows.push_back({"torus mesh +0.1 (--sdf)", std::to_string(r.stats.triangles),
                    r.stats.closed ? "yes" : "no", std::to_string(euler), "0"});
    j["torus_offset"] = {{"triangles", r.stats.triangles},
                         {"closed", r.stats.closed},
                         {"euler_characteristic", euler},
                         {"exact_samples", sdf.stats.exact_samples},
                         {"samples", sdf.stats.samples}};
  }
  tour.grid({"surface", "triangles", "closed", "Euler characteristic", "expected"}, rows);
  tour.preview_montage("isosurfaces.png",
                       {{"TORUS", &surfaces[0]}, {"GENUS 3", &surfaces[1]}},
                       "marching cubes at 96^3");
  tour.record(j);
}

}  // namespace geom::cli
