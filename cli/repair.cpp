// geom repair IN OUT: weld, drop degenerate faces, orient, split non-manifold elements.

#include "commands.h"
#include "common.h"

#include <memory>

namespace geom::cli {

void add_repair_command(CLI::App& app) {
  struct Args {
    std::string input, output;
    double weld = 0.0;
    bool keep_unreferenced = false;
    bool no_orient = false;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "repair",
      "Weld duplicate vertices, drop degenerate faces, orient consistently, split non-manifold "
      "edges and vertices; print what changed",
      [args] {
        BuildOptions options = repair_defaults();
        options.weld_tolerance = args->weld;
        options.orient = !args->no_orient;
        options.drop_unreferenced = !args->keep_unreferenced;
        Loaded loaded = load_input(args->input, args->common, options, false);
        const std::string out = args->output.empty() ? args->common.output : args->output;
        if (out.empty()) throw UsageError("repair needs an output file (OUT or -o)");
        write_output(loaded.mesh, {args->input}, args->common, {}, out);
        nlohmann::json j = to_json(loaded.report);
        j["input"] = args->input;
        j["output"] = out;
        j["vertices"] = loaded.mesh.n_vertices();
        j["faces"] = loaded.mesh.n_faces();
        std::string text = args->input + " -> " + out + ": " +
                           std::to_string(loaded.mesh.n_vertices()) + " vertices, " +
                           std::to_string(loaded.mesh.n_faces()) + " faces\n" +
                           to_text(loaded.report);
        CommonOptions shown = args->common;
        if (out == "-") shown.quiet = true, shown.json = false;
        report(shown, j, text);
        return 0;
      });
  cmd->add_option("input", args->input, "Input mesh file (- for stdin)")->required();
  cmd->add_option("output", args->output, "Output mesh file (- for stdout, with --format)");
  cmd->add_option("--weld", args->weld,
                  "Weld tolerance x bounding-box diagonal (0: exact duplicates; negative: none)")
      ->capture_default_str()
      ->type_name("TOL");
  cmd->add_flag("--keep-unreferenced", args->keep_unreferenced,
                "Keep vertices that no face uses");
  cmd->add_flag("--no-orient", args->no_orient, "Do not flip faces to agree with neighbours");
  add_common_options(cmd, args->common, kOutput | kJson | kQuiet | kForce | kFormat);
}

}  // namespace geom::cli
