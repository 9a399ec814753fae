// geom's mesh codec against Draco (Edgebreaker, cl 7 and cl 10) and meshoptimizer's
// index/vertex codecs, on the same meshes with the same position bits: bytes, bits per
// vertex (connectivity / geometry), encode and decode time, max position error. Then a
// quantisation sweep (8…16 bits) of size, max/RMS error and time.
//
// Times are CPU seconds (best of a few runs), and for encode and flat decode also wall
// seconds: Draco and meshoptimizer are single-threaded, geom codes and decodes the chunks of
// a large mesh (CompressOptions::chunk_triangles) on every core, so its CPU time counts all
// threads and its wall time is what a caller waits (meaningful on an otherwise idle machine).
// "geom L7 1 chunk" is level 7 as one stream: what chunking costs in bytes and saves in time.
// decode_ms builds our half-edge SurfaceMesh; decode_flat_ms decodes to position and index
// arrays, which is what Draco's and meshoptimizer's decoders return, so dec/draco_cl10
// (CPU) and dec_wall/draco_cl10 compare those. A note under the table says when Draco's decoder returns fewer vertices
// than the input: it drops unreferenced (isolated) ones, which geom keeps and pays for.
// reuse_wall_ms is the flat decode through one codec::FlatDecoder into the arrays of the
// previous decode, as meshoptimizer's decoders write into the caller's arrays (its figure is
// that one); decode_flat_wall_ms allocates anew each time, and the fresh pages the kernel
// must clear are part of what it measures.
//
// Usage: bench_compress [--quick] [--only NAME] [--no-sweep] [--save-streams DIR]
//   --quick: a 100k-triangle synthetic mesh, no sweep; --only: meshes whose name contains
//   NAME (the synthetic one is "...-sub-flip-shuffled"); --no-sweep: skip the bits sweep;
//   --save-streams: write each geom stream of the main table to DIR/<mesh> <codec>.gmc, so
//   that a decoder change can be timed and profiled on exactly these bytes.
// --corner-order prints only what keeping the source's faces' first corners costs (bytes and
// bits per polygon / triangle against keep_corner_order = false), in
// bench-out/compress_corner_order.csv.
// A third table compares the cost of per-corner texture coordinates with seams (real textured
// meshes from GEOM_DATA_DIR) against Draco's, in bench-out/compress_texcoords.csv.
// Writes bench-out/compress.csv and bench-out/compress_bits.csv; the accuracy chart (one
// command):
//   bench/plot.py bench-out/compress_bits.csv --x max_err --y bpv --group codec --logx
//       --title "compression: bits per vertex against max error (8-16 bits)"
//       -o bench-out/compress_bits.png

#include "support/harness.h"

#include <geom/compress/container/codec.h>
#include <geom/compress/container/soup_codec.h>
#include <geom/core/soup.h>
#include <geom/io/io.h>

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/mesh.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>
#include <meshoptimizer.h>

#include <cmath>
#include <cstring>
#include <numeric>
#include <random>
#include <unordered_map>

using namespace geom;
using namespace geom::bench;

