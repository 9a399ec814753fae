// geom info FILE: the topology of the input as given, and what build() would repair.

#include "commands.h"
#include "common.h"

#include <geom/core/topology.h>

#include <memory>

namespace geom::cli {

void add_info_command(CLI::App& app) {
  struct Args {
    std::string input;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "info", "Print the topology report of a mesh file (as given) and what repair would change",
      [args] {
        Loaded loaded = load_input(args->input, args->common, repair_defaults(), false);
        const TopologyReport topology = analyze(loaded.soup);
        nlohmann::json j = to_json(topology);
        j["file"] = args->input;
        j["repairs"] = to_json(loaded.report);
        std::string text = args->input + ":\n" + to_text(topology) + "repairs needed:\n" +
                           to_text(loaded.report);
        report(args->common, j, text);
        return 0;
      });
  cmd->add_option("file", args->input, "Mesh file (obj, ply, off, stl, drc, gltf, glb; - for stdin)")
      ->required();
  add_common_options(cmd, args->common, kJson | kQuiet);
}

}  // namespace geom::cli
