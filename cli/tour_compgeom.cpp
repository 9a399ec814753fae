// Tour step "compgeom": the convex hull of the vertices, and the Delaunay triangulation and
// clipped Voronoi diagram of their projection on the xz plane — all on exact predicates.

#include "svg.h"
#include "tour.h"

#include <geom/compgeom/delaunay2.h>
#include <geom/compgeom/hull3.h>
#include <geom/compgeom/voronoi2.h>

namespace geom::cli {

void tour_compgeom(TourContext& tour) {
  tour.heading("Computational geometry");
  tour.text("`geom hull`, `geom delaunay`, `geom voronoi`: every orientation and in-circle "
            "decision is exact (adaptive arithmetic, symbolic perturbation for ties).");
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector2d> plane;
  for (Vertex v : tour.mesh.vertices()) {
    points.push_back(tour.mesh.position(v));
    plane.emplace_back(points.back().x(), points.back().z());
  }
  Hull3Result hull = convex_hull_3d(points);
  SurfaceMesh hull_surface = hull_mesh(points, hull);
  if (!hull_surface.is_empty()) tour.write_mesh(tour.stem + "_hull.obj", hull_surface, "convex hull of the vertices");
  DelaunayResult dt = delaunay_2d(plane);
  VoronoiResult vd = voronoi_2d(plane);
  Svg svg;
  for (const auto& cell : vd.cells) svg.polygon(cell, "fill:#dde6f0;stroke:#334;stroke-width:0.6");
  svg.points(plane, "#c22");
  const auto p = tour.path(tour.stem + "_voronoi.svg");
  svg.write(p.string());
  tour.add_file(p, "Voronoi diagram of the vertices projected on xz, clipped to the box");
  tour.table({{"points", std::to_string(points.size())},
              {"hull vertices", std::to_string(hull.vertices.size())},
              {"hull triangles", std::to_string(hull.triangles.size())},
              {"Delaunay triangles (xz)", std::to_string(dt.triangles.size())},
              {"duplicates merged (xz)", std::to_string(dt.duplicates)},
              {"cocircular ties decided symbolically", std::to_string(dt.cocircular)},
              {"Voronoi cells", std::to_string(vd.cells.size())}});
  if (!hull_surface.is_empty())
    tour.preview_montage(tour.stem + "_hull.png", {{"INPUT", &tour.mesh}, {"CONVEX HULL", &hull_surface}},
                         "the input and its convex hull");
  tour.text("![Voronoi diagram](" + tour.stem + "_voronoi.svg)");
  tour.record({{"hull_vertices", hull.vertices.size()}, {"hull_triangles", hull.triangles.size()},
               {"delaunay_triangles", dt.triangles.size()}, {"voronoi_cells", vd.cells.size()}});
}

}  // namespace geom::cli
