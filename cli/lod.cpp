// geom lod: a chain of levels of detail, each written to its own file with its measured error.

#include "commands.h"
#include "common.h"

#include <geom/io/gltf.h>
#include <geom/lod/lod_chain.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>

namespace geom::cli {

void add_lod_command(CLI::App& app) {
  struct Args {
    std::string input, outdir;
    int levels = 4;
    double step = 0.5;
    std::string gltf;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "lod", "Write K levels of detail (each a fraction of the previous) with their errors",
      [args] {
        if (args->levels < 1 || args->levels > 30) throw UsageError("--levels must be in [1, 30]");
        if (!(args->step > 0 && args->step < 1)) throw UsageError("--step must be in (0, 1)");
        if (!args->gltf.empty()) require_extension(args->gltf, {".glb", ".gltf"}, "--gltf");
        Loaded loaded = load_input(args->input, args->common);
        LodChainOptions o;
        o.ratios.clear();
        for (int k = 1; k <= args->levels; ++k) o.ratios.push_back(std::pow(args->step, k));
        const std::vector<LodLevel> levels = lod_chain(loaded.mesh, o);
        warn_not_carried("lod", missing_properties(loaded.mesh, levels.front().mesh), args->common);
        std::filesystem::create_directories(args->outdir);
        const FileFormat format = args->common.output_format.value_or(FileFormat::kPly);
        const std::string stem = args->input == "-" ? "mesh" : std::filesystem::path(args->input).stem().string();
        nlohmann::json j = nlohmann::json::array();
        std::string text;
        for (std::size_t k = 0; k < levels.size(); ++k) {
          const std::filesystem::path out = std::filesystem::path(args->outdir) /
              (stem + "_lod" + std::to_string(k + 1) + "." + format_name(format));
          WriteOptions write;
          write.format = format;
          write_output(levels[k].mesh, {args->input}, args->common, write, out.string());
          const MeshDistance& e = levels[k].error;
          j.push_back({{"file", out.string()}, {"ratio", levels[k].ratio}, {"faces", levels[k].faces},
                       {"hausdorff", e.hausdorff}, {"rms", e.rms},
                       {"relative_hausdorff", e.relative_hausdorff()}, {"relative_rms", e.relative_rms()}});
          text += out.string() + ": " + std::to_string(levels[k].faces) + " triangles, Hausdorff " +
                  std::to_string(e.relative_hausdorff()) + " of the diagonal, RMS " +
                  std::to_string(e.relative_rms()) + "\n";
        }
        if (!args->gltf.empty()) {
          // The whole chain in one file for renderers: the input, then each level, linked by
          // MSFT_lod so a viewer shows the first and switches by screen coverage.
          std::vector<PolygonSoup> chain{to_soup(loaded.mesh)};
          for (const LodLevel& l : levels) chain.push_back(to_soup(l.mesh));
          check_not_input(args->gltf, {args->input}, args->common);
          const bool binary = std::filesystem::path(args->gltf).extension() != ".gltf";
          const std::string bytes = write_gltf(gltf_lod_chain(std::move(chain)), binary);
          std::ofstream out(args->gltf, std::ios::binary);
          if (!out || !out.write(bytes.data(), static_cast<std::streamsize>(bytes.size())))
            throw Error("cannot write '" + args->gltf + "'");
          text += args->gltf + ": the chain as glTF with MSFT_lod\n";
        }
        report(args->common, j, text);
        return 0;
      });
  cmd->add_option("input", args->input, "Mesh file (- for stdin)")->required();
  cmd->add_option("outdir", args->outdir, "Directory for <stem>_lod<k>.<ext>")->required();
  cmd->add_option("--levels", args->levels, "Number of levels (default 4)");
  cmd->add_option("--step", args->step, "Face ratio between consecutive levels (default 0.5)");
  cmd->add_option("--gltf", args->gltf, "Also write the chain to one .glb/.gltf with the MSFT_lod extension");
  add_common_options(cmd, args->common, kJson | kQuiet | kForce | kFormat);
}

}  // namespace geom::cli
