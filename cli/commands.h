#pragma once
/// \file
/// The `geom` subcommands. HOW TO ADD ONE (the pattern every capability follows):
///
///  1. Write `cli/<name>.cpp` with one public function, `void add_<name>_command(CLI::App& app)`,
///     in namespace geom::cli. It registers the subcommand and its options, and hands
///     add_command() a runner that reads, calls the library, writes and reports:
///
///        void add_simplify_command(CLI::App& app) {
///          struct Args { std::string input; SimplifyOptions options; CommonOptions common; };
///          auto args = std::make_shared<Args>();           // outlives parsing
///          CLI::App* cmd = add_command(app, "simplify", "Reduce the face count",
///                                      [args] {
///            Loaded loaded = load_input(args->input, args->common);     // progress on stderr
///            auto result = simplify(loaded.mesh, args->options);        // the library
///            write_output(result.mesh, {args->input}, args->common);    // -o, never an input
///            nlohmann::json j = {{"collapses", result.collapses}};
///            report(args->common, j, "collapsed " + std::to_string(result.collapses));
///            return 0;                                     // the exit code
///          });
///          cmd->add_option("input", args->input, "Mesh file (- for stdin)")->required();
///          cmd->add_option("--target-faces", args->options.target_faces, "...");
///          add_common_options(cmd, args->common, kOutput | kJson | kQuiet | kForce);
///        }
///
///  2. Declare it below (one line) and call it from the kCommands list in cli/main.cpp
///     (one line).
///  3. Add `<name>.cpp` to GEOM_CLI_SOURCES and `geom::<capability>` to GEOM_CLI_LIBS in
///     cli/CMakeLists.txt (one line each).
///  4. Tour: write `cli/tour_<capability>.cpp` with `void tour_<capability>(TourContext&)`,
///     declare it in cli/tour.h and add one line to kTourSteps in cli/tour.cpp (see tour.h).
///  5. Test: add the subcommand's name to COMMANDS in tests/python/test_cli.py (checks --help)
///     and a test of its exit codes there.
///
/// Rules (common.h implements them, so use its helpers rather than your own):
///  - option names are the same everywhere: -o/--output, --json, --quiet, --force;
///  - a geom::Error (or any std::exception) thrown from a runner becomes one line on stderr and
///    exit 1; a UsageError or a CLI11 parse error exits 2; the runner's return value is the
///    exit code otherwise (e.g. 1 when `validate` finds a requested property missing);
///  - human-readable text on stdout by default, one JSON document with --json;
///  - progress only on stderr, only when stderr is a terminal and --quiet is not given;
///  - outputs never overwrite an input unless --force is given;
///  - an output's extension says what is written: one that is not a mesh (PNG, .gmc, SVG)
///    is checked with require_extension before any work, a usage error when it is wrong;
///  - the CLI never computes geometry: it calls the library.

#include <CLI/CLI.hpp>

namespace geom::cli {

void add_info_command(CLI::App& app);
void add_convert_command(CLI::App& app);
void add_validate_command(CLI::App& app);
void add_repair_command(CLI::App& app);
void add_tour_command(CLI::App& app);
void add_render_command(CLI::App& app);
void add_montage_command(CLI::App& app);
void add_isosurface_command(CLI::App& app);
void add_simplify_command(CLI::App& app);
void add_compare_command(CLI::App& app);
void add_lod_command(CLI::App& app);
void add_progressive_command(CLI::App& app);
void add_batch_command(CLI::App& app);
void add_progressive_extract_command(CLI::App& app);

void add_delaunay_command(CLI::App& app);
void add_voronoi_command(CLI::App& app);
void add_hull_command(CLI::App& app);
void add_subdivide_command(CLI::App& app);
void add_compress_command(CLI::App& app);
void add_decompress_command(CLI::App& app);

}  // namespace geom::cli