namespace {

struct Flat {
  std::string name;
  std::vector<Point> points;
  std::vector<std::uint32_t> tris;
};

Flat flatten_triangles(const std::string& name, const SurfaceMesh& m) {
  Flat f{name, {}, {}};
  std::vector<std::uint32_t> dense(m.vertices_size());
  for (Vertex v : m.vertices()) {
    dense[v.idx()] = static_cast<std::uint32_t>(f.points.size());
    f.points.push_back(m.position(v));
  }
  for (Face fc : m.faces()) {
    std::vector<std::uint32_t> c;
    for (Vertex v : m.vertices(fc)) c.push_back(dense[v.idx()]);
    for (std::size_t i = 1; i + 1 < c.size(); ++i) f.tris.insert(f.tris.end(), {c[0], c[i], c[i + 1]});
  }
  return f;
}

SurfaceMesh build(const Flat& f) {
  SurfaceMesh m;
  m.reserve(f.points.size(), f.tris.size() / 2 + f.points.size(), f.tris.size() / 3);
  for (const Point& p : f.points) m.add_vertex(p);
  for (std::size_t t = 0; t < f.tris.size(); t += 3)
    m.add_triangle(Vertex(f.tris[t]), Vertex(f.tris[t + 1]), Vertex(f.tris[t + 2]));
  return m;
}

/// 1-to-4 midpoint subdivision with jittered new vertices.
Flat subdivide(const Flat& in, std::mt19937& rng, double jitter) {
  Flat out{in.name, in.points, {}};
  std::unordered_map<std::uint64_t, std::uint32_t> mid;
  mid.reserve(in.tris.size());
  std::normal_distribution<double> n(0.0, 1.0);
  auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
    const std::uint64_t key = (std::uint64_t{std::min(a, b)} << 32) | std::max(a, b);
    auto [it, fresh] = mid.try_emplace(key, static_cast<std::uint32_t>(out.points.size()));
    if (fresh) {
      const double len = (in.points[a] - in.points[b]).norm();
      out.points.push_back(0.5 * (in.points[a] + in.points[b]) +
                           jitter * len * Eigen::Vector3d(n(rng), n(rng), n(rng)));
    }
    return it->second;
  };
  for (std::size_t t = 0; t < in.tris.size(); t += 3) {
    const std::uint32_t a = in.tris[t], b = in.tris[t + 1], c = in.tris[t + 2];
    const std::uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    out.tris.insert(out.tris.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
  }
  return out;
}

/// Irregular, shuffled ~1M-triangle mesh: a real mesh subdivided twice with jitter, a
/// quarter of its edges flipped at random, vertex and face order shuffled.
Flat big_mesh(const Flat& base, std::size_t target_tris) {
  std::mt19937 rng(2024);
  Flat f = base;
  while (f.tris.size() / 3 * 4 <= target_tris * 5 / 4) f = subdivide(f, rng, 0.05);
  SurfaceMesh m = build(f);
  std::uniform_int_distribution<std::uint32_t> pick(0, static_cast<std::uint32_t>(m.n_edges() - 1));
  for (std::size_t i = 0; i < m.n_edges() / 4; ++i) {
    const Edge e(pick(rng));
    if (m.can_flip(e)) m.flip(e);
  }
  f = flatten_triangles(base.name, m);
  std::vector<std::uint32_t> perm(f.points.size());
  std::iota(perm.begin(), perm.end(), 0u);
  std::shuffle(perm.begin(), perm.end(), rng);
  Flat s{base.name + "-sub-flip-shuffled", std::vector<Point>(f.points.size()), {}};
  for (std::size_t i = 0; i < perm.size(); ++i) s.points[perm[i]] = f.points[i];
  std::vector<std::uint32_t> order(f.tris.size() / 3);
  std::iota(order.begin(), order.end(), 0u);
  std::shuffle(order.begin(), order.end(), rng);
  for (std::uint32_t t : order)
    for (int j = 0; j < 3; ++j) s.tris.push_back(perm[f.tris[3 * t + j]]);
  return s;
}

Flat torus(int nu, int nv) {
  Flat f{"torus", {}, {}};
  const double pi = std::acos(-1.0);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double u = 2 * pi * i / nu, v = 2 * pi * j / nv;
      f.points.push_back({(3 + std::cos(v)) * std::cos(u), (3 + std::cos(v)) * std::sin(u), std::sin(v)});
    }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>((j % nv) * nu + (i % nu)); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i)
      f.tris.insert(f.tris.end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j), id(i + 1, j + 1), id(i, j + 1)});
  return f;
}

struct Row {
  std::string codec;
  std::size_t bytes = 0, conn_bytes = 0, geom_bytes = 0;
  double enc = 0, dec = 0, dec_flat = 0, max_err = 0;
  double enc_wall = 0, dec_flat_wall = 0;  // ours uses every core on chunked streams
  double dec_reuse_wall = 0;  // decoding into buffers kept from the previous decode (0: n/a)
  bool err_is_bound = false;
  std::size_t decoded_vertices = 0;  // what the decoder returns (Draco drops unreferenced ones)
};

std::filesystem::path save_streams;  // --save-streams (empty: none)

