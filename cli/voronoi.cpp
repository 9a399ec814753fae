// geom voronoi: Voronoi cells of a 2D point file, clipped to a box; SVG or OBJ out.

#include "commands.h"
#include "common.h"
#include "svg.h"

#include <geom/compgeom/voronoi2.h>
#include <geom/io/points.h>

#include <memory>
#include <sstream>

namespace geom::cli {

namespace {

std::vector<Eigen::Vector2d> parse_clip(const std::string& text) {
  std::vector<double> v;
  std::stringstream s(text);
  std::string item;
  while (std::getline(s, item, ',')) {
    try {
      std::size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw UsageError("--clip expects xmin,ymin,xmax,ymax, got '" + text + "'");
    }
  }
  if (v.size() != 4 || !(v[0] < v[2]) || !(v[1] < v[3]))
    throw UsageError("--clip expects xmin,ymin,xmax,ymax with min < max, got '" + text + "'");
  return box_polygon(v[0], v[1], v[2], v[3]);
}

}  // namespace

void add_voronoi_command(CLI::App& app) {
  struct Args {
    std::string input, clip;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "voronoi", "Voronoi diagram of 2D points, cells clipped to a box; SVG/OBJ out", [args] {
        require_svg_or_mesh_output(args->common.output);
        PointSet ps = read_points(args->input);
        std::vector<Eigen::Vector2d> p(ps.points.size());
        for (std::size_t i = 0; i < p.size(); ++i) p[i] = ps.points[i].head<2>();
        VoronoiOptions options;
        if (!args->clip.empty()) options.clip = parse_clip(args->clip);
        VoronoiResult r = voronoi_2d(p, options);
        std::size_t cells = 0;
        for (const auto& c : r.cells) cells += !c.empty();
        if (!args->common.output.empty()) {
          check_not_input(args->common.output, {args->input}, args->common);
          if (is_svg(args->common.output)) {
            Svg svg;
            svg.polygon(r.clip, "fill:none;stroke:#999;stroke-width:1");
            for (const auto& c : r.cells)
              svg.polygon(c, "fill:#f4efe2;stroke:#234;stroke-width:0.7");
            svg.points(p, "#b22");
            svg.write(args->common.output);
          } else {
            // One polygon face per cell, in input order (repeated points have none).
            SurfaceMesh mesh;
            for (const auto& c : r.cells) {
              if (c.size() < 3) continue;
              std::vector<Vertex> f;
              for (const auto& q : c) f.push_back(mesh.add_vertex(Point(q.x(), q.y(), 0)));
              mesh.add_face(f);
            }
            write_output(mesh, {args->input}, args->common);
          }
        }
        nlohmann::json j = {
            {"points", p.size()}, {"cells", cells}, {"duplicates", r.delaunay.duplicates}};
        report(args->common, j, std::to_string(cells) + " Voronoi cells");
        return 0;
      });
  cmd->add_option("input", args->input, "Point file (x y per line, or a mesh's vertices)")
      ->required();
  cmd->add_option("--clip", args->clip,
                  "Clip box xmin,ymin,xmax,ymax (default: bounding box + 10%)");
  add_common_options(cmd, args->common, kOutput | kJson | kQuiet | kForce);
}

}  // namespace geom::cli
