// geom progressive / progressive-extract: write a progressive-mesh stream (.gpm) and take a
// level out of one.

#include "commands.h"
#include "common.h"

#include <geom/lod/progressive_mesh.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>

namespace geom::cli {

namespace {

std::vector<std::byte> read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw Error("cannot open '" + path + "' for reading");
  std::vector<char> raw((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::vector<std::byte> out(raw.size());
  std::memcpy(out.data(), raw.data(), raw.size());
  return out;
}

}  // namespace

void add_progressive_command(CLI::App& app) {
  struct Args {
    std::string input, output;
    double ratio = 0.0;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "progressive", "Write a progressive mesh stream (.gpm): base mesh, then vertex splits",
      [args] {
        require_extension(args->output, {".gpm"}, "output");
        check_not_input(args->output, {args->input}, args->common);
        Loaded loaded = load_input(args->input, args->common);
        ProgressiveOptions o;
        o.simplify.ratio = args->ratio;
        const ProgressiveMesh pm = ProgressiveMesh::build(loaded.mesh, o);
        warn_not_carried("progressive", missing_properties(loaded.mesh, SurfaceMesh()), args->common,
                         "a .gpm stream holds positions only; not stored");
        const std::vector<std::byte> bytes = pm.encode();
        std::ofstream f(args->output, std::ios::binary);
        if (!f) throw Error("cannot open '" + args->output + "' for writing");
        f.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
        if (!f) throw Error("cannot write '" + args->output + "'");
        nlohmann::json j = {{"base_vertices", pm.base_vertices()}, {"base_faces", pm.base_faces()},
                            {"max_vertices", pm.max_vertices()}, {"max_faces", pm.max_faces()},
                            {"splits", pm.splits().size()}, {"bytes", bytes.size()}};
        report(args->common, j,
               args->output + ": base " + std::to_string(pm.base_faces()) + " triangles + " +
                   std::to_string(pm.splits().size()) + " vertex splits, " + std::to_string(bytes.size()) +
                   " bytes\n");
        return 0;
      });
  cmd->add_option("input", args->input, "Mesh file (- for stdin)")->required();
  cmd->add_option("output", args->output, "Progressive mesh file (.gpm)")->required();
  cmd->add_option("--base-ratio", args->ratio,
                  "Base mesh as a fraction of the input's triangles (default 0: as coarse as possible)");
  add_common_options(cmd, args->common, kJson | kQuiet | kForce);
}

void add_progressive_extract_command(CLI::App& app) {
  struct Args {
    std::string input, output;
    std::optional<std::size_t> faces, vertices;
    bool partial = false;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(
      app, "progressive-extract", "Write one level of a progressive mesh stream as a mesh", [args] {
        if (args->faces && args->vertices) throw UsageError("give --faces or --vertices, not both");
        if (!args->output.empty()) args->common.output = args->output;
        ProgressiveMesh pm = ProgressiveMesh::decode(read_bytes(args->input), args->partial);
        std::size_t level = pm.max_vertices();
        if (args->faces) level = pm.vertices_for_faces(*args->faces);
        if (args->vertices) level = *args->vertices;
        pm.set_level(level);
        write_output(pm.mesh(), {args->input}, args->common);
        nlohmann::json j = {{"vertices", pm.n_vertices()}, {"faces", pm.n_faces()},
                            {"max_vertices", pm.max_vertices()}};
        CommonOptions out = args->common;
        if (args->common.output == "-") out.quiet = true, out.json = false;
        report(out, j, std::to_string(pm.n_vertices()) + " vertices, " + std::to_string(pm.n_faces()) +
                           " triangles (of " + std::to_string(pm.max_vertices()) + " vertices)\n");
        return 0;
      });
  cmd->add_option("input", args->input, "Progressive mesh file (.gpm)")->required();
  cmd->add_option("output", args->output, "Output mesh file (or -o)");
  cmd->add_option("--faces", args->faces, "Finest level with at most N triangles");
  cmd->add_option("--vertices", args->vertices, "Level with N vertices (clamped to the stored range)");
  cmd->add_flag("--partial", args->partial, "Accept a truncated stream (use the splits it has)");
  add_common_options(cmd, args->common, kOutput | kJson | kQuiet | kForce | kFormat);
}

}  // namespace geom::cli