Row run_ours(const Flat& f, const SurfaceMesh& m, unsigned bits, int level, bool preserve,
             bool one_stream = false) {
  Row r;
  r.codec = std::string("geom L") + std::to_string(level) + (preserve ? " ordered" : "") +
            (one_stream ? " 1 chunk" : "");
  CompressResult c;
  const CompressOptions options{.bits = bits, .level = level, .preserve_order = preserve,
                                .chunk_triangles = one_stream ? 0 : CompressOptions{}.chunk_triangles};
  const CpuWall enc = cpu_wall_min([&] { c = compress(m, options); }, 2);
  r.enc = enc.cpu, r.enc_wall = enc.wall;
  r.bytes = c.bytes.size();
  if (!save_streams.empty()) {
    std::filesystem::create_directories(save_streams);
    std::ofstream(save_streams / (f.name + " " + r.codec + ".gmc"), std::ios::binary)
        .write(reinterpret_cast<const char*>(c.bytes.data()), static_cast<std::streamsize>(c.bytes.size()));
  }
  r.conn_bytes = c.stats.connectivity_bytes + c.stats.order_bytes;
  r.geom_bytes = c.stats.geometry_bytes;
  codec::FlatDecode fd;
  const CpuWall dec = cpu_wall_min([&] { fd = codec::decompress_flat(c.bytes); }, 5);
  r.dec_flat = dec.cpu, r.dec_flat_wall = dec.wall;
  codec::FlatDecoder decoder;
  r.dec_reuse_wall = cpu_wall_min([&] { decoder.decode(c.bytes, fd); }, 5).wall;
  DecompressResult d;
  r.dec = cpu_time_min([&] { d = decompress(c.bytes); }, 2);
  std::size_t i = 0;
  for (Vertex v : d.mesh.vertices()) {
    const Point& p = f.points[c.vertex_permutation[i++]];
    r.max_err = std::max(r.max_err, (d.mesh.position(v) - p).cwiseAbs().maxCoeff());
  }
  return r;
}

Row run_draco(const Flat& f, unsigned bits, int cl) {
  Row r;
  r.codec = "draco cl" + std::to_string(cl);
  draco::Mesh dm;
  draco::GeometryAttribute ga;
  ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
  const int att = dm.AddAttribute(ga, true, static_cast<std::uint32_t>(f.points.size()));
  for (std::size_t i = 0; i < f.points.size(); ++i) {
    const float p[3] = {float(f.points[i].x()), float(f.points[i].y()), float(f.points[i].z())};
    dm.attribute(att)->SetAttributeValue(draco::AttributeValueIndex(static_cast<std::uint32_t>(i)), p);
  }
  for (std::size_t t = 0; t < f.tris.size(); t += 3)
    dm.AddFace({draco::PointIndex(f.tris[t]), draco::PointIndex(f.tris[t + 1]), draco::PointIndex(f.tris[t + 2])});
  dm.set_num_points(static_cast<std::uint32_t>(f.points.size()));
  draco::EncoderBuffer buf;
  const CpuWall enc_t = cpu_wall_min([&] {
    draco::Encoder enc;
    enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, static_cast<int>(bits));
    enc.SetSpeedOptions(10 - cl, 10 - cl);
    enc.SetEncodingMethod(draco::MESH_EDGEBREAKER_ENCODING);
    buf.Clear();
    if (!enc.EncodeMeshToBuffer(dm, &buf).ok()) throw Error("draco encode failed");
  }, 2);
  r.enc = enc_t.cpu, r.enc_wall = enc_t.wall;
  r.bytes = buf.size();
  const CpuWall dec = cpu_wall_min([&] {
    draco::DecoderBuffer db;
    db.Init(buf.data(), buf.size());
    draco::Decoder dec;
    auto res = dec.DecodeMeshFromBuffer(&db);
    if (!res.ok()) throw Error("draco decode failed");
    r.decoded_vertices = res.value()->num_points();
  }, 5);
  r.dec = r.dec_flat = dec.cpu;
  r.dec_flat_wall = dec.wall;  // (its decoder allocates the mesh it returns: no reuse)
  Eigen::Vector3d lo = f.points[0], hi = f.points[0];
  for (const Point& p : f.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  r.max_err = 0.5 * (hi - lo).maxCoeff() / double((1u << bits) - 1);
  r.err_is_bound = true;
  return r;
}

