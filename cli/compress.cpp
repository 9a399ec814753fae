// `geom compress IN OUT.gmc` and `geom decompress IN.gmc OUT`: the mesh codec (geom/compress).

#include "commands.h"
#include "common.h"

#include <geom/compress/container/codec.h>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>

namespace geom::cli {

namespace {

std::vector<std::uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open " + path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) throw Error("cannot write " + path);
}

/// Loading splits non-manifold edges and vertices apart. The stream then records which
/// vertices are one (CompressOptions::vertex_origin), so that decompression writes the
/// source's vertices again; returns how many copies the split made (0: none).
std::size_t record_split(const BuildReport& report, CompressOptions& options) {
  if (!report.split_apart()) return 0;
  options.vertex_origin = report.vertex_origin;
  std::vector<std::uint32_t> sorted = report.vertex_origin;
  std::sort(sorted.begin(), sorted.end());
  return sorted.size() - static_cast<std::size_t>(std::unique(sorted.begin(), sorted.end()) - sorted.begin());
}

}  // namespace

void add_compress_command(CLI::App& app) {
  struct Args {
    std::string input, output;
    CompressOptions options;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(app, "compress",
                              "Compress a mesh to a .gmc stream (a non-manifold file too: the "
                              "vertices loading splits apart are recorded, and decompress joins them)",
                              [args] {
    require_extension(args->output, {".gmc"}, "output");
    check_not_input(args->output, {args->input}, args->common);
    Loaded loaded = load_input(args->input, args->common);
    const std::size_t copies = record_split(loaded.report, args->options);
    const CompressResult r = compress(loaded.mesh, args->options);
    write_bytes(args->output, r.bytes);
    const double nv = std::max<double>(1.0, static_cast<double>(loaded.mesh.n_vertices()));
    nlohmann::json j = {{"bytes", r.bytes.size()},
                        {"vertices", loaded.mesh.n_vertices()},
                        {"faces", loaded.mesh.n_faces()},
                        {"bits_per_vertex", 8.0 * r.bytes.size() / nv},
                        {"connectivity_bits_per_vertex", 8.0 * r.stats.connectivity_bytes / nv},
                        {"geometry_bits_per_vertex", 8.0 * r.stats.geometry_bytes / nv},
                        {"order_bits_per_vertex", 8.0 * r.stats.order_bytes / nv},
                        {"normal_bits_per_vertex", 8.0 * r.stats.normal_bytes / nv},
                        {"texcoord_bits_per_vertex", 8.0 * r.stats.texcoord_bytes / nv},
                        {"texcoord_max_error", r.stats.texcoord_max_error},
                        {"quantisation_bits", r.stats.bits},
                        {"chunks", r.stats.chunks},
                        {"split_vertices", copies},
                        {"source_vertices", loaded.mesh.n_vertices() - copies},
                        {"max_error", r.stats.max_error},
                        {"dropped_properties", r.stats.dropped_properties}};
    for (const AttributeStats& a : r.stats.attributes)
      j["attributes"][a.name] = {{"bytes", a.bytes},
                                 {"bits_per_vertex", 8.0 * a.bytes / nv},
                                 {"max_error", a.max_error}};
    if (copies > 0 && !args->common.quiet)
      std::cerr << "geom compress: non-manifold input: coded as a manifold mesh with " << copies
                << " vertices split apart; geom decompress joins them again\n";
    // Properties the stream cannot hold must not vanish unnoticed.
    if (!r.stats.dropped_properties.empty() && !args->common.quiet) {
      std::string names;
      for (const std::string& n : r.stats.dropped_properties) names += (names.empty() ? "" : ", ") + n;
      std::cerr << "geom compress: warning: not stored, decompression will not restore: " << names << '\n';
    }
    report(args->common, j,
           "wrote " + std::to_string(r.bytes.size()) + " bytes (" +
               std::to_string(8.0 * r.bytes.size() / nv) + " bits/vertex, max error " +
               std::to_string(r.stats.max_error) + ")");
    return 0;
  });
  cmd->add_option("input", args->input, "Mesh file (- for stdin)")->required();
  cmd->add_option("output", args->output, "Compressed output (.gmc)")->required();
  auto* bits = cmd->add_option("--bits", args->options.bits, "Bits per coordinate (1-30)")
                   ->check(CLI::Range(1, 30));
  cmd->add_option("--precision", args->options.precision,
                  "Largest error per coordinate (overrides --bits)")
      ->excludes(bits);
  cmd->add_option("--level", args->options.level, "Compression level 0-9 (higher: smaller)")
      ->check(CLI::Range(0, 9));
  cmd->add_flag("--preserve-order", args->options.preserve_order,
                "Keep vertex and face order exactly (larger)");
  cmd->add_option("--chunk-triangles", args->options.chunk_triangles,
                  "Split meshes of at least twice this many triangles into chunks that decode in "
                  "parallel (0: one stream; else at least 16384; positions-only meshes without "
                  "preserved order or non-manifold vertices)")
      ->capture_default_str();
  cmd->add_option("--normal-bits", args->options.normal_bits,
                  "Octahedral bits per normal coordinate, per vertex or corner (2-20; 0 drops normals)")
      ->check(CLI::Range(0, 20));
  cmd->add_option("--texcoord-bits", args->options.texcoord_bits,
                  "Bits per texture coordinate, per vertex or corner (1-30; 0 drops them)")
      ->check(CLI::Range(0, 30));
  cmd->add_option("--attribute-bits", args->options.attribute_bits,
                  "Bits per component of other vertex properties, e.g. v:color (1-30; 0 drops them)")
      ->check(CLI::Range(0, 30));
  add_common_options(cmd, args->common, kJson | kQuiet | kForce);
}

void add_decompress_command(CLI::App& app) {
  struct Args {
    std::string input, output;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(app, "decompress", "Decompress a .gmc stream to a mesh file", [args] {
    const DecompressResult r = decompress(read_bytes(args->input));
    // A stream of a non-manifold source: its split vertices are written as one again.
    PolygonSoup soup = to_soup(r.mesh);
    if (!r.vertex_representative.empty()) join_vertices(soup, r.vertex_representative);
    write_output(soup, {args->input}, args->common, {}, args->output);
    nlohmann::json j = {{"vertices", soup.positions.size()},
                        {"faces", r.mesh.n_faces()},
                        {"joined_vertices", r.mesh.n_vertices() - soup.positions.size()},
                        {"order_preserved", r.order_preserved},
                        {"max_error", r.max_error}};
    report(args->common, j,
           "decoded " + std::to_string(soup.positions.size()) + " vertices, " +
               std::to_string(r.mesh.n_faces()) + " faces");
    return 0;
  });
  cmd->add_option("input", args->input, "Compressed stream (.gmc)")->required();
  cmd->add_option("output", args->output, "Mesh file to write")->required();
  add_common_options(cmd, args->common, kJson | kQuiet | kForce | kFormat);
}

}  // namespace geom::cli
