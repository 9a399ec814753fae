// `geom compress IN OUT.gmc` and `geom decompress IN.gmc OUT`: the mesh codec (geom/compress).

#include "commands.h"
#include "common.h"

#include <geom/compress/container/codec.h>
#include <geom/compress/container/soup_codec.h>

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

}  // namespace

void add_compress_command(CLI::App& app) {
  struct Args {
    std::string input, output;
    CompressOptions options;
    CommonOptions common;
  };
  auto args = std::make_shared<Args>();
  CLI::App* cmd = add_command(app, "compress",
                              "Compress a mesh file to a .gmc stream as given: every face (degenerate "
                              "and duplicate ones too), each polygon's first corner, and a "
                              "non-manifold file's vertices come back from decompress",
                              [args] {
    require_extension(args->output, {".gmc"}, "output");
    check_not_input(args->output, {args->input}, args->common);
    // The file as given: what a half-edge mesh cannot hold travels beside it (soup_codec.h).
    const PolygonSoup soup = read_input(args->input, args->common);
    const CompressResult r = compress(soup, args->options);
    write_bytes(args->output, r.bytes);
    const CompressStats& st = r.stats;
    const std::size_t n_vertices = soup.positions.size();
    const std::size_t n_faces = soup.n_faces() - st.unstorable_faces;
    const double nv = std::max<double>(1.0, static_cast<double>(n_vertices));
    nlohmann::json j = {{"bytes", r.bytes.size()},
                        {"vertices", n_vertices},
                        {"faces", n_faces},
                        {"bits_per_vertex", 8.0 * r.bytes.size() / nv},
                        {"connectivity_bits_per_vertex", 8.0 * st.connectivity_bytes / nv},
                        {"geometry_bits_per_vertex", 8.0 * st.geometry_bytes / nv},
                        {"order_bits_per_vertex", 8.0 * st.order_bytes / nv},
                        {"normal_bits_per_vertex", 8.0 * st.normal_bytes / nv},
                        {"texcoord_bits_per_vertex", 8.0 * st.texcoord_bytes / nv},
                        {"texcoord_max_error", st.texcoord_max_error},
                        {"rotation_bytes", st.rotation_bytes},
                        {"loose_faces", st.loose_faces},
                        {"loose_face_bytes", st.loose_face_bytes},
                        {"unstored_faces", st.unstorable_faces},
                        {"quantisation_bits", st.bits},
                        {"chunks", st.chunks},
                        {"split_vertices", st.split_copies},
                        {"source_vertices", n_vertices},
                        {"max_error", st.max_error},
                        {"dropped_properties", st.dropped_properties}};
    for (const AttributeStats& a : st.attributes)
      j["attributes"][a.name] = {{"bytes", a.bytes},
                                 {"bits_per_vertex", 8.0 * a.bytes / nv},
                                 {"max_error", a.max_error}};
    if (!args->common.quiet) {
      if (st.split_copies > 0)
        std::cerr << "geom compress: non-manifold input: coded as a manifold mesh with "
                  << st.split_copies << " vertices split apart; geom decompress joins them again\n";
      if (st.loose_faces > 0)
        std::cerr << "geom compress: " << st.loose_faces
                  << " faces a mesh cannot hold (degenerate, zero-area or duplicate) stored beside "
                     "it; geom decompress writes them back\n";
      if (st.unstorable_faces > 0)
        std::cerr << "geom compress: warning: " << st.unstorable_faces
                  << " faces name a vertex beyond the file's " << n_vertices
                  << ": not stored, decompression will not restore them\n";
    }
    // Properties the stream cannot hold must not vanish unnoticed.
    warn_not_carried("compress", r.stats.dropped_properties, args->common,
                     "not stored, decompression will not restore");
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
  cmd->add_flag("!--any-corner-order", args->options.keep_corner_order,
                "Let polygons of 4+ corners start at another corner (smaller; a non-planar "
                "polygon's fan triangulation then changes)");
  cmd->add_flag("--keep-triangle-corners", args->options.keep_triangle_corners,
                "Keep triangles' first corners too (larger; their surface does not depend on it)");
  cmd->add_option("--chunk-triangles", args->options.chunk_triangles,
                  "Split meshes of at least twice this many triangles into chunks that decode in "
                  "parallel (0: one stream; else at least 16384; positions-only meshes without "
                  "preserved order, non-manifold vertices, loose faces or kept polygon corners)")
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
    // The source as it was: its loose faces back, its split vertices joined.
    const PolygonSoup soup = to_soup(r);
    write_output(soup, {args->input}, args->common, {}, args->output);
    nlohmann::json j = {{"vertices", soup.positions.size()},
                        {"faces", soup.n_faces()},
                        {"loose_faces", r.loose_faces.size()},
                        {"joined_vertices", r.mesh.n_vertices() - soup.positions.size()},
                        {"order_preserved", r.order_preserved},
                        {"max_error", r.max_error}};
    report(args->common, j,
           "decoded " + std::to_string(soup.positions.size()) + " vertices, " +
               std::to_string(soup.n_faces()) + " faces");
    return 0;
  });
  cmd->add_option("input", args->input, "Compressed stream (.gmc)")->required();
  cmd->add_option("output", args->output, "Mesh file to write")->required();
  add_common_options(cmd, args->common, kJson | kQuiet | kForce | kFormat);
}

}  // namespace geom::cli
