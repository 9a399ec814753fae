// geom validate FILE: exit 1 when the mesh lacks a property the caller asked for.

#include "commands.h"
#include "common.h"

#include <geom/core/topology.h>
#include <geom/core/validate.h>

#include <memory>

namespace geom::cli {

void add_validate_command(CLI::App& app) {
  struct Args {
    std::string input;
    bool manifold = false, closed = false, oriented = false, all = false;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "validate",
      "Check that a mesh file reads, builds into a valid mesh and (as asked) is manifold, "
      "closed and consistently oriented; exit 1 listing why not",
      [args] {
        if (args->all) args->manifold = args->closed = args->oriented = true;
        const Requirements required{args->manifold, args->closed, args->oriented};
        const RequirementCheck check = check_requirements(read_input(args->input, args->common), required);
        const TopologyReport& t = check.topology;
        const BuildReport& r = check.repairs;
        const std::vector<std::string>& failures = check.failures;

        nlohmann::json j = {{"file", args->input},
                            {"ok", failures.empty()},
                            {"problems", failures},
                            {"manifold", t.manifold},
                            {"closed", t.closed},
                            {"orientable", t.orientable},
                            {"repairs", to_json(r)}};
        std::string text;
        if (failures.empty()) {
          text = args->input + ": ok";
          if (args->manifold) text += ", manifold";
          if (args->closed) text += ", closed";
          if (args->oriented) text += ", oriented";
        } else {
          text = args->input + ": " + std::to_string(failures.size()) + " problem(s)\n";
          for (const auto& f : failures) text += "  " + f + '\n';
        }
        report(args->common, j, text);
        return failures.empty() ? 0 : 1;
      });
  cmd->add_option("file", args->input, "Mesh file (- for stdin)")->required();
  cmd->add_flag("--manifold", args->manifold, "Require every edge and vertex to be manifold");
  cmd->add_flag("--closed", args->closed, "Require no boundary");
  cmd->add_flag("--oriented", args->oriented,
                "Require consistently oriented faces (and an orientable surface)");
  cmd->add_flag("--all", args->all, "All of --manifold --closed --oriented");
  add_common_options(cmd, args->common, kJson | kQuiet);
}

}  // namespace geom::cli
