// compress(): the level's search over traversals and predictors, and the stream writer.
// The reader is codec.cpp; FORMAT.md specifies the stream.
#include <geom/compress/container/codec.h>

#include <geom/compress/attributes.h>
#include <geom/compress/connectivity.h>
#include <geom/compress/container/chunks.h>
#include <geom/compress/container/extension.h>
#include <geom/compress/container/mesh_tables.h>
#include <geom/compress/container/stream.h>
#include <geom/compress/point_chain.h>
#include <geom/compress/predict.h>
#include <geom/compress/quantise.h>
#include <geom/compress/rans.h>
#include <geom/core/soup.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

namespace geom {

namespace {

using namespace codec;
using namespace codec::detail;

/// One traversal's connectivity coding, shared by every candidate coded on it.
struct Traversed {
  Traversal traversal = Traversal::kRightFirst;
  Streams connectivity;
  CornerTable table;
  TraversalOrder order;
  std::vector<std::uint32_t> vertex_order;  // decoded vertex → dense input vertex
  std::vector<QPoint> q;                    // grid points in vertex_order
};

/// A configuration's coding. Only the degree-order predictors renumber the table, so only
/// they own a table and vertex order (the growth order with anchored isolated vertices
/// reorders those, so it owns a vertex order); the others read their traversal's (a level
/// tries up to eight candidates and copying megabytes for each was a fifth of the encode time).
struct Candidate {
  const Traversed* base = nullptr;
  Predictor predictor = Predictor::kDelta;
  Blend blend;  // with predictors 4–7
  bool anchored = false;  // predictors 5 and 7: isolated vertices predicted from anchors
  unsigned log2_deadline = 0;  // predictors 6 and 7
  Streams geometry;
  bool renumbered = false;
  bool reordered = false;  // own vertex order only
  CornerTable own_table;
  std::vector<std::uint32_t> own_vertex_order;

