// geom simplify: quadric edge-collapse simplification.

#include "commands.h"
#include "common.h"

#include <geom/lod/simplify.h>
#include <geom/spatial/distance.h>

#include <algorithm>
#include <iostream>
#include <memory>

namespace geom::cli {

void add_simplify_command(CLI::App& app) {
  struct Args {
    std::string input, output;
    std::optional<double> ratio, max_error;
    std::optional<std::size_t> faces;
    bool keep_boundary = false, measure = false;
    std::vector<std::string> attributes;
    double attribute_weight = 1.0;
    SimplifyOptions options;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "simplify", "Reduce the face count by quadric edge collapse", [args] {
        if (!args->ratio && !args->faces && !args->max_error)
          throw UsageError("give --ratio R, --faces N or --max-error E");
        if (args->ratio && args->faces) throw UsageError("give --ratio or --faces, not both");
        if (!args->output.empty()) {
          if (!args->common.output.empty() && args->common.output != args->output)
            throw UsageError("two outputs given (OUT and -o)");
          args->common.output = args->output;
        }
        SimplifyOptions o = args->options;
        o.ratio = args->ratio.value_or(args->faces || args->max_error ? 0.0 : 0.5);
        o.target_faces = args->faces.value_or(0);
        if (args->max_error) o.max_error = *args->max_error;
        o.lock_boundary = args->keep_boundary;
        const bool none = std::ranges::count(args->attributes, "none") > 0;
        if (none && args->attributes.size() > 1)
          throw UsageError("--attributes none cannot be combined with attribute names");
        for (const std::string& a : args->attributes) {
          if (a == "none") continue;
          SimplifyAttribute& slot = a == "normals" ? o.attributes.normals
                                    : a == "uv"    ? o.attributes.texcoords
                                                   : o.attributes.colors;
          slot = {.enabled = true, .weight = args->attribute_weight};
        }
        Loaded loaded = load_input(args->input, args->common);
        if (args->attributes.empty()) o.attributes = present_attributes(loaded.mesh, args->attribute_weight);
        o.keep_attributes = false;
        // Non-manifold vertices the build split stay in place and are joined again.
        const bool split = loaded.report.split_apart();
        if (split) {
          const std::vector<Vertex> copies = split_copies(loaded.report.vertex_origin);
          o.locked.insert(o.locked.end(), copies.begin(), copies.end());
        }
        Progress progress("simplify", !args->common.quiet && args->common.output != "-");
        o.progress = progress.callback();
        SimplifyResult r = simplify(loaded.mesh, o);
        progress.finish();
        warn_not_carried("simplify", r.dropped_properties, args->common);
        if (split) {
          PolygonSoup joined = join_split_copies(r, loaded.report.vertex_origin);
          joined.material_libraries = loaded.soup.material_libraries;
          if (!args->common.quiet)
            std::cerr << "geom simplify: the vertices split for the half-edge mesh stayed in place "
                         "and are joined again (" << o.locked.size() << " copies)\n";
          write_output(joined, {args->input}, args->common);
        } else {
          write_output(r.mesh, {args->input}, args->common);
        }
        nlohmann::json j = {{"faces_before", r.faces_before},
                            {"faces_after", r.faces_after},
                            {"collapses", r.collapses},
                            {"max_quadric_error", r.max_quadric_error},
                            {"refit_rounds", r.refit_rounds},
                            {"stop", to_string(r.stop)},
                            {"attributes", o.attributes.names()},
                            {"dropped_properties", r.dropped_properties}};
        std::string text = std::to_string(r.faces_before) + " -> " + std::to_string(r.faces_after) +
                           " triangles (" + std::to_string(r.collapses) + " collapses; " +
                           to_string(r.stop) + ")\n";
        if (args->measure && r.mesh.n_faces() > 0) {
          const MeshDistance d = mesh_distance(loaded.mesh, r.mesh);
          j["hausdorff"] = d.hausdorff;
          j["rms"] = d.rms;
          j["relative_hausdorff"] = d.relative_hausdorff();
          j["relative_rms"] = d.relative_rms();
          text += "Hausdorff " + std::to_string(d.hausdorff) + " (" +
                  std::to_string(d.relative_hausdorff()) + " of the diagonal), RMS " +
                  std::to_string(d.rms) + "\n";
        }
        CommonOptions out = args->common;
        if (args->common.output == "-") out.quiet = true, out.json = false;
        report(out, j, text);
        return 0;
      });
  cmd->add_option("input", args->input, "Mesh file (- for stdin)")->required();
  cmd->add_option("output", args->output, "Output mesh file (or -o)");
  cmd->add_option("--ratio", args->ratio, "Target as a fraction of the input's triangles");
  cmd->add_option("--faces", args->faces, "Target triangle count");
  cmd->add_option("--max-error", args->max_error,
                  "Skip collapses whose quadric error (RMS plane distance, model units) exceeds E");
  cmd->add_flag("--keep-boundary", args->keep_boundary, "Never move or remove boundary vertices");
  cmd->add_option("--boundary-weight", args->options.boundary_weight,
                  "Weight of boundary constraint planes (default 100; 0 = none)");
  cmd->add_option("--min-quality", args->options.min_triangle_quality,
                  "Reject collapses leaving triangles below this quality (default 0.02)");
  cmd->add_option("--attributes", args->attributes,
                  "Attribute-aware quadrics for these properties (comma-separated: normals, uv, "
                  "color; none); the output carries them, seams kept. Default: every one the "
                  "input has")
      ->delimiter(',')
      ->check(CLI::IsMember({"normals", "uv", "color", "none"}));
  cmd->add_option("--attribute-weight", args->attribute_weight,
                  "Weight of attribute deviation against distance in a unit-diagonal box (default 1; "
                  "0 = carry without steering)");
  cmd->add_option("--refit", args->options.refit_iterations,
                  "Afterwards refit the vertices to the input surface for N rounds: lower error "
                  "(RMS 5-25% on scans). Default -1 = automatic: one round when keeping about a "
                  "quarter or less (cheap there: 0.15-0.25x the collapses' time), else none; "
                  "above a quarter it costs 1.2x; 0 = off")
      ->check(CLI::Range(-1, 1000));
  cmd->add_flag("--measure", args->measure, "Report the sampled Hausdorff and RMS distance");
  add_common_options(cmd, args->common, kOutput | kJson | kQuiet | kForce | kFormat);
}

}  // namespace geom::cli
