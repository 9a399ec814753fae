// geom delaunay: Delaunay (or constrained Delaunay) triangulation of a 2D point file.

#include "commands.h"
#include "common.h"
#include "svg.h"

#include <geom/compgeom/delaunay2.h>
#include <geom/io/points.h>

#include <cmath>
#include <memory>

namespace geom::cli {

namespace {

std::vector<Eigen::Vector2d> to_2d(const PointSet& ps) {
  std::vector<Eigen::Vector2d> p(ps.points.size());
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = ps.points[i].head<2>();
  return p;
}

// Segments come as a point file whose "points" are index pairs.
std::vector<Segment> read_segments(const std::string& path, std::size_t n) {
  PointSet s = read_points(path);
  std::vector<Segment> segs;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    double a = s.points[i].x(), b = s.points[i].y();
    auto valid = [&](double x) { return x >= 0 && x < double(n) && std::floor(x) == x; };
    if (!valid(a) || !valid(b))
      throw Error("'" + path + "': segment " + std::to_string(i) +
                  " must be two point indices in [0, " + std::to_string(n) + ")");
    segs.push_back({static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b)});
  }
  return segs;
}

}  // namespace

void add_delaunay_command(CLI::App& app) {
  struct Args {
    std::string input, constraints;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "delaunay", "Delaunay triangulation of 2D points (exact predicates); OBJ/PLY/SVG out",
      [args] {
        require_svg_or_mesh_output(args->common.output);
        PointSet ps = read_points(args->input);
        std::vector<Eigen::Vector2d> p = to_2d(ps);
        ConstrainedDelaunayResult r;
        if (!args->constraints.empty()) {
          r = constrained_delaunay_2d(p, read_segments(args->constraints, p.size()));
        } else {
          static_cast<DelaunayResult&>(r) = delaunay_2d(p);
        }
        if (!args->common.output.empty()) {
          check_not_input(args->common.output, {args->input, args->constraints}, args->common);
          if (is_svg(args->common.output)) {
            Svg svg;
            for (const auto& t : r.triangles)
              svg.polygon({p[t[0]], p[t[1]], p[t[2]]}, "fill:#dde8f5;stroke:#345;stroke-width:0.5");
            for (const auto& s : r.constrained_edges)
              svg.polygon({p[s.a], p[s.b]}, "fill:none;stroke:#c22;stroke-width:1.5");
            svg.points(p, "#123");
            svg.write(args->common.output);
          } else {
            // Output vertices are the input points in input order.
            SurfaceMesh mesh;
            std::vector<Vertex> v;
            for (const auto& q : ps.points) v.push_back(mesh.add_vertex(q));
            for (const auto& t : r.triangles) mesh.add_triangle(v[t[0]], v[t[1]], v[t[2]]);
            write_output(mesh, {args->input}, args->common);
          }
        }
        nlohmann::json j = {{"points", p.size()},
                            {"vertices", r.vertices},
                            {"duplicates", r.duplicates},
                            {"triangles", r.triangles.size()},
                            {"collinear", r.collinear},
                            {"cocircular", r.cocircular},
                            {"constrained_edges", r.constrained_edges.size()},
                            {"split_segments", r.split_segments},
                            {"exact_fallback_rate", r.predicates.exact_rate()}};
        std::string text = std::to_string(r.triangles.size()) + " triangles over " +
                           std::to_string(r.vertices) + " vertices (" +
                           std::to_string(r.duplicates) + " duplicates merged" +
                           (r.collinear ? ", all collinear" : "") + ")";
        report(args->common, j, text);
        return 0;
      });
  cmd->add_option("input", args->input, "Point file (x y per line, or a mesh's vertices)")
      ->required();
  cmd->add_option("--constraints", args->constraints,
                  "File of segments as point-index pairs (a constrained triangulation)");
  add_common_options(cmd, args->common, kOutput | kJson | kQuiet | kForce);
}

}  // namespace geom::cli