  Traversal traversal() const { return base->traversal; }
  const Streams& connectivity() const { return base->connectivity; }
  const TraversalOrder& order() const { return base->order; }
  const CornerTable& table() const { return renumbered ? own_table : base->table; }
  const std::vector<std::uint32_t>& vertex_order() const {
    return renumbered || reordered ? own_vertex_order : base->vertex_order;
  }
};

/// The configurations a level may try; each level's set contains the previous level's.
/// Below level 9 the left-first traversal codes only the predictor whose right-first stream
/// was smallest (search()): the predictors rank alike on both traversals, and that rule,
/// the same at levels 6–8, keeps each level's tried set a superset of the one below.
/// Level 9 also codes predictors 4 and 5 in growth order (6 and 7: the Stanford bunny's
/// stream is 0.6 % smaller with 7); they decode a few per cent slower, even fused into the
/// connectivity decoder, so the lower levels keep the degree order (see predict_growth.cpp).
std::vector<std::pair<Traversal, Predictor>> configurations(int level) {
  std::vector<std::pair<Traversal, Predictor>> c = {{Traversal::kRightFirst, Predictor::kDelta}};
  if (level >= 1) c.push_back({Traversal::kRightFirst, Predictor::kParallelogram});
  if (level >= 3) c.push_back({Traversal::kRightFirst, Predictor::kMultiParallelogram});
  // Predictor 3 is only decoded now: 4 codes the same with zero weights, in fewer bits.
  if (level >= 5) c.push_back({Traversal::kRightFirst, Predictor::kMultiParallelogramBlend});
  if (level >= 6) {
    c.push_back({Traversal::kLeftFirst, Predictor::kParallelogram});
    c.push_back({Traversal::kLeftFirst, Predictor::kMultiParallelogram});
    c.push_back({Traversal::kLeftFirst, Predictor::kMultiParallelogramBlend});
    c.push_back({Traversal::kRightFirst, Predictor::kMultiParallelogramSelect});
    c.push_back({Traversal::kLeftFirst, Predictor::kMultiParallelogramSelect});
  }
  if (level >= 9) {
    c.push_back({Traversal::kLeftFirst, Predictor::kDelta});
    for (Traversal t : {Traversal::kRightFirst, Traversal::kLeftFirst}) {
      c.push_back({t, Predictor::kGrowthBlend});
      c.push_back({t, Predictor::kGrowthSelect});
    }
  }
  return c;
}

void write_attribute_header(ByteWriter& w, unsigned normal_bits, const Quantiser* uv) {
  if (normal_bits > 0) w.u8(static_cast<std::uint8_t>(normal_bits));
  if (uv) {
    w.u8(static_cast<std::uint8_t>(uv->bits));
    w.f64(uv->origin.x());
    w.f64(uv->origin.y());
    w.f64(uv->step);
  }
}

/// The input's per-vertex normals and texture coordinates (dense order), when present and
/// asked for.
struct Attributes {
  std::vector<Normal> normals;
  std::vector<TexCoord> uvs;
  Quantiser uv_grid;
};

Attributes gather_attributes(const SurfaceMesh& mesh, const CompressOptions& options) {
  if (options.normal_bits == 1 || options.normal_bits > 20)
    throw InvalidArgument("compress: normal bits must be 0 or in [2, 20], got " +
                          std::to_string(options.normal_bits));
  if (options.texcoord_bits > 30)
    throw InvalidArgument("compress: texture coordinate bits must be in [0, 30], got " +
                          std::to_string(options.texcoord_bits));
  Attributes a;
  const auto normals = mesh.get_property<Vertex, Normal>(prop::kVertexNormal);
  if (options.normal_bits > 0 && normals) {
    const auto& p = normals;
    for (Vertex v : mesh.vertices()) a.normals.push_back(p[v]);
  }
  const auto uvs = mesh.get_property<Vertex, TexCoord>(prop::kVertexTexCoord);
  if (options.texcoord_bits > 0 && uvs) {
    const auto& p = uvs;
    for (Vertex v : mesh.vertices()) a.uvs.push_back(p[v]);
    a.uv_grid = texcoord_quantiser(a.uvs, options.texcoord_bits);
  }
  if (mesh.n_vertices() == 0) a.normals.clear(), a.uvs.clear();
  return a;
}

/// The vertices no triangle uses, in the order they are coded (after the connected ones):
/// each is predicted by the one before it, so a chain through near neighbours keeps those
/// deltas short (scanned meshes such as the Stanford bunny carry thousands).
std::vector<std::uint32_t> isolated_order(const CornerTable& table, std::span<const QPoint> q) {
  std::vector<std::uint8_t> used(q.size(), 0);
  for (std::uint32_t v : table.vertex) used[v] = 1;
  std::vector<std::uint32_t> isolated;
  for (std::uint32_t v = 0; v < q.size(); ++v)
    if (!used[v]) isolated.push_back(v);
  std::vector<QPoint> points(isolated.size());
  for (std::size_t i = 0; i < isolated.size(); ++i) points[i] = q[isolated[i]];
  // A wider search window finds nearer successors (the whole set for the bunny's 1,113,
  // about 0.3 bits a point fewer than a window of 32); the work, n · window, stays below 2^24.
  const std::size_t window = std::clamp<std::size_t>(
      (std::size_t{1} << 24) / std::max<std::size_t>(points.size(), 1), 32, 2048);
  std::vector<std::uint32_t> chain = point_chain(points, static_cast<unsigned>(window));
  for (std::uint32_t& i : chain) i = isolated[i];
  return chain;
}

/// What compress() is coding, shared by the search and the writer.
struct EncodeInput {
  const SurfaceMesh& mesh;
  const CompressOptions& options;
  const FlatMesh& flat;
  const Quantiser& quant;
  const Attributes& attributes;
};

/// Everything coded after the geometry. It depends on the candidate's table and vertex
/// order, so a level's search weighs it too; otherwise a higher level could pick a smaller
/// geometry with larger attributes and give a larger stream.
struct Tail {
  std::vector<std::uint32_t> face_order;  // decoded face → dense input face
  Streams order, normals, uvs;
  ExtensionEncoding extension;
};

/// Each decoded polygon's first corner: the place of its input face's first corner in the
/// rebuilt cycle.
std::vector<std::uint32_t> rotations(const EncodeInput& in, const Candidate& c,
                                     const Polygons& polys,
                                     std::span<const std::uint32_t> face_order) {
  const std::size_t nv = in.flat.positions.size();
  std::vector<std::uint32_t> decoded_id(nv);
  for (std::uint32_t i = 0; i < nv; ++i) decoded_id[c.vertex_order()[i]] = i;
  std::vector<std::uint32_t> rot(polys.size(), 0);
  for (std::size_t j = 0; j < polys.size(); ++j) {
    const std::uint32_t first = decoded_id[in.flat.face_first_vertex[face_order[j]]];
    while (polys.vertex[polys.offset[j] + rot[j]] != first) ++rot[j];
  }
  return rot;
}

Streams encode_order(const EncodeInput& in, const Candidate& c, const Polygons& polys,
                     std::span<const std::uint32_t> face_order) {
  const std::size_t nv = in.flat.positions.size();
  RansEncoder re;
  BitWriter bw;
  GammaModel vm, fm, rm;
  std::int64_t prev = 0;
  for (std::uint32_t v : c.vertex_order()) {
    vm.encode(re, bw, zigzag(std::int64_t{v} - prev));
    prev = v;
  }
  std::vector<std::uint32_t> decoded_id(nv);
  for (std::uint32_t i = 0; i < nv; ++i) decoded_id[c.vertex_order()[i]] = i;
  prev = 0;
  for (std::size_t j = 0; j < polys.size(); ++j) {
    const std::uint32_t f = face_order[j];
    fm.encode(re, bw, zigzag(std::int64_t{f} - prev));
    prev = f;
    const std::uint32_t first = decoded_id[in.flat.face_first_vertex[f]];
    std::uint32_t rot = 0;
    while (polys.vertex[polys.offset[j] + rot] != first) ++rot;
    rm.encode(re, bw, rot);
  }
  Streams s;
  if (re.symbols() > 0) s.rans = re.finish();
  s.raw = bw.finish();
  return s;
}

std::vector<std::uint32_t> face_order(const EncodeInput& in, const Candidate& c,
                                      const Polygons& polys) {
  std::vector<std::uint32_t> order(polys.size());
  for (std::size_t j = 0; j < polys.size(); ++j)
    order[j] = in.flat.triangle_face[c.order().corner_origin[3 * polys.first_triangle[j]] / 3];
  return order;
}

Tail encode_tail(const EncodeInput& in, const Candidate& c) {
  const std::size_t nv = in.flat.positions.size();
  const Attributes& attributes = in.attributes;
  Tail tail;
  const Polygons polys = reassemble(c.table(), 0);
  tail.face_order = face_order(in, c, polys);
  if (in.options.preserve_order) tail.order = encode_order(in, c, polys, tail.face_order);

  // Attributes follow the decoded vertex order on the chosen table.
  const std::vector<std::uint32_t>& vertex_order = c.vertex_order();
  std::vector<QPoint> qa(nv);
  if (!attributes.normals.empty()) {
    for (std::size_t i = 0; i < nv; ++i)
      qa[i] = octahedral_quantise(attributes.normals[vertex_order[i]], in.options.normal_bits,
                                  vertex_order[i]);
    encode_attribute(c.table(), qa, in.options.normal_bits, tail.normals.rans, tail.normals.raw);
  }
  if (!attributes.uvs.empty()) {
    for (std::size_t i = 0; i < nv; ++i) {
      const TexCoord& t = attributes.uvs[vertex_order[i]];
      qa[i] = attributes.uv_grid.quantise(Point(t.x(), t.y(), 0.0));
    }
    encode_attribute(c.table(), qa, attributes.uv_grid.bits, tail.uvs.rans, tail.uvs.raw);
  }
  FaceCorners corners{&polys, {}, in.options.keep_triangle_corners ? 3u : 4u};
  std::vector<std::uint32_t> rotation;
  if (!in.options.preserve_order &&
      (in.options.keep_triangle_corners || (in.options.keep_corner_order && in.flat.polygons))) {
    rotation = rotations(in, c, polys, tail.face_order);
    corners.rotation = rotation;
  }
  tail.extension = encode_extension(in.mesh, in.options, in.flat, c.table(), c.order().corner_origin,
                                    vertex_order, !attributes.normals.empty(),
                                    !attributes.uvs.empty(), corners);
  return tail;
}

/// Whether every candidate's tail is empty, judged from one candidate's: which parts exist
/// depends on the mesh and the options, not on the candidate.
bool tail_is_empty(const Tail& t) {
  return t.order.size() + t.normals.size() + t.uvs.size() + t.extension.bytes.size() == 0;
}

/// The stream of candidate c with its tail, and its stats (not the permutations).
CompressResult write_stream(const EncodeInput& in, const Candidate& c, const Tail& tail) {
  const Attributes& attributes = in.attributes;
  const std::size_t nv = in.flat.positions.size();
  ByteWriter w;
  for (std::uint8_t m : kMagic) w.u8(m);
  const bool has_attributes =
      !attributes.normals.empty() || !attributes.uvs.empty() || !tail.extension.bytes.empty();
  w.u8(has_attributes ? kVersionAttributes : kVersion);
  std::uint8_t flags = kFlagTwoLanes;  // every RansEncoder writes two lanes
  if (in.options.preserve_order) flags |= kFlagPreserveOrder;
  if (in.flat.polygons) flags |= kFlagPolygons;
  if (c.traversal() == Traversal::kLeftFirst) flags |= kFlagLeftFirst;
  if (!attributes.normals.empty()) flags |= kFlagNormals;
  if (!attributes.uvs.empty()) flags |= kFlagTexcoords;
  if (!tail.extension.bytes.empty()) flags |= kFlagExtension;
  w.u8(flags);
  w.u8(static_cast<std::uint8_t>(c.predictor));
  w.u8(static_cast<std::uint8_t>(in.quant.bits));
  for (int a = 0; a < 3; ++a) w.f64(in.quant.origin[a]);
  w.f64(in.quant.step);
  write_attribute_header(w, attributes.normals.empty() ? 0 : in.options.normal_bits,
                         attributes.uvs.empty() ? nullptr : &attributes.uv_grid);
  if (blended(c.predictor)) w.u8(c.blend.byte());
  if (selecting(c.predictor)) w.u8(c.anchored ? 1 : 0);
  if (growth(c.predictor)) w.u8(static_cast<std::uint8_t>(c.log2_deadline));
  w.varint(in.flat.n_faces);
  w.varint(in.flat.table.n_triangles());
  w.varint(nv);
  w.varint(nv - c.table().n_vertices);
  CompressResult result;
  CompressStats& stats = result.stats;
  stats.header_bytes = w.bytes().size();
  // Writes a stream's two sections and returns the bytes they took.
  auto put = [&w](const Streams& s) {
    const std::size_t before = w.bytes().size();
    write_section(w, s.rans);
    write_section(w, s.raw);
    return w.bytes().size() - before;
  };
  stats.connectivity_bytes = put(c.connectivity());
  stats.geometry_bytes = put(c.geometry);
  if (!attributes.normals.empty()) stats.normal_bytes = put(tail.normals);
  if (!attributes.uvs.empty()) {
    stats.texcoord_bytes = put(tail.uvs);
    stats.texcoord_max_error = attributes.uv_grid.max_error();
  }
  if (in.options.preserve_order) stats.order_bytes = put(tail.order);
  w.append(tail.extension.bytes);
  stats.rotation_bytes = tail.extension.rotation_bytes;
  stats.loose_face_bytes = tail.extension.loose_face_bytes;
  stats.attributes = tail.extension.attributes;
  stats.dropped_properties = tail.extension.dropped;
  result.bytes = std::move(w.bytes());
  stats.bits = in.quant.bits;
  stats.step = in.quant.step;
  stats.max_error = in.quant.max_error();
  stats.predictor = static_cast<int>(c.predictor);
  stats.traversal = static_cast<int>(c.traversal());
  return result;
}

/// The smallest whole stream seen so far, with what its permutations need.
struct Best {
  CompressResult result;
  Candidate candidate;
  std::vector<std::uint32_t> face_order;  // empty until known
  bool have = false;
  bool empty_tail = false;  // known once the first candidate's tail is coded
  ExtensionEncoding empty_extension;  // with empty_tail: codes nothing, names what is dropped
};

/// Keeps c in best when its whole stream is smaller; c is left holding buffers to reuse.
/// Returns the size of c's stream.
std::size_t consider(const EncodeInput& in, Candidate& c, Best& best) {
  Tail tail;
  if (!best.have || !best.empty_tail)
    tail = encode_tail(in, c);
  else
    tail.extension = best.empty_extension;
  CompressResult r = write_stream(in, c, tail);
  if (!best.have && tail_is_empty(tail)) {
    best.empty_tail = true;
    best.empty_extension = tail.extension;
  }
  const std::size_t size = r.bytes.size();
  if (best.have && size >= best.result.bytes.size()) return size;
  best.result = std::move(r);
  std::swap(best.candidate, c);
  best.face_order = std::move(tail.face_order);
  best.have = true;
  return size;
}

/// Codes the connectivity with traversal trav into t.
void traverse(const EncodeInput& in, std::span<const QPoint> q_in,
              std::span<const std::uint32_t> isolated, Traversal trav, Traversed& t) {
  t.traversal = trav;
  RansEncoder re;
  re.reserve(in.flat.table.vertex.size() / 2);
  BitWriter bw;
  encode_connectivity(in.flat.table, in.flat.polygons, trav, re, bw, t.table, t.order);
  if (!in.flat.table.vertex.empty()) t.connectivity.rans = re.finish();
  t.connectivity.raw = bw.finish();
  t.vertex_order = t.order.vertex_origin;
  t.vertex_order.insert(t.vertex_order.end(), isolated.begin(), isolated.end());
  t.q.resize(t.vertex_order.size());
  for (std::size_t i = 0; i < t.q.size(); ++i) t.q[i] = q_in[t.vertex_order[i]];
}

/// Codes every configuration of the level and keeps the smallest stream in best, which
/// refers to traversals (they must outlive it).
void search(const EncodeInput& in, std::span<const QPoint> q_in,
            std::span<const std::uint32_t> isolated, std::array<Traversed, 2>& traversals,
            Best& best) {
  const std::size_t nv = in.flat.positions.size();
  Blend blend;  // predictor 4's weights, measured on the first traversal
  bool blend_measured = false;
  Blend growth_blend;  // predictor 6's weights and deadline, tuned on the first traversal
  unsigned log2_deadline = kLog2Deadlines[0];
  bool growth_tuned = false;
  // Predictor 6's first streams choose its weights and deadline by size: from predictor 4's
  // weights, both stepped by 2 while the stream shrinks, upwards first (the probe's proxy,
  // summed residual bit lengths, pulls too little in growth order: measured there it gives
  // 3/3 on the 1M-triangle scan, where 7/7 codes 1 % smaller); then the longer deadline, and
  // on small meshes (whose passes cost little) shorter ones too: with fewer triangles than
  // the deadline, the wait for two parallelograms can stall the growth.
  auto tune_growth = [&](Predictor p, auto& try_predictor) {
    growth_blend = blend;
    std::size_t size = try_predictor(p, growth_blend, nullptr, false, false, kLog2Deadlines[0]);
    for (const int dir : {2, -2}) {
      bool moved = false;
      for (int step = 0; step < 7; ++step) {
        const int one = growth_blend.one + dir, many = growth_blend.many + dir;
        if (one < 0 || many < 0 || one > 15 || many > 15) break;
        const Blend w{static_cast<std::uint8_t>(one), static_cast<std::uint8_t>(many)};
        const std::size_t s = try_predictor(p, w, nullptr, false, false, kLog2Deadlines[0]);
        if (s >= size) break;
        size = s, growth_blend = w, moved = true;
      }
      if (moved) break;
    }
    std::vector<unsigned> more(kLog2Deadlines + 1, std::end(kLog2Deadlines));
    if (nv < (std::size_t{1} << 15)) more.insert(more.end(), {10, 8, 6});
    for (unsigned d : more) {
      const std::size_t s = try_predictor(p, growth_blend, nullptr, false, false, d);
      if (s < size) size = s, log2_deadline = d;
    }
  };
  Candidate k;  // scratch: after consider() it holds a losing (or the old best's) buffers
  RansEncoder re;
  // Up to six symbols per vertex; reserving once spares the doubling copies per candidate.
  re.reserve(6 * nv);
  int slot = 0;
  Predictor right_best = Predictor::kDelta;  // the predictor of the smallest right-first stream
  std::size_t right_best_size = std::numeric_limits<std::size_t>::max();
  bool right_best_anchored = false;  // with predictor 5: how its isolated vertices were coded
  for (Traversal trav : {Traversal::kRightFirst, Traversal::kLeftFirst}) {
    std::vector<Predictor> preds;
    for (auto [t, p] : configurations(in.options.level))
      if (t == trav && (trav == Traversal::kRightFirst || in.options.level >= 9 || p == right_best))
        preds.push_back(p);
    if (preds.empty()) continue;
    Traversed& c = traversals[slot++];
    traverse(in, q_in, isolated, trav, c);
    // The predictors on the traversal's own order share one coding pass; each stream is
    // still considered in level order below, so ties resolve as before.
    std::vector<Predictor> in_order;
    for (Predictor p : preds)
      if (!by_degree(p) && !growth(p)) in_order.push_back(p);
    std::vector<RansEncoder> each_rans(in_order.size());
    std::vector<BitWriter> each_raw(in_order.size());
    for (RansEncoder& r : each_rans) r.reserve(6 * nv);
    if (!in_order.empty())
      encode_positions_each(c.table, c.q, in.quant.bits, in_order, each_rans, each_raw);
    DegreePlan plan;  // the measuring degree pass's traversal, replayed with the weights
    // Codes the positions with predictor p on this traversal (replaying with `again`);
    // returns the stream's size.
    auto try_predictor = [&](Predictor p, Blend weights, Blend* suggest, bool again = false,
                             bool anchored = false, unsigned log2_deadline = 0) {
      k.base = &c;
      k.predictor = p;
      k.blend = weights;
      k.anchored = anchored;
      k.log2_deadline = growth(p) ? log2_deadline : 0;
      re.clear();
      BitWriter bw;
      k.renumbered = by_degree(p);
      k.reordered = false;
      if (growth(p)) {
        // The table keeps its numbering; anchored isolated vertices are coded in anchor order.
        const std::vector<std::uint32_t> seq = encode_positions_growth(
            c.table, c.q, in.quant.bits, re, bw, p, weights, anchored, log2_deadline);
        if (!seq.empty()) {
          k.reordered = true;
          k.own_vertex_order.resize(seq.size());
          for (std::size_t i = 0; i < seq.size(); ++i)
            k.own_vertex_order[i] = c.vertex_order[seq[i]];
        }
        k.geometry.rans.clear();
        if (nv > 0) k.geometry.rans = re.finish();
        k.geometry.raw = bw.finish();
      } else if (!k.renumbered) {
        const std::size_t j = static_cast<std::size_t>(
            std::find(in_order.begin(), in_order.end(), p) - in_order.begin());
        k.geometry.rans.clear();
        if (nv > 0) k.geometry.rans = each_rans[j].finish();
        k.geometry.raw = each_raw[j].finish();
      } else {
        // One fused pass renumbers the table and codes (c.q is in the table's numbering).
        k.own_table = c.table;
        k.own_vertex_order = c.vertex_order;
        const std::vector<std::uint32_t> seq =
            again ? encode_positions_degree_again(k.own_table, plan, in.quant.bits, re, bw, p, weights)
                  : encode_positions_degree(k.own_table, c.q, in.quant.bits, re, bw, p, weights,
                                            suggest, anchored, suggest ? &plan : nullptr);
        for (std::size_t i = 0; i < seq.size(); ++i) k.own_vertex_order[i] = c.vertex_order[seq[i]];
        k.geometry.rans.clear();
        if (nv > 0) k.geometry.rans = re.finish();
        k.geometry.raw = bw.finish();
      }
      const std::size_t size = consider(in, k, best);
      if (trav == Traversal::kRightFirst && size < right_best_size)
        right_best_size = size, right_best = p, right_best_anchored = anchored;
      return size;
    };
    for (Predictor p : preds) {
      const Blend& weights = growth(p) ? growth_blend : blend;
      if (selecting(p)) {
        // The second traversal tries it only where it won the first (it costs a slower pass),
        // and only with the isolated vertices' code that won there.
        if (trav == Traversal::kLeftFirst) {
          if (right_best == p)
            try_predictor(p, weights, nullptr, false, right_best_anchored, log2_deadline);
          continue;
        }
        // The weights (and deadline) measured for the blend, which runs first.
        try_predictor(p, weights, nullptr, false, false, log2_deadline);
        // Isolated scan points near the surface: from their nearest vertex, not a chain.
        if (!isolated.empty() && c.table.n_vertices > 0)
          try_predictor(p, weights, nullptr, false, true, log2_deadline);
      } else if (!blended(p)) {
        try_predictor(p, {}, nullptr);
      } else if (p == Predictor::kMultiParallelogramBlend && !blend_measured) {
        // The first degree pass measures whether pulling predictions towards the parallelograms'
        // edge centroid would shorten the residuals (irregular, curved scans); if so, try it.
        try_predictor(p, {}, &blend);
        blend_measured = true;
        if (blend.any()) try_predictor(p, blend, nullptr, true);
      } else if (p == Predictor::kGrowthBlend && !growth_tuned) {
        growth_tuned = true;
        tune_growth(p, try_predictor);
      } else {
        try_predictor(p, weights, nullptr, false, false, log2_deadline);  // they suit the mesh
      }
    }
  }
}
}  // namespace

CompressResult codec::detail::compress_on_grid(const SurfaceMesh& mesh,
                                               const CompressOptions& options,
                                               const FlatMesh& flat, const Quantiser& quant) {
  const std::size_t nv = flat.positions.size();
  const Attributes attributes = gather_attributes(mesh, options);
  std::vector<QPoint> q_in(nv);
  for (std::size_t i = 0; i < nv; ++i) q_in[i] = quant.quantise(flat.positions[i]);
  const std::vector<std::uint32_t> isolated = isolated_order(flat.table, q_in);

  const EncodeInput in{mesh, options, flat, quant, attributes};
  std::array<Traversed, 2> traversals;
  Best best;
  search(in, q_in, isolated, traversals, best);
  CompressResult result = std::move(best.result);
  if (options.preserve_order) {
    result.vertex_permutation.resize(nv);
    result.face_permutation.resize(flat.n_faces);
    for (std::uint32_t i = 0; i < nv; ++i) result.vertex_permutation[i] = i;
    for (std::uint32_t i = 0; i < flat.n_faces; ++i) result.face_permutation[i] = i;
  } else {
    if (best.face_order.empty())
      best.face_order = face_order(in, best.candidate, reassemble(best.candidate.table(), 0));
    result.vertex_permutation = best.candidate.vertex_order();
    result.face_permutation = std::move(best.face_order);
  }
  return result;
}

CompressResult compress(const SurfaceMesh& mesh, const CompressOptions& options) {
  if (options.level < 0 || options.level > 9)
    throw InvalidArgument("compression level must be in [0, 9], got " + std::to_string(options.level));
  if (options.chunk_triangles != 0 && options.chunk_triangles < kMinChunkTriangles)
    throw InvalidArgument("compress: chunk_triangles must be 0 (one stream) or at least " +
                          std::to_string(kMinChunkTriangles) + ", got " +
                          std::to_string(options.chunk_triangles));
  if (!options.vertex_origin.empty() && options.vertex_origin.size() != mesh.n_vertices())
    throw InvalidArgument("compress: vertex_origin has " + std::to_string(options.vertex_origin.size()) +
                          " entries for " + std::to_string(mesh.n_vertices()) + " vertices");
  check_loose_faces(options, mesh.n_vertices(), mesh.n_faces());
  const FlatMesh flat = flatten(mesh);
  // An origin list that joins nothing is dropped here, so that no candidate groups it again
  // (and the mesh may still be chunked).
  std::optional<CompressOptions> unsplit;
  if (!options.vertex_origin.empty() && !has_split_vertices(options.vertex_origin, flat.positions)) {
    unsplit = options;
    unsplit->vertex_origin.clear();
  }
  const CompressOptions& opt = unsplit ? *unsplit : options;
  const Quantiser quant = options.precision > 0
                              ? quantiser_for_precision(flat.positions, options.precision)
                              : (options.precision < 0 || std::isnan(options.precision)
                                     ? throw InvalidArgument("precision must be positive (or 0 to use bits)")
                                     : quantiser_for_bits(flat.positions, options.bits));
  if (auto chunked = compress_chunked(mesh, opt, flat, quant)) return std::move(*chunked);
  return compress_on_grid(mesh, opt, flat, quant);
}

}  // namespace geom
