// The `geom` command-line tool: one subcommand per file (see commands.h for the pattern).

#include "commands.h"
#include "common.h"

#include <geom/core/errors.h>

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <iostream>

namespace {

using AddCommand = void (*)(CLI::App&);

// One line per subcommand, in the order `geom --help` lists them.
constexpr AddCommand kCommands[] = {
    geom::cli::add_info_command,
    geom::cli::add_convert_command,
    geom::cli::add_validate_command,
    geom::cli::add_repair_command,
    geom::cli::add_tour_command,
    geom::cli::add_render_command,
    geom::cli::add_montage_command,
    geom::cli::add_isosurface_command,
    geom::cli::add_simplify_command,
    geom::cli::add_compare_command,
    geom::cli::add_lod_command,
    geom::cli::add_progressive_command,
    geom::cli::add_progressive_extract_command,
    geom::cli::add_delaunay_command,
    geom::cli::add_voronoi_command,
    geom::cli::add_hull_command,
    geom::cli::add_subdivide_command,
    geom::cli::add_compress_command,
    geom::cli::add_decompress_command,
    geom::cli::add_batch_command,
};

constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"geom: a geometry processing toolkit for polygon meshes", "geom"};
  app.require_subcommand(1, 1);
  app.set_version_flag("--version", "geom 0.1.0");
  for (AddCommand add : kCommands) add(app);

  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);  // prints the message and the relevant help
    return kExitUsage;
  } catch (const geom::cli::ExitCode& e) {
    return e.code;
  } catch (const geom::cli::UsageError& e) {
    std::cerr << "geom: " << e.what() << '\n';
    return kExitUsage;
  } catch (const std::bad_alloc&) {
    std::cerr << "geom: out of memory\n";
    return kExitFailure;
  } catch (const std::exception& e) {
    // One line: multi-line messages (a validation report) are joined so scripts can rely on it.
    std::string message = e.what();
    for (char& c : message)
      if (c == '\n') c = ' ';
    std::cerr << "geom: " << message << '\n';
    return kExitFailure;
  }
  return 0;
}
