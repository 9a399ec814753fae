// geom convert IN OUT: any supported format to any other.

#include "commands.h"
#include "common.h"

#include <memory>

namespace geom::cli {

void add_convert_command(CLI::App& app) {
  struct Args {
    std::string input, output;
    std::optional<double> weld;
    bool binary = false, ascii = false;
    bool no_attributes = false;
    int drc_bits = 0;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "convert", "Convert a mesh file to another format (by extension, or --format)",
      [args] {
        BuildOptions build_options;
        // Conversion keeps the file's faces as they are (no reorientation) unless welding was
        // asked for; repairs the builder must make anyway are reported.
        build_options.orient = false;
        if (args->weld) build_options.weld_tolerance = *args->weld;
        Loaded loaded = load_input(args->input, args->common, build_options);
        WriteOptions write;
        write.binary = !args->ascii;
        write.attributes = !args->no_attributes;
        write.drc_position_bits = args->drc_bits;
        write_output(loaded.mesh, {args->input}, args->common, write, args->output);
        nlohmann::json j = {{"input", args->input},
                            {"output", args->output},
                            {"vertices", loaded.mesh.n_vertices()},
                            {"faces", loaded.mesh.n_faces()},
                            {"repairs", to_json(loaded.report)}};
        std::string text = args->input + " -> " + args->output + ": " +
                           std::to_string(loaded.mesh.n_vertices()) + " vertices, " +
                           std::to_string(loaded.mesh.n_faces()) + " faces\n";
        if (loaded.report.changed()) text += to_text(loaded.report);
        // Text would mix with the mesh when it goes to stdout.
        CommonOptions out = args->common;
        if (args->output == "-") out.quiet = true, out.json = false;
        report(out, j, text);
        return 0;
      });
  cmd->add_option("input", args->input, "Input mesh file (- for stdin)")->required();
  cmd->add_option("output", args->output, "Output mesh file (- for stdout, with --format)")
      ->required();
  cmd->add_option("--weld", args->weld,
                  "Weld vertices closer than TOL x bounding-box diagonal (no TOL or 0: exact "
                  "duplicates only)")
      ->expected(0, 1)
      ->default_str("0")
      ->type_name("[TOL]");
  auto* binary = cmd->add_flag("--binary", args->binary, "Binary PLY/STL (the default)");
  auto* ascii = cmd->add_flag("--ascii", args->ascii, "ASCII PLY/STL");
  binary->excludes(ascii);
  cmd->add_flag("--no-attributes", args->no_attributes,
                "Write positions and faces only (no normals, colours, texture coordinates)");
  cmd->add_option("--drc-bits", args->drc_bits,
                  "Draco: quantisation bits for positions (0: lossless floats)")
      ->check(CLI::Range(0, 30));
  add_common_options(cmd, args->common, kJson | kQuiet | kForce | kFormat);
}

}  // namespace geom::cli
