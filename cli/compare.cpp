// geom compare: sampled symmetric Hausdorff and RMS distance between two meshes.

#include "commands.h"
#include "common.h"

#include <geom/spatial/distance.h>

#include <memory>

namespace geom::cli {

void add_compare_command(CLI::App& app) {
  struct Args {
    std::string a, b;
    DistanceOptions options;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "compare", "Hausdorff and RMS distance between two surfaces (dense sampling)", [args] {
        Loaded a = load_input(args->a, args->common);
        Loaded b = load_input(args->b, args->common);
        const MeshDistance d = mesh_distance(a.mesh, b.mesh, args->options);
        nlohmann::json j = {{"hausdorff", d.hausdorff},
                            {"rms", d.rms},
                            {"relative_hausdorff", d.relative_hausdorff()},
                            {"relative_rms", d.relative_rms()},
                            {"diagonal", d.diagonal},
                            {"a_to_b", {{"max", d.a_to_b.max}, {"mean", d.a_to_b.mean}, {"rms", d.a_to_b.rms}, {"samples", d.a_to_b.samples}}},
                            {"b_to_a", {{"max", d.b_to_a.max}, {"mean", d.b_to_a.mean}, {"rms", d.b_to_a.rms}, {"samples", d.b_to_a.samples}}}};
        const std::string text =
            "Hausdorff " + std::to_string(d.hausdorff) + " (" + std::to_string(d.relative_hausdorff()) +
            " of the bounding-box diagonal)\nRMS       " + std::to_string(d.rms) + " (" +
            std::to_string(d.relative_rms()) + ")\nA->B max " + std::to_string(d.a_to_b.max) +
            ", B->A max " + std::to_string(d.b_to_a.max) + "\n";
        report(args->common, j, text);
        return 0;
      });
  cmd->add_option("a", args->a, "First mesh")->required();
  cmd->add_option("b", args->b, "Second mesh")->required();
  cmd->add_option("--samples", args->options.samples, "Area samples per direction (default 200000)");
  cmd->add_option("--seed", args->options.seed, "Sampling seed (default 1)");
  add_common_options(cmd, args->common, kJson | kQuiet);
}

}  // namespace geom::cli