Row run_meshopt(const Flat& f, unsigned bits) {
  Row r;
  r.codec = "meshopt";
  struct QV { std::uint16_t x, y, z, w; };
  Eigen::Vector3d lo = f.points[0], hi = f.points[0];
  for (const Point& p : f.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double step = (hi - lo).maxCoeff() / double((1u << bits) - 1);
  std::vector<std::uint8_t> ib, vb;
  std::vector<std::uint32_t> remap(f.points.size());
  const std::size_t nv = f.points.size(), ni = f.tris.size();
  const CpuWall enc = cpu_wall_min([&] {
    std::vector<std::uint32_t> idx(ni);
    meshopt_optimizeVertexCache(idx.data(), f.tris.data(), ni, nv);
    std::vector<QV> q(nv);
    for (std::size_t i = 0; i < nv; ++i) {
      const Eigen::Vector3d t = ((f.points[i] - lo) / step).array().round();
      q[i] = {std::uint16_t(t.x()), std::uint16_t(t.y()), std::uint16_t(t.z()), 0};
    }
    std::vector<QV> qo(nv);
    meshopt_optimizeVertexFetchRemap(remap.data(), idx.data(), ni, nv);
    meshopt_remapIndexBuffer(idx.data(), idx.data(), ni, remap.data());
    meshopt_remapVertexBuffer(qo.data(), q.data(), nv, sizeof(QV), remap.data());
    ib.resize(meshopt_encodeIndexBufferBound(ni, nv));
    ib.resize(meshopt_encodeIndexBuffer(ib.data(), ib.size(), idx.data(), ni));
    vb.resize(meshopt_encodeVertexBufferBound(nv, sizeof(QV)));
    vb.resize(meshopt_encodeVertexBuffer(vb.data(), vb.size(), qo.data(), nv, sizeof(QV)));
  }, 2);
  r.enc = enc.cpu, r.enc_wall = enc.wall;
  r.bytes = ib.size() + vb.size();
  r.conn_bytes = ib.size();
  r.geom_bytes = vb.size();
  std::vector<std::uint32_t> idx(ni);
  std::vector<QV> qv(nv);
  const CpuWall dec = cpu_wall_min([&] {
    if (meshopt_decodeIndexBuffer(idx.data(), ni, 4, ib.data(), ib.size()) != 0 ||
        meshopt_decodeVertexBuffer(qv.data(), nv, sizeof(QV), vb.data(), vb.size()) != 0)
      throw Error("meshopt decode failed");
  }, 5);
  r.dec = r.dec_flat = dec.cpu;
  r.dec_flat_wall = r.dec_reuse_wall = dec.wall;  // into the same arrays every time
  for (std::size_t i = 0; i < nv; ++i) {
    if (remap[i] == ~0u) continue;  // unreferenced vertex: meshopt drops it
    const QV& q = qv[remap[i]];
    const Eigen::Vector3d p = lo + step * Eigen::Vector3d(q.x, q.y, q.z);
    r.max_err = std::max(r.max_err, (p - f.points[i]).cwiseAbs().maxCoeff());
  }
  return r;
}

/// Draco's bytes for positions + per-corner UVs (its corner table codes the UV seams), with
/// the positions alone, at compression level cl; the difference is what the UVs cost.
std::pair<std::size_t, std::size_t> draco_uv_bytes(const SurfaceMesh& m, unsigned bits, unsigned uv_bits, int cl) {
  const auto uv = m.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  std::size_t sizes[2] = {0, 0};
  for (int with_uv = 0; with_uv < 2; ++with_uv) {
    std::vector<std::array<Halfedge, 3>> tris;
    for (Face f : m.faces()) {
      std::vector<Halfedge> c(m.halfedges(f).begin(), m.halfedges(f).end());
      for (std::size_t i = 1; i + 1 < c.size(); ++i) tris.push_back({c[0], c[i], c[i + 1]});
    }
    draco::TriangleSoupMeshBuilder b;
    b.Start(static_cast<int>(tris.size()));
    const int pos = b.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
    const int tex = with_uv ? b.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32) : -1;
    for (std::size_t t = 0; t < tris.size(); ++t) {
      float p[3][3], q[3][2];
      for (int k = 0; k < 3; ++k) {
        const Point& x = m.position(m.to_vertex(tris[t][k]));
        for (int a = 0; a < 3; ++a) p[k][a] = float(x[a]);
        for (int a = 0; a < 2; ++a) q[k][a] = float(uv[tris[t][k]][a]);
      }
      const draco::FaceIndex fi(static_cast<std::uint32_t>(t));
      b.SetAttributeValuesForFace(pos, fi, p[0], p[1], p[2]);
      if (with_uv) b.SetAttributeValuesForFace(tex, fi, q[0], q[1], q[2]);
    }
    const std::unique_ptr<draco::Mesh> dm = b.Finalize();
    draco::Encoder enc;
    enc.SetAttributeQuantization(draco::GeometryAttribute::POSITION, static_cast<int>(bits));
    enc.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, static_cast<int>(uv_bits));
    enc.SetSpeedOptions(10 - cl, 10 - cl);
    enc.SetEncodingMethod(draco::MESH_EDGEBREAKER_ENCODING);
    draco::EncoderBuffer buf;
    if (!dm || !enc.EncodeMeshToBuffer(*dm, &buf).ok()) throw Error("draco encode failed");
    sizes[with_uv] = buf.size();
  }
  return {sizes[1], sizes[1] - sizes[0]};
}

