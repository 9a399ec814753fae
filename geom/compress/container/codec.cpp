// decompress() and decompress_flat(), the stream reader: every read is checked and errors name
// the byte offset. The writer, compress(), is encode.cpp; FORMAT.md specifies the stream.
#include <geom/compress/container/codec.h>

#include <geom/compress/attributes.h>
#include <geom/compress/container/chunks.h>
#include <geom/compress/container/core.h>
#include <geom/compress/container/extension.h>
#include <geom/compress/container/mesh_tables.h>
#include <geom/compress/container/stream.h>
#include <geom/compress/connectivity.h>
#include <geom/compress/predict.h>
#include <geom/compress/quantise.h>
#include <geom/compress/rans.h>
#include <geom/core/huge_pages.h>
#include <geom/core/soup.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <string>

namespace geom {

namespace {

using namespace codec;
using namespace codec::detail;

/// Every vertex codes three residual lengths, each costing at least −log2(1 − 32(n − 1)/2^15)
/// > (n − 1)/710 bits with n length symbols: at most 2048/(n − 1) vertices per byte.
std::uint64_t max_vertices_per_byte(const Header& h) {
  if (!blended(h.predictor)) return kMaxVerticesPerByte;
  return 2048 / (h.quantiser.bits + 1);  // n = bits + 2 length symbols
}

void read_attribute_header(ByteReader& r, Header& h) {
  if (h.flags & kFlagNormals) {
    h.normal_bits = r.u8();
    if (h.normal_bits < 2 || h.normal_bits > 20)
      throw DecodeError(r.offset() - 1, "normal bits outside 2–20");
  }
  if (h.flags & kFlagTexcoords) {
    Quantiser& u = h.uv_quantiser;
    u.bits = r.u8();
    if (u.bits < 1 || u.bits > 30) throw DecodeError(r.offset() - 1, "texture coordinate bits outside 1–30");
    u.origin = {r.f64(), r.f64(), 0.0};
    u.step = r.f64();
    const double top = static_cast<double>((std::uint64_t{1} << u.bits) - 1);
    if (!u.origin.allFinite() || !std::isfinite(u.step) || !(u.step > 0) ||
        !(u.origin.array() + u.step * top).allFinite())
      throw DecodeError(r.offset() - 8, "texture coordinate grid not finite and positive");
  }
}


}  // namespace

namespace {
/// Empties a Core for the next stream, keeping its arrays' capacity.
void recycle(Core& core) {
  core.h = {};
  CornerTable& t = core.table;
  t.n_vertices = 0;
  t.vertex.clear();
  t.opposite.clear();
  t.diagonal.clear();
  t.corners_of.clear();
  core.q.clear();
  core.normals.clear();
  core.uvs.clear();
  core.order_rans = core.order_raw = {};
  core.order_offset = core.connectivity_offset = 0;
  core.extension_at = 0;
  core.open_corners.clear();
  core.open_corners_known = false;
}
}  // namespace

Core codec::detail::decode_core(std::span<const std::uint8_t> bytes, bool open_corners) {
  Core core;
  Scratch scratch;
  decode_core_into(bytes, core, scratch, open_corners);
  return core;
}

void codec::detail::decode_core_into(std::span<const std::uint8_t> bytes, Core& core,
                                     Scratch& scratch, bool open_corners) {
  recycle(core);
  ByteReader r(bytes);
  Header& h = core.h;
  for (std::uint8_t m : kMagic)
    if (r.u8() != m) throw DecodeError(r.offset() - 1, "not a geom compressed mesh (bad magic)");
  const std::uint8_t version = r.u8();
  if (version != kVersion && version != kVersionAttributes)
    throw DecodeError(r.offset() - 1, "unsupported stream version " + std::to_string(version) +
                                          " (this decoder reads versions 1, 2 and 3)");
  h.flags = r.u8();
  if (h.flags & ~(version == kVersion ? kKnownFlagsV1 : kKnownFlags))
    throw DecodeError(r.offset() - 1, "unknown flags for version " + std::to_string(version));
  const std::uint8_t pred = r.u8();
  if (pred > 7) throw DecodeError(r.offset() - 1, "unknown predictor " + std::to_string(pred));
  h.predictor = static_cast<Predictor>(pred);
  h.quantiser.bits = r.u8();
  if (h.quantiser.bits < 1 || h.quantiser.bits > 30)
    throw DecodeError(r.offset() - 1, "quantisation bits outside 1–30");
  for (int a = 0; a < 3; ++a) h.quantiser.origin[a] = r.f64();
  h.quantiser.step = r.f64();
  if (!h.quantiser.origin.allFinite() || !std::isfinite(h.quantiser.step) ||
      !(h.quantiser.step > 0))
    throw DecodeError(r.offset() - 8, "grid origin or step not finite and positive");
  const double top = static_cast<double>((std::uint64_t{1} << h.quantiser.bits) - 1);
  if (!(h.quantiser.origin.array() + h.quantiser.step * top).allFinite())
    throw DecodeError(r.offset() - 8, "grid extends beyond the double range");
  read_attribute_header(r, h);
  if (blended(h.predictor)) h.blend = Blend::from_byte(r.u8());
  if (selecting(h.predictor)) {
    const std::uint8_t isolated = r.u8();
    if (isolated > 1)
      throw DecodeError(r.offset() - 1, "unknown isolated vertex mode " + std::to_string(isolated));
    h.anchored = isolated == 1;
  }
  if (growth(h.predictor)) {
    h.log2_deadline = r.u8();
    if (h.log2_deadline > kMaxLog2Deadline)
      throw DecodeError(r.offset() - 1, "growth-order deadline 2^" +
                                            std::to_string(h.log2_deadline) + " beyond 2^" +
                                            std::to_string(kMaxLog2Deadline));
  }
  const std::size_t counts_at = r.offset();
  h.n_faces = r.varint();
  h.n_triangles = r.varint();
  h.n_vertices = r.varint();
  h.n_isolated = r.varint();
  const std::uint64_t conn_at = r.offset();
  const auto conn_rans = r.take(r.varint());
  const auto conn_raw = r.take(r.varint());
  const std::uint64_t geom_at = r.offset();
  const auto geom_rans = r.take(r.varint());
  const auto geom_raw = r.take(r.varint());
  std::span<const std::uint8_t> attr[2][2];  // [normals, uvs][rans, raw]
  for (int a = 0; a < 2; ++a)
    if (h.flags & (a == 0 ? kFlagNormals : kFlagTexcoords))
      for (int k = 0; k < 2; ++k) attr[a][k] = r.take(r.varint());
  if (h.flags & kFlagPreserveOrder) {
    core.order_offset = r.offset();
    core.order_rans = r.take(r.varint());
    core.order_raw = r.take(r.varint());
  }
  if (h.flags & kFlagExtension) {
    core.extension_at = r.offset();
    r.take(r.remaining());  // decode_extension parses it once the table is known
  }
  if (r.remaining() != 0) throw DecodeError(r.offset(), "trailing bytes after the last section");
  if (h.n_triangles > kMaxTrianglesPerByte * conn_rans.size() + 16 || h.n_triangles > (1u << 30) ||
      h.n_faces > h.n_triangles || (h.n_faces == 0) != (h.n_triangles == 0) ||
      h.n_vertices > max_vertices_per_byte(h) * geom_rans.size() + 64 || h.n_vertices > (1u << 30) ||
      h.n_isolated > h.n_vertices ||
      (!(h.flags & kFlagPolygons) && h.n_faces != h.n_triangles))
    throw DecodeError(counts_at, "element counts impossible for the section sizes");

  // Section payloads start after their varint length; offsets here are approximate to within
  // that varint, exact for the data bytes via the decoders' own base.
  const std::uint64_t conn_base = static_cast<std::uint64_t>(conn_rans.data() - bytes.data());
  const std::uint64_t conn_raw_base = static_cast<std::uint64_t>(conn_raw.data() - bytes.data());
  core.connectivity_offset = conn_at;
  // One block for the stages' scratch, sized for the largest at once: the position pass then
  // reuses the pages the connectivity step's gates touched (the counts are bounded above).
  const bool degree = by_degree(h.predictor);
  const auto n_tri = static_cast<std::size_t>(h.n_triangles);
  const bool grows = growth(h.predictor);
  scratch.reserve(std::max({connectivity_scratch_bytes(n_tri),
                            degree ? degree_scratch_bytes(3 * n_tri, h.n_vertices) : 0,
                            grows ? growth_scratch_bytes(3 * n_tri, h.n_vertices) : 0}));
  // The table and the positions are reserved here, before the stages allocate their own
  // arrays (their reserve calls then find the room): in a process that decodes mesh after
  // mesh, the allocator then hands the same blocks back each time instead of fresh pages the
  // kernel must clear (about 7 % of a repeated decode of the 1M-triangle bench mesh), and a
  // FlatDecoder's core already has the room.
  geom::detail::reserve_huge(core.table.vertex, 3 * n_tri);
  geom::detail::reserve_huge(core.table.opposite, 3 * n_tri);
  geom::detail::reserve_huge(core.q, static_cast<std::size_t>(h.n_vertices));
  {
    const bool polygons = h.flags & kFlagPolygons;
    const Traversal trav = (h.flags & kFlagLeftFirst) ? Traversal::kLeftFirst : Traversal::kRightFirst;
    if (h.n_triangles > 0) {
      RansDecoder rd(conn_rans, conn_base, rans_lanes(h.flags));
      BitReader br(conn_raw, conn_raw_base);
      decode_connectivity(n_tri, polygons, trav, rd, br, core.table, &scratch,
                          {static_cast<std::size_t>(h.n_vertices - h.n_isolated), degree});
      rd.finish();
    } else if (!conn_rans.empty() || !conn_raw.empty()) {
      throw DecodeError(conn_at, "connectivity data for an empty mesh");
    }
  }
  if (core.table.n_vertices + h.n_isolated != h.n_vertices)
    throw DecodeError(counts_at, "vertex count disagrees with the connectivity");
  if (h.n_vertices > 0) {
    RansDecoder rd(geom_rans, static_cast<std::uint64_t>(geom_rans.data() - bytes.data()),
                   rans_lanes(h.flags));
    BitReader br(geom_raw, static_cast<std::uint64_t>(geom_raw.data() - bytes.data()));
    if (grows) {
      decode_positions_growth(core.table, static_cast<std::size_t>(h.n_vertices), h.quantiser.bits,
                              rd, br, core.q, h.predictor, h.blend, h.anchored, h.log2_deadline,
                              &scratch);
    } else if (degree) {
      decode_positions_degree(core.table, static_cast<std::size_t>(h.n_vertices), h.quantiser.bits,
                              rd, br, core.q, h.predictor, h.blend, h.anchored, &scratch,
                              open_corners ? &core.open_corners : nullptr);
      core.open_corners_known = open_corners;
    } else {
      decode_positions(core.table, static_cast<std::size_t>(h.n_vertices), h.quantiser.bits,
                       h.predictor, rd, br, core.q);
    }
    rd.finish();
  } else if (!geom_rans.empty() || !geom_raw.empty()) {
    throw DecodeError(geom_at, "geometry data for an empty mesh");
  }
  auto base = [&](std::span<const std::uint8_t> s) {
    return static_cast<std::uint64_t>(s.data() - bytes.data());
  };
  const auto nv = static_cast<std::size_t>(h.n_vertices);
  if (h.flags & kFlagNormals)
    decode_attribute(core.table, nv, h.normal_bits, attr[0][0], base(attr[0][0]), attr[0][1],
                     base(attr[0][1]), core.normals, rans_lanes(h.flags));
  if (h.flags & kFlagTexcoords)
    decode_attribute(core.table, nv, h.uv_quantiser.bits, attr[1][0], base(attr[1][0]),
                     attr[1][1], base(attr[1][1]), core.uvs, rans_lanes(h.flags));
}

namespace {

void check_permutation(const std::vector<std::uint32_t>& p, std::uint64_t where, const char* what) {
  std::vector<std::uint8_t> seen(p.size(), 0);
  for (std::uint32_t i : p) {
    if (i >= p.size() || seen[i])
      throw DecodeError(where, std::string(what) + " order is not a permutation");
    seen[i] = 1;
  }
}

}  // namespace

DecompressResult decompress(std::span<const std::uint8_t> bytes) {
  Core core = is_chunked(bytes) ? decode_chunked(bytes) : decode_core(bytes);
  const Header& h = core.h;
  const std::size_t nv = static_cast<std::size_t>(h.n_vertices);
  const Polygons polys = reassemble(core.table, core.connectivity_offset);
  if (polys.size() != h.n_faces)
    throw DecodeError(core.connectivity_offset, "face count disagrees with the polygon flags");
  const std::size_t nf = polys.size();

  DecompressResult result;
  result.max_error = h.quantiser.max_error();
  std::vector<std::uint32_t> vertex_slot(nv), face_slot(nf), rotation(nf, 0);
  for (std::uint32_t i = 0; i < nv; ++i) vertex_slot[i] = i;
  for (std::uint32_t j = 0; j < nf; ++j) face_slot[j] = j;
  if (h.flags & kFlagPreserveOrder) {
    const std::uint64_t base = static_cast<std::uint64_t>(core.order_rans.data() - bytes.data());
    if (nv + nf == 0) {
      if (!core.order_rans.empty() || !core.order_raw.empty())
        throw DecodeError(core.order_offset, "order data for an empty mesh");
    } else {
      RansDecoder rd(core.order_rans, base, rans_lanes(h.flags));
      BitReader br(core.order_raw, static_cast<std::uint64_t>(core.order_raw.data() - bytes.data()));
      GammaModel vm, fm, rm;
      std::int64_t prev = 0;
      for (std::uint32_t i = 0; i < nv; ++i) {
        prev += unzigzag(vm.decode(rd, br));
        if (prev < 0 || prev >= static_cast<std::int64_t>(nv))
          throw DecodeError(rd.offset(), "vertex order index out of range");
        vertex_slot[i] = static_cast<std::uint32_t>(prev);
      }
      prev = 0;
      for (std::uint32_t j = 0; j < nf; ++j) {
        prev += unzigzag(fm.decode(rd, br));
        if (prev < 0 || prev >= static_cast<std::int64_t>(nf))
          throw DecodeError(rd.offset(), "face order index out of range");
        face_slot[j] = static_cast<std::uint32_t>(prev);
        rotation[j] = rm.decode(rd, br);
        if (rotation[j] >= polys.offset[j + 1] - polys.offset[j])
          throw DecodeError(rd.offset(), "face rotation exceeds the face size");
      }
      rd.finish();
    }
    check_permutation(vertex_slot, core.order_offset, "vertex");
    check_permutation(face_slot, core.order_offset, "face");
    result.order_preserved = true;
    result.vertex_permutation.resize(nv);
    result.face_permutation.resize(nf);
    for (std::uint32_t i = 0; i < nv; ++i) result.vertex_permutation[i] = i;
    for (std::uint32_t j = 0; j < nf; ++j) result.face_permutation[j] = j;
  }

  // The block is read before the faces are built: its rotations give their first corners.
  ExtensionDecoding ext;
  if (h.flags & kFlagExtension) {
    ext = decode_extension(bytes, core.extension_at, core.table, core.q, h.flags & kFlagNormals,
                           h.flags & kFlagTexcoords, rans_lanes(h.flags), nf,
                           h.flags & kFlagPreserveOrder);
    if (ext.rotation.min_degree != 0)
      rotation = decode_rotation(ext.rotation, core.table, polys, rans_lanes(h.flags));
    result.loose_faces = std::move(ext.loose.faces);
    for (auto& f : result.loose_faces)
      for (std::uint32_t& v : f) v = vertex_slot[v];
    result.loose_face_positions = std::move(ext.loose.positions);
  }

  SurfaceMesh& mesh = result.mesh;
  mesh.reserve(nv, polys.vertex.size() / 2 + nf + 3, nf);
  // vertex_slot is a permutation (checked above), so every vertex is written once, and in
  // place: a copy and nv add_vertex calls took 24 ms of a 340 ms decode (557k vertices).
  mesh.resize(nv, 0, 0);
  auto points = mesh.positions();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nv, 16384),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i < r.end(); ++i)
                        points[Vertex(vertex_slot[i])] = h.quantiser.dequantise(core.q[i]);
                    });
  if (h.flags & kFlagNormals) {
    auto p = mesh.add_property<Vertex, Normal>(prop::kVertexNormal);
    for (std::size_t i = 0; i < nv; ++i)
      p[Vertex(vertex_slot[i])] = octahedral_dequantise(core.normals[i], h.normal_bits);
  }
  if (h.flags & kFlagTexcoords) {
    auto p = mesh.add_property<Vertex, TexCoord>(prop::kVertexTexCoord);
    for (std::size_t i = 0; i < nv; ++i)
      p[Vertex(vertex_slot[i])] = h.uv_quantiser.dequantise(core.uvs[i]).head<2>();
    result.texcoord_max_error = h.uv_quantiser.max_error();
  }
  std::vector<std::uint32_t> face_of_slot(nf);
  for (std::uint32_t j = 0; j < nf; ++j) face_of_slot[face_slot[j]] = j;
  if (!(h.flags & kFlagPolygons)) {
    link_decoded_triangles(mesh, core.table, face_of_slot, rotation, vertex_slot,
                           core.connectivity_offset);
  } else {
    std::vector<Vertex> corners;
    for (std::uint32_t s = 0; s < nf; ++s) {
      const std::uint32_t j = face_of_slot[s];
      const std::uint32_t b = polys.offset[j], k = polys.offset[j + 1] - b;
      corners.clear();
      for (std::uint32_t i = 0; i < k; ++i)
        corners.push_back(Vertex(vertex_slot[polys.vertex[b + (i + rotation[j]) % k]]));
      try {
        mesh.add_face(corners);
      } catch (const TopologyError& e) {
        throw DecodeError(core.connectivity_offset,
                          std::string("decoded faces do not form a valid mesh: ") + e.what());
      }
    }
  }
  if (h.flags & kFlagExtension)
    apply_extension(ext, mesh, core.table, vertex_slot, face_slot, result.attributes,
                    result.vertex_representative);
  return result;
}

