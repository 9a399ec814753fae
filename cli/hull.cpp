// geom hull: convex hull of a 2D or 3D point file.

#include "commands.h"
#include "common.h"
#include "svg.h"

#include <geom/compgeom/hull2.h>
#include <geom/compgeom/hull3.h>
#include <geom/io/points.h>

#include <memory>

namespace geom::cli {

void add_hull_command(CLI::App& app) {
  struct Args {
    std::string input;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "hull",
      "Convex hull of 2D or 3D points (exact predicates); OBJ/PLY (3D) or SVG (2D) out", [args] {
        require_svg_or_mesh_output(args->common.output);
        PointSet ps = read_points(args->input);
        // Output vertices are the input points in input order; faces index them.
        std::vector<std::vector<std::uint32_t>> faces;
        nlohmann::json j = {{"points", ps.points.size()}, {"dimension_of_input", ps.dimension}};
        std::string text;
        std::vector<Eigen::Vector2d> p2;
        if (ps.dimension == 2) {
          for (const auto& q : ps.points) p2.push_back(q.head<2>());
          Hull2Result h = convex_hull_2d(p2);
          if (h.vertices.size() >= 3) faces.push_back(h.vertices);
          j["hull_vertices"] = h.vertices.size();
          j["degenerate"] = h.degenerate;
          text = std::to_string(h.vertices.size()) + " hull vertices" +
                 (h.degenerate ? " (degenerate)" : "");
        } else {
          Hull3Result h = convex_hull_3d(ps.points);
          for (const auto& t : h.triangles) faces.push_back({t[0], t[1], t[2]});
          if (h.planar && h.polygon.size() >= 3) faces.push_back(h.polygon);
          j["hull_vertices"] = h.vertices.size();
          j["facets"] = h.triangles.size();
          j["dimension"] = h.dimension;
          j["planar"] = h.planar;
          j["exact_fallback_rate"] = h.predicates.exact_rate();
          text = std::to_string(h.vertices.size()) + " hull vertices, " +
                 std::to_string(h.triangles.size()) + " triangles" +
                 (h.planar ? " (all coplanar)" : "");
        }
        if (!args->common.output.empty()) {
          check_not_input(args->common.output, {args->input}, args->common);
          if (is_svg(args->common.output)) {
            if (ps.dimension != 2) throw UsageError("SVG output needs 2D points");
            Svg svg;
            for (const auto& f : faces) {
              std::vector<Eigen::Vector2d> poly;
              for (auto i : f) poly.push_back(p2[i]);
              svg.polygon(poly, "fill:#e6f0e0;stroke:#253;stroke-width:1");
            }
            svg.points(p2, "#123");
            svg.write(args->common.output);
          } else {
            SurfaceMesh mesh;
            std::vector<Vertex> v;
            for (const auto& q : ps.points) v.push_back(mesh.add_vertex(q));
            for (const auto& f : faces) {
              std::vector<Vertex> fv;
              for (auto i : f) fv.push_back(v[i]);
              mesh.add_face(fv);
            }
            write_output(mesh, {args->input}, args->common);
          }
        }
        report(args->common, j, text);
        return 0;
      });
  cmd->add_option("input", args->input, "Point file (x y [z] per line, or a mesh's vertices)")
      ->required();
  add_common_options(cmd, args->common, kOutput | kJson | kQuiet | kForce);
}

}  // namespace geom::cli