/// Texture coordinates with seams (per-corner UVs, as a textured OBJ loads): bits per vertex
/// of the UV layer, ours (seam bits + wedge values) against Draco's, 12-bit UVs both.
void texcoord_table(const std::filesystem::path& dir, unsigned bits, const std::string& only) {
  Table t({"mesh", "V", "corners", "codec", "bytes", "bpv", "uv_bytes", "uv_bpv", "uv_max_err"});
  bool any = false;
  for (const char* name : {"spot_triangulated.obj", "beast.obj"}) {
    if (std::string(name).find(only) == std::string::npos) continue;
    SurfaceMesh m;
    try {
      m = load_mesh(dir / name).mesh;
    } catch (const std::exception& e) {
      std::cerr << "skip " << name << ": " << e.what() << '\n';
      continue;
    }
    if (!m.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord)) continue;
    std::size_t corners = 0;
    for (Face f : m.faces()) corners += m.valence(f);
    const double nv = static_cast<double>(m.n_vertices());
    auto add = [&](const std::string& codec, std::size_t bytes, std::size_t uv_bytes, const std::string& err) {
      any = true;
      t.add({name, std::to_string(m.n_vertices()), std::to_string(corners), codec, std::to_string(bytes),
             fmt(8.0 * bytes / nv, 4), std::to_string(uv_bytes), fmt(8.0 * uv_bytes / nv, 4), err});
    };
    const CompressResult c = compress(m, {.bits = bits});
    for (const AttributeStats& a : c.stats.attributes)
      if (a.name == prop::kCornerTexCoord) add("geom L7", c.bytes.size(), a.bytes, fmt(a.max_error, 3));
    for (int cl : {7, 10}) {
      const auto [bytes, uv_bytes] = draco_uv_bytes(m, bits, 12, cl);
      add("draco cl" + std::to_string(cl), bytes, uv_bytes, "-");
    }
  }
  if (!any) return;
  t.print();
  t.write_csv(out_dir() / "compress_texcoords.csv");
}

}  // namespace