namespace codec {
FlatDecoder::FlatDecoder() : ws_(std::make_unique<detail::Workspace>()) {}
FlatDecoder::~FlatDecoder() = default;
FlatDecoder::FlatDecoder(FlatDecoder&&) noexcept = default;
FlatDecoder& FlatDecoder::operator=(FlatDecoder&&) noexcept = default;

namespace {
/// A non-manifold source's split copies (FORMAT.md, extension kind 3) joined into their
/// representatives, as `geom decompress` writes them: a copy's per-vertex values leave the
/// arrays and its corners take its representative's number, so the arrays hold the source's
/// vertices. Copies ascend and each representative lies below its copy and is not one
/// (decode_extension checked), so it is renumbered before its copies are met.
void join_split(std::span<const std::array<std::uint32_t, 2>> split, FlatDecode& out) {
  const std::size_t n = out.positions.size() / 3;
  std::vector<std::uint32_t> to(n);
  std::size_t next_copy = 0;
  std::uint32_t kept = 0;
  auto move_down = [](auto& values, std::size_t dims, std::size_t from, std::size_t at) {
    if (values.empty()) return;
    for (std::size_t x = 0; x < dims; ++x) values[dims * at + x] = values[dims * from + x];
  };
  for (std::uint32_t v = 0; v < n; ++v) {
    if (next_copy < split.size() && split[next_copy][0] == v) {
      to[v] = to[split[next_copy++][1]];
      continue;
    }
    move_down(out.positions, 3, v, kept);
    move_down(out.normals, 3, v, kept);
    move_down(out.texcoords, 2, v, kept);
    to[v] = kept++;
  }
  out.positions.resize(3 * std::size_t{kept});
  if (!out.normals.empty()) out.normals.resize(3 * std::size_t{kept});
  if (!out.texcoords.empty()) out.texcoords.resize(2 * std::size_t{kept});
  for (std::uint32_t& v : out.triangles) v = to[v];
}

/// The per-corner normals and texture coordinates, corner by corner as the triangles list
/// them (the table's corners: FlatDecode::triangles is the table); a corner attribute equal
/// to the vertex one (mode 1) takes its vertex's value.
void corner_values(const ExtensionDecoding& ext, FlatDecode& out) {
  out.corner_normals.clear();
  out.corner_texcoords.clear();
  for (const DecodedCornerAttribute& a : ext.corners) {
    const std::size_t dims = a.normal ? 3 : 2;
    std::vector<float>& to = a.normal ? out.corner_normals : out.corner_texcoords;
    const std::vector<float>& per_vertex = a.normal ? out.normals : out.texcoords;
    to.resize(dims * out.triangles.size());
    for (std::size_t c = 0; c < out.triangles.size(); ++c) {
      float* v = to.data() + dims * c;
      if (a.from_vertex) {
        std::copy_n(per_vertex.data() + dims * out.triangles[c], dims, v);
      } else if (a.normal) {
        const Normal n = octahedral_dequantise({a.values[c][0], a.values[c][1], 0}, a.bits);
        v[0] = float(n.x()), v[1] = float(n.y()), v[2] = float(n.z());
      } else {
        v[0] = float(a.origin[0] + a.step * a.values[c][0]);
        v[1] = float(a.origin[1] + a.step * a.values[c][1]);
      }
    }
  }
}

void decode_flat(std::span<const std::uint8_t> bytes, detail::Workspace& ws, FlatDecode& out) {
  if (detail::is_chunked(bytes)) return detail::decode_chunked_flat(bytes, ws, out);
  if (ws.cores.empty()) ws.cores.resize(1);
  Core& core = ws.cores[0];
  decode_core_into(bytes, core, ws.scratch.local());
  if (ws.one_shot) ws.scratch.clear();
  // The block is decoded whole, so that a corrupt one is an error here too, though its
  // generic attributes do not reach the arrays.
  ExtensionDecoding ext;
  if (core.h.flags & kFlagExtension)
    ext = decode_extension(bytes, core.extension_at, core.table, core.q,
                           core.h.flags & kFlagNormals, core.h.flags & kFlagTexcoords,
                           rans_lanes(core.h.flags), static_cast<std::size_t>(core.h.n_faces),
                           core.h.flags & kFlagPreserveOrder);
  out.positions.clear();  // (so that growing copies nothing)
  out.positions.resize(3 * core.q.size());
  for (std::size_t i = 0; i < core.q.size(); ++i)
    core.h.quantiser.dequantise_into(core.q[i], out.positions.data() + 3 * i);
  // The table is the triangles: swapped, so that the table keeps out's old capacity.
  std::swap(out.triangles, core.table.vertex);
  out.normals.clear();
  out.normals.reserve(3 * core.normals.size());
  for (const QPoint& q : core.normals) {
    const Normal n = octahedral_dequantise(q, core.h.normal_bits);
    out.normals.insert(out.normals.end(), {float(n.x()), float(n.y()), float(n.z())});
  }
  out.texcoords.clear();
  out.texcoords.reserve(2 * core.uvs.size());
  for (const QPoint& q : core.uvs) {
    const Point t = core.h.uv_quantiser.dequantise(q);
    out.texcoords.insert(out.texcoords.end(), {float(t.x()), float(t.y())});
  }
  if (!ext.split.empty()) join_split(ext.split, out);
  corner_values(ext, out);
}
}  // namespace

void FlatDecoder::decode(std::span<const std::uint8_t> bytes, FlatDecode& out) {
  decode_flat(bytes, *ws_, out);
}

FlatDecode decompress_flat(std::span<const std::uint8_t> bytes) {
  detail::Workspace ws;
  ws.one_shot = true;
  FlatDecode out;
  decode_flat(bytes, ws, out);
  return out;
}
}  // namespace codec

