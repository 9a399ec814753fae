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
        BuildOptions no_changes;
        no_changes.orient = false;
        Loaded loaded = load_input(args->input, args->common, no_changes);
        const TopologyReport t = analyze(loaded.soup);
        const ValidationReport structure = validate(loaded.mesh);
        const BuildReport& r = loaded.report;

        std::vector<std::string> failures;
        for (const auto& p : structure.problems) failures.push_back("invalid mesh: " + p);
        if (args->manifold && !t.manifold) {
          std::string why = "not manifold:";
          if (t.nonmanifold_edges) why += " " + std::to_string(t.nonmanifold_edges) +
                                          " edges with 3 or more faces;";
          if (t.nonmanifold_vertices) why += " " + std::to_string(t.nonmanifold_vertices) +
                                             " non-manifold vertices;";
          if (t.degenerate_faces) why += " " + std::to_string(t.degenerate_faces) +
                                         " degenerate faces;";
          if (why.back() == ';') why.pop_back();
          failures.push_back(why);
        }
        if (args->closed && !t.closed)
          failures.push_back("not closed: " + std::to_string(t.boundary_loops) +
                             " boundary loops (" + std::to_string(t.boundary_edges) +
                             " boundary edges)");
        if (args->oriented) {
          // build() with orient=false still detects faces that disagree with their
          // neighbours; it reports them as the flips it would make.
          BuildOptions orient;
          const BuildReport o = build(loaded.soup, orient).report;
          if (!o.orientable || !t.orientable)
            failures.push_back("not orientable: some component is a one-sided surface");
          else if (o.flipped_faces)
            failures.push_back("not consistently oriented: " + std::to_string(o.flipped_faces) +
                               " faces disagree with their neighbours");
        }

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