/// What keeping the source's faces as given costs (positions only, so the figures are the
/// core stream's): polygons' first corners (the default) against the old stream
/// (keep_corner_order off), and triangles' first corners on request.
void corner_order_table(const std::filesystem::path& dir, unsigned bits) {
  Table t({"mesh", "faces", "polygons", "old_bytes", "bytes", "extra_bytes", "extra_%",
           "bits/polygon", "+tri_corners_bytes", "bits/triangle"});
  for (const char* name : {"spot_quadrangulated.obj", "fandisk_quads.off", "horse_quad.obj",
                           "beast.obj", "suzanne.obj", "cylinder.obj", "spot_triangulated.obj",
                           "fandisk.off", "bunny_closed.off", "stanford-bunny.obj", "nefertiti.obj"}) {
    PolygonSoup soup;
    try {
      const PolygonSoup file = read_soup(dir / name);
      soup.positions = file.positions;
      soup.face_offsets = file.face_offsets;
      soup.face_indices = file.face_indices;
    } catch (const std::exception& e) {
      std::cerr << "skip " << name << ": " << e.what() << '\n';
      continue;
    }
    std::size_t polygons = 0, triangles = 0;
    for (std::size_t f = 0; f < soup.n_faces(); ++f)
      (soup.face(f).size() > 3 ? polygons : triangles) += 1;
    const std::size_t old = compress(soup, {.bits = bits, .keep_corner_order = false}).bytes.size();
    const std::size_t now = compress(soup, {.bits = bits}).bytes.size();
    const std::size_t all =
        compress(soup, {.bits = bits, .keep_triangle_corners = true}).bytes.size();
    auto per = [](std::size_t bytes, std::size_t n) { return n ? fmt(8.0 * double(bytes) / double(n), 3) : std::string("-"); };
    t.add({name, std::to_string(soup.n_faces()), std::to_string(polygons), std::to_string(old),
           std::to_string(now), std::to_string(now - old), fmt(100.0 * double(now - old) / double(old), 3),
           per(now - old, polygons), std::to_string(all - now), per(all - now, triangles)});
  }
  t.print();
  t.write_csv(out_dir() / "compress_corner_order.csv");
}