std::size_t max_compressed_size(std::size_t n_vertices, std::size_t n_faces, std::size_t n_corners,
                                std::size_t n_attributes, std::size_t n_corner_attributes,
                                std::size_t n_generic_components, std::size_t n_split_copies,
                                std::size_t n_loose_faces, std::size_t n_loose_corners) {
  const std::size_t n_tri = n_corners >= 2 * n_faces ? n_corners - 2 * n_faces : n_corners;
  // Every model symbol costs at most log2(2^15 / kMinFreq) = 10 bits (+ rounding; 11 used);
  // raw fields are at most 31 bits. Per triangle ≤ 12 symbols and 93 raw bits; per vertex
  // 7 symbols (predictor 5's subset mask or an isolated vertex's anchor gap, and 6 for the
  // residuals) and 87 raw bits, 118 with a gap's; order: 1 symbol + 31 bits per vertex,
  // 2 + 62 per face.
  const std::size_t conn = (n_tri * (12 * 11 + 93) + 7) / 8 + 16;
  const std::size_t geom = (n_vertices * (7 * 11 + 118) + 7) / 8 + 16;
  const std::size_t order = (n_vertices * (11 + 31) + n_faces * (2 * 11 + 62) + 7) / 8 + 16;
  // An attribute codes like the positions (fewer bits, same bound) plus ≤ 26 header bytes
  // and two section lengths.
  // A chunked stream (version 3) codes each vertex once per chunk that has it (at most once
  // per triangle corner in all), with a merge map entry (three gamma values) for every copy
  // after the first, and a stream header per chunk.
  std::size_t chunked = 0;
  if (n_tri >= 2 * kMinChunkTriangles) {
    const std::size_t chunks = n_tri / kMinChunkTriangles, copies = 3 * n_tri;
    chunked = 32 + chunks * (128 + 6 * 10 + 16) + (copies * (7 * 11 + 118 + 3 * (11 + 31)) + 7) / 8;
  }
  return 128 + conn + geom + order + 6 * 10 + n_attributes * (geom + 26 + 2 * 10) + chunked +
         max_extension_size(n_vertices, 3 * n_tri, n_corner_attributes, n_generic_components,
                            n_split_copies, n_faces, n_loose_faces, n_loose_corners);
}

}  // namespace geom
