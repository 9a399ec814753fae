// geom subdivide: Catmull-Clark or Loop refinement with OpenSubdiv's rules.

#include "commands.h"
#include "common.h"

#include <geom/subdivision/subdivision.h>

#include <chrono>
#include <iostream>
#include <map>
#include <memory>

namespace geom::cli {

void add_subdivide_command(CLI::App& app) {
  struct Args {
    std::string input, output;
    std::string scheme = "catmull-clark";
    std::optional<std::string> boundary;
    std::string crease_method = "uniform";
    std::string uv = "linear";
    SubdivideOptions options;
    double crease_angle = -1.0;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "subdivide", "Refine with Catmull-Clark or Loop subdivision (OpenSubdiv's rules)",
      [args] {
        if (!args->output.empty()) {
          if (!args->common.output.empty() && args->common.output != args->output)
            throw UsageError("two outputs given (OUT and -o)");
          args->common.output = args->output;
        }
        SubdivideOptions o = args->options;
        o.scheme = args->scheme == "loop" ? SubdivisionScheme::kLoop
                                          : SubdivisionScheme::kCatmullClark;
        o.crease_method = args->crease_method == "chaikin" ? CreaseMethod::kChaikin
                                                           : CreaseMethod::kUniform;
        o.face_varying = args->uv == "smooth" ? FaceVaryingInterpolation::kLinearBoundaries
                                              : FaceVaryingInterpolation::kLinearAll;
        if (args->crease_angle >= 0.0) o.crease_angle = args->crease_angle;
        // As given: non-manifold input is refined as OpenSubdiv refines it, nothing dropped.
        PolygonSoup soup = read_input(args->input, args->common);
        // The file's "t interpolateboundary" tag (RenderMan values: 0 none, 1 edges and
        // corners, 2 edges) applies unless --boundary is given.
        const std::map<std::string, BoundaryInterpolation> modes = {
            {"none", BoundaryInterpolation::kNone},
            {"edges", BoundaryInterpolation::kEdges},
            {"corners", BoundaryInterpolation::kEdgesAndCorners}};
        if (args->boundary) {
          o.boundary = modes.at(*args->boundary);
        } else if (soup.boundary_interpolation) {
          const int tag = *soup.boundary_interpolation;
          o.boundary = tag == 0 ? BoundaryInterpolation::kNone
                       : tag == 1 ? BoundaryInterpolation::kEdgesAndCorners
                                  : BoundaryInterpolation::kEdges;
        }
        Progress progress("subdivide", !args->common.quiet && args->common.output != "-");
        o.progress = progress.callback();
        const auto t0 = std::chrono::steady_clock::now();
        SoupSubdivideResult r = subdivide(soup, o);
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        progress.finish();
        if (r.opened_edges > 0 && !args->common.quiet)
          std::cerr << "geom: warning: subdivide: " << r.opened_edges
                    << " smooth edges had to be opened to split non-manifold input; next to "
                       "them the result differs from OpenSubdiv's\n";
        write_output(r.soup, {args->input}, args->common);
        const LevelCounts& last = r.per_level.back();
        nlohmann::json j = {{"scheme", args->scheme},
                            {"levels", r.levels},
                            {"vertices", last.vertices},
                            {"edges", last.edges},
                            {"faces", last.faces},
                            {"faces_before", soup.n_faces()},
                            {"angle_creased_edges", r.angle_creased_edges},
                            {"nonmanifold_edges", r.nonmanifold_edges},
                            {"nonmanifold_vertices", r.nonmanifold_vertices},
                            {"degenerate_edges", r.degenerate_edges},
                            {"split_vertices", r.split_vertices},
                            {"opened_edges", r.opened_edges},
                            {"seconds", seconds}};
        std::string text = std::to_string(soup.n_faces()) + " -> " +
                           std::to_string(last.faces) + " faces (" + args->scheme + ", " +
                           std::to_string(r.levels) + " levels, " + std::to_string(seconds) +
                           " s)\n";
        if (r.nonmanifold_edges + r.nonmanifold_vertices + r.degenerate_edges > 0)
          text += "refined as given, as OpenSubdiv does: " + std::to_string(r.nonmanifold_edges) +
                  " non-manifold edges, " + std::to_string(r.nonmanifold_vertices) +
                  " non-manifold vertices, " + std::to_string(r.degenerate_edges) +
                  " edges from a vertex to itself (all infinitely sharp)\n";
        if (o.limit) {
          j["limit_max_distance"] = r.limit_max_distance;
          j["limit_rms_distance"] = r.limit_rms_distance;
          text += "pushed to the limit surface: max move " +
                  std::to_string(r.limit_max_distance) + ", RMS " +
                  std::to_string(r.limit_rms_distance) + "\n";
        }
        CommonOptions out = args->common;
        if (args->common.output == "-") out.quiet = true, out.json = false;
        report(out, j, text);
        return 0;
      });
  cmd->add_option("input", args->input, "Mesh file (- for stdin)")->required();
  cmd->add_option("output", args->output, "Output mesh file (or -o)");
  cmd->add_option("--scheme", args->scheme, "catmull-clark (default) or loop")
      ->check(CLI::IsMember({"catmull-clark", "loop"}));
  cmd->add_option("--levels", args->options.levels, "Refinement levels (default 1)")
      ->check(CLI::Range(0, 10));
  cmd->add_option("--boundary", args->boundary,
                  "none, edges (default) or corners (edges and corners stay sharp)")
      ->check(CLI::IsMember({"none", "edges", "corners"}));
  cmd->add_option("--crease-method", args->crease_method, "uniform (default) or chaikin")
      ->check(CLI::IsMember({"uniform", "chaikin"}));
  cmd->add_option("--uv", args->uv,
                  "Texture coordinates (corner data): linear (default), or smooth inside each "
                  "UV island and linear along seams (OpenSubdiv FVAR_LINEAR_BOUNDARIES)")
      ->check(CLI::IsMember({"linear", "smooth"}));
  cmd->add_flag("--limit", args->options.limit,
                "Push the final vertices (and smooth UVs) onto the limit surface");
  cmd->add_option("--crease-angle", args->crease_angle,
                  "Make edges with a dihedral angle above DEG degrees infinitely sharp")
      ->check(CLI::Range(0.0, 180.0));
  add_common_options(cmd, args->common, kOutput | kJson | kQuiet | kForce | kFormat);
}

}  // namespace geom::cli