int main(int argc, char** argv) {
  bool quick = false, sweep_bits = true, corner_order = false;
  std::string only;
  const char* const usage =
      "usage: bench_compress [--quick] [--only NAME] [--no-sweep] [--save-streams DIR] [--corner-order]";
  if (wants_help(argc, argv, usage)) return 0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--quick") quick = true;
    else if (a == "--no-sweep") sweep_bits = false;
    else if (a == "--only" && i + 1 < argc) only = argv[++i];
    else if (a == "--save-streams" && i + 1 < argc) save_streams = argv[++i];
    else if (a == "--corner-order") corner_order = true;
    else {
      std::cerr << usage << "\n";
      return 2;
    }
  }
  const unsigned bits = 11;
  std::vector<Flat> meshes;
  const auto dir = data_dir();
  if (corner_order) {
    if (dir) corner_order_table(*dir, bits);
    return 0;
  }
  Flat bunny;
  if (dir) {
    for (const char* name : {"nefertiti.obj", "armadillo.obj", "stanford-bunny.obj", "bunny_closed.off"}) {
      try {
        Flat f = flatten_triangles(name, load_mesh(*dir / name).mesh);
        if (std::string(name) == "bunny_closed.off") bunny = f;
        else meshes.push_back(std::move(f));
      } catch (const std::exception& e) {
        std::cerr << "skip " << name << ": " << e.what() << '\n';
      }
    }
  }
  if (bunny.tris.empty()) bunny = torus(200, 150);
  meshes.insert(meshes.begin(), big_mesh(bunny, quick ? 100000 : 1000000));
  if (!only.empty())
    std::erase_if(meshes, [&](const Flat& f) { return f.name.find(only) == std::string::npos; });

  std::vector<std::string> notes;
  Table table({"mesh", "V", "F", "codec", "bytes", "bpv", "bpv_conn", "bpv_geom", "encode_ms",
               "encode_wall_ms", "decode_ms", "decode_flat_ms", "decode_flat_wall_ms",
               "reuse_wall_ms", "max_err",
               "size/draco_cl10", "dec/draco_cl10", "dec_wall/draco_cl10"});
  for (const Flat& f : meshes) {
    const SurfaceMesh m = build(f);
    std::vector<Row> rows;
    rows.push_back(run_draco(f, bits, 7));
    rows.push_back(run_draco(f, bits, 10));
    rows.push_back(run_meshopt(f, bits));
    for (int level : {0, 3, 7, 9}) rows.push_back(run_ours(f, m, bits, level, false));
    if (CompressOptions{}.chunk_triangles > 0 && f.tris.size() / 3 >= 2 * CompressOptions{}.chunk_triangles)
      rows.push_back(run_ours(f, m, bits, 7, false, true));  // what chunking costs and saves
    rows.push_back(run_ours(f, m, bits, 7, true));
    const Row& d10 = rows[1];
    if (d10.decoded_vertices != f.points.size())
      notes.push_back(f.name + ": Draco decodes " + std::to_string(d10.decoded_vertices) + " of " +
                      std::to_string(f.points.size()) +
                      " vertices (it drops unreferenced ones; geom keeps and codes them all)");
    const double nv = static_cast<double>(f.points.size());
    for (const Row& r : rows) {
      table.add({f.name, std::to_string(f.points.size()), std::to_string(f.tris.size() / 3), r.codec,
                 std::to_string(r.bytes), fmt(8.0 * r.bytes / nv, 4),
                 r.conn_bytes ? fmt(8.0 * r.conn_bytes / nv, 4) : "-",
                 r.geom_bytes ? fmt(8.0 * r.geom_bytes / nv, 4) : "-", fmt(1e3 * r.enc, 4),
                 fmt(1e3 * r.enc_wall, 4), fmt(1e3 * r.dec, 4), fmt(1e3 * r.dec_flat, 4),
                 fmt(1e3 * r.dec_flat_wall, 4),
                 r.dec_reuse_wall > 0 ? fmt(1e3 * r.dec_reuse_wall, 4) : "-",
                 fmt(r.max_err, 3) + (r.err_is_bound ? " (bound)" : ""),
                 ratio(double(r.bytes), double(d10.bytes)), ratio(r.dec_flat, d10.dec),
                 ratio(r.dec_flat_wall, d10.dec_flat_wall)});
    }
  }
  table.print();
  for (const std::string& n : notes) std::cout << "note: " << n << '\n';
  table.write_csv(out_dir() / "compress.csv");
  if (dir) texcoord_table(*dir, bits, only);
  if (quick || !sweep_bits || meshes.empty()) return 0;

  // What accuracy costs: bits against size, error and time on the big mesh.
  Table sweep({"bits", "codec", "bytes", "bpv", "max_err", "rms_err", "encode_ms", "decode_ms"});
  const Flat& f = meshes.front();
  const SurfaceMesh m = build(f);
  const double nv = static_cast<double>(f.points.size());
  for (unsigned b = 8; b <= 16; ++b) {
    CompressResult c;
    const double enc = cpu_time_min([&] { c = compress(m, {.bits = b}); }, 1);
    codec::FlatDecode fd;
    const double dec = cpu_time_min([&] { fd = codec::decompress_flat(c.bytes); }, 2);
    double maxe = 0, sum = 0;
    for (std::size_t i = 0; i < c.vertex_permutation.size(); ++i) {
      const Point& p = f.points[c.vertex_permutation[i]];
      const Eigen::Vector3d d(fd.positions[3 * i] - p.x(), fd.positions[3 * i + 1] - p.y(),
                              fd.positions[3 * i + 2] - p.z());
      maxe = std::max(maxe, d.cwiseAbs().maxCoeff());
      sum += d.squaredNorm();
    }
    // rms_err is of the 3-D error vector; max_err is per coordinate.
    sweep.add({std::to_string(b), "geom L7", std::to_string(c.bytes.size()),
               fmt(8.0 * c.bytes.size() / nv, 4), fmt(maxe, 3), fmt(std::sqrt(sum / nv), 3),
               fmt(1e3 * enc, 4), fmt(1e3 * dec, 4)});
    const Row d10 = run_draco(f, b, 10);
    sweep.add({std::to_string(b), "draco cl10", std::to_string(d10.bytes),
               fmt(8.0 * d10.bytes / nv, 4), fmt(d10.max_err, 3), "n/a", fmt(1e3 * d10.enc, 4),
               fmt(1e3 * d10.dec, 4)});
  }
  sweep.print();
  sweep.write_csv(out_dir() / "compress_bits.csv");
  return 0;
}
