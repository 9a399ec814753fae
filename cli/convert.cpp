// geom convert IN OUT: any supported format to any other. What the file holds is written as
// it was read (no half-edge mesh is built) unless --weld or --repair asks for changes.

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
    bool repair = false;
    int drc_bits = 0;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "convert", "Convert a mesh file to another format (by extension, or --format)",
      [args] {
        WriteOptions write;
        write.binary = !args->ascii;
        write.attributes = !args->no_attributes;
        write.drc_position_bits = args->drc_bits;
        PolygonSoup soup;
        nlohmann::json repairs = nullptr;
        std::string changes;
        if (args->weld || args->repair) {
          BuildOptions build_options;
          if (args->repair) build_options = repair_defaults();
          // Welding alone keeps the faces' orientation as given.
          build_options.orient = args->repair;
          build_options.weld_tolerance = args->weld ? *args->weld : 0.0;
          Loaded loaded = load_input(args->input, args->common, build_options, false);
          soup = to_soup(loaded.mesh);
          soup.material_libraries = loaded.soup.material_libraries;  // a mesh keeps none
          repairs = to_json(loaded.report);
          if (loaded.report.changed()) changes = to_text(loaded.report);
        } else {
          soup = read_input(args->input, args->common);
        }
        write_output(soup, {args->input}, args->common, write, args->output);
        nlohmann::json j = {{"input", args->input},
                            {"output", args->output},
                            {"vertices", soup.positions.size()},
                            {"faces", soup.n_faces()},
                            {"repairs", repairs}};
        std::string text = args->input + " -> " + args->output + ": " +
                           std::to_string(soup.positions.size()) + " vertices, " +
                           std::to_string(soup.n_faces()) + " faces\n" + changes;
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
  cmd->add_flag("--repair", args->repair,
                "Repair as `geom repair` does (weld exact duplicates, drop degenerate and "
                "duplicate faces and unused vertices, orient, split non-manifold elements) and "
                "report it");
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
