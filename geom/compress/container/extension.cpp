#include <geom/compress/container/extension.h>

#include <geom/compress/attributes.h>
#include <geom/compress/container/face_entries.h>
#include <geom/compress/container/stream.h>
#include <geom/compress/corner_attributes.h>
#include <geom/compress/predict.h>
#include <geom/core/soup.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <typeinfo>
#include <unordered_map>

namespace geom::codec::detail {

namespace {

enum Kind : std::uint8_t { kCornerTexcoord = 0, kCornerNormal = 1, kGeneric = 2, kSplit = 3 };
constexpr std::uint64_t kMaxVerticesPerByte = 64;  // as the core stream (FORMAT.md)

// Generic vertex property types by their stream code (the index here).
using GenericTypes = std::tuple<double, float, Eigen::Vector2d, Eigen::Vector3d, Eigen::Vector4d,
                                Eigen::Vector2f, Eigen::Vector3f, Eigen::Vector4f>;
constexpr std::uint8_t kTypeCount = std::tuple_size_v<GenericTypes>;

template <class T>
constexpr unsigned dims_of() {
  if constexpr (std::is_arithmetic_v<T>)
    return 1;
  else
    return static_cast<unsigned>(T::RowsAtCompileTime);
}

/// Call f with a value-initialised T for type code `type`.
template <std::size_t I = 0, class F>
void with_type(std::uint8_t type, F&& f) {
  if constexpr (I < kTypeCount) {
    if (type == I)
      f(std::tuple_element_t<I, GenericTypes>{});
    else
      with_type<I + 1>(type, std::forward<F>(f));
  }
}

/// The stream code of a vertex property's type, or kTypeCount when it has none.
std::uint8_t type_code(const SurfaceMesh& mesh, const std::string& name) {
  const std::type_info* t = mesh.props<Vertex>().type_of(name);
  std::uint8_t code = kTypeCount;
  for (std::uint8_t i = 0; i < kTypeCount; ++i)
    with_type(i, [&](auto tag) {
      if (t && *t == typeid(tag)) code = i;
    });
  return code;
}

std::string str(std::size_t x) { return std::to_string(x); }

/// Each flat (input) corner's halfedge: the one of its face that ends at its vertex.
std::vector<Halfedge> input_corner_halfedges(const SurfaceMesh& mesh, const FlatMesh& flat) {
  std::vector<std::uint32_t> dense(mesh.vertices_size(), kNone);
  std::uint32_t n = 0;
  for (Vertex v : mesh.vertices()) dense[v.idx()] = n++;
  std::vector<Face> faces;
  faces.reserve(mesh.n_faces());
  for (Face f : mesh.faces()) faces.push_back(f);
  std::vector<Halfedge> out(flat.table.vertex.size());
  for (std::size_t c = 0; c < out.size(); ++c)
    for (Halfedge h : mesh.halfedges(faces[flat.triangle_face[c / 3]]))
      if (dense[mesh.to_vertex(h).idx()] == flat.table.vertex[c]) out[c] = h;
  return out;
}

template <class T>
void check_corner_values(const Property<Halfedge, const T>& p, std::span<const Halfedge> hs,
                         const std::string& name) {
  for (Halfedge h : hs)
    if (!p[h].allFinite())
      throw InvalidArgument("compress: property '" + name + "' of halfedge " + str(h.idx()) +
                            " is not finite");
}

/// One per-corner attribute entry. Returns false when it is not coded.
template <class T>
bool encode_corner(ByteWriter& w, const SurfaceMesh& mesh, bool normal, unsigned bits,
                   bool vertex_coded, std::span<const Halfedge> decoded_he,
                   const CornerTable& decoded, AttributeStats& stats) {
  const std::string name = normal ? prop::kCornerNormal : prop::kCornerTexCoord;
  const auto p = mesh.get_property<Halfedge, T>(name);
  if (!p || bits == 0) return false;
  check_corner_values(p, decoded_he, name);
  w.u8(normal ? kCornerNormal : kCornerTexcoord);
  stats.name = name;
  if (vertex_coded) {
    const auto pv =
        mesh.get_property<Vertex, T>(normal ? prop::kVertexNormal : prop::kVertexTexCoord);
    bool same = true;
    for (Halfedge h : decoded_he) same = same && p[h] == pv[mesh.to_vertex(h)];
    if (same) {
      w.u8(1);  // the vertex attribute, corner by corner: nothing more to send
      return true;
    }
  }
  w.u8(0);
  std::vector<Grid2> q(decoded_he.size());
  if constexpr (std::is_same_v<T, Normal>) {
    w.u8(static_cast<std::uint8_t>(bits));
    for (std::size_t c = 0; c < q.size(); ++c) {
      const QPoint g = octahedral_quantise(p[decoded_he[c]], bits, 0);
      q[c] = {g[0], g[1]};
    }
    stats.max_error = 4.5 / std::ldexp(1.0, static_cast<int>(bits));
  } else {
    std::vector<TexCoord> uv(q.size());
    for (std::size_t c = 0; c < q.size(); ++c) uv[c] = p[decoded_he[c]];
    const Quantiser grid = texcoord_quantiser(uv, bits);
    w.u8(static_cast<std::uint8_t>(bits));
    w.f64(grid.origin.x());
    w.f64(grid.origin.y());
    w.f64(grid.step);
    for (std::size_t c = 0; c < q.size(); ++c) {
      const QPoint g = grid.quantise(Point(uv[c].x(), uv[c].y(), 0.0));
      q[c] = {g[0], g[1]};
    }
    stats.max_error = grid.max_error();
  }
  RansEncoder re;
  BitWriter bw;
  std::vector<std::uint8_t> rans;
  if (!q.empty()) {
    encode_corner_values(decoded, q, bits, re, bw);
    rans = re.finish();
  }
  write_section(w, rans);
  write_section(w, bw.finish());
  return true;
}

/// A generic vertex property on a grid per component, through the position coder in planes
/// of three components.
template <class T>
void encode_generic(ByteWriter& w, const SurfaceMesh& mesh, const std::string& name,
                    std::uint8_t type, unsigned bits, const CornerTable& decoded,
                    std::span<const std::uint32_t> vertex_order, std::span<const Vertex> live,
                    AttributeStats& stats) {
  constexpr unsigned dims = dims_of<T>();
  const auto p = mesh.get_property<Vertex, T>(name);
  const std::size_t nv = vertex_order.size();
  std::vector<double> x(nv * dims);
  for (std::size_t i = 0; i < nv; ++i) {
    const T& v = p[live[vertex_order[i]]];
    for (unsigned k = 0; k < dims; ++k) {
      double c;
      if constexpr (dims == 1)
        c = static_cast<double>(v);
      else
        c = static_cast<double>(v[k]);
      if (!std::isfinite(c))
        throw InvalidArgument("compress: property '" + name + "' of vertex " +
                              str(live[vertex_order[i]].idx()) + " is not finite");
      x[i * dims + k] = c;
    }
  }
  w.u8(kGeneric);
  w.u8(static_cast<std::uint8_t>(name.size()));
  w.append(std::span(reinterpret_cast<const std::uint8_t*>(name.data()), name.size()));
  w.u8(type);
  w.u8(static_cast<std::uint8_t>(bits));
  const double top = static_cast<double>((std::uint64_t{1} << bits) - 1);
  double origin[4] = {0, 0, 0, 0}, step[4] = {1, 1, 1, 1};
  stats.name = name;
  for (unsigned k = 0; k < dims; ++k) {
    double lo = nv ? x[k] : 0.0, hi = lo;
    for (std::size_t i = 0; i < nv; ++i)
      lo = std::min(lo, x[i * dims + k]), hi = std::max(hi, x[i * dims + k]);
    origin[k] = lo;
    if (hi > lo) step[k] = (hi - lo) / top;
    if (!std::isfinite(step[k]) || !(step[k] > 0))
      throw InvalidArgument("compress: property '" + name + "' spans a range too wide to quantise");
    if (hi > lo) stats.max_error = std::max(stats.max_error, 0.5 * step[k]);
    w.f64(origin[k]);
    w.f64(step[k]);
  }
  std::vector<QPoint> q(nv);
  for (unsigned plane = 0; plane * 3 < dims; ++plane) {
    for (std::size_t i = 0; i < nv; ++i)
      for (unsigned a = 0; a < 3; ++a) {
        const unsigned k = plane * 3 + a;
        q[i][a] = k < dims ? static_cast<std::uint32_t>(std::clamp(
                                 std::round((x[i * dims + k] - origin[k]) / step[k]), 0.0, top))
                           : 0;
      }
    RansEncoder re;
    BitWriter bw;
    std::vector<std::uint8_t> rans;
    if (nv > 0) {
      encode_positions(decoded, q, bits, Predictor::kMultiParallelogram, re, bw);
      rans = re.finish();
    }
    write_section(w, rans);
    write_section(w, bw.finish());
  }
}

/// repeat(i, j) for each i < n whose origin_of(i) an earlier index had, j the first of them.
template <class Origin, class Repeat>
void for_each_repeat(std::size_t n, Origin&& origin_of, Repeat&& repeat) {
  std::unordered_map<std::uint32_t, std::uint32_t> first;
  first.reserve(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const auto [at, fresh] = first.try_emplace(origin_of(i), i);
    if (!fresh) repeat(i, at->second);
  }
}

/// Each decoded vertex whose origin an earlier decoded vertex has, with that earlier one:
/// (copy, representative), copies ascending.
std::vector<std::array<std::uint32_t, 2>> split_copies(std::span<const std::uint32_t> origin,
                                                       std::span<const std::uint32_t> vertex_order) {
  std::vector<std::array<std::uint32_t, 2>> out;
  if (origin.empty()) return out;
  for_each_repeat(
      vertex_order.size(), [&](std::uint32_t d) { return origin[vertex_order[d]]; },
      [&](std::uint32_t d, std::uint32_t first) { out.push_back({d, first}); });
  return out;
}

/// The split vertices' entry: their count, then per copy its gap to the previous copy (the
/// first: its number) and its representative.
void encode_split(ByteWriter& w, std::span<const std::array<std::uint32_t, 2>> split) {
  w.u8(kSplit);
  w.varint(split.size());
  std::uint32_t next = 0;
  for (const auto& [copy, rep] : split) {
    w.varint(copy - next);
    w.varint(rep);
    next = copy + 1;
  }
}

template <class H>
void drop_all(const SurfaceMesh& mesh, std::vector<std::string>& dropped,
              const std::vector<std::string>& kept = {}) {
  for (const std::string& n : mesh.property_names<H>())
    if (std::find(kept.begin(), kept.end(), n) == kept.end()) dropped.push_back(n);
}

}  // namespace

ExtensionEncoding encode_extension(const SurfaceMesh& mesh, const CompressOptions& options,
                                   const FlatMesh& flat, const CornerTable& decoded,
                                   std::span<const std::uint32_t> corner_origin,
                                   std::span<const std::uint32_t> vertex_order, bool vertex_normals,
                                   bool vertex_uvs, const FaceCorners& corners) {
  if (options.attribute_bits > 30)
    throw InvalidArgument("compress: attribute bits must be in [0, 30], got " +
                          str(options.attribute_bits));
  ExtensionEncoding out;
  ByteWriter body;
  std::size_t entries = 0;
  auto entry = [&](auto&& code) {
    const std::size_t before = body.bytes().size();
    AttributeStats s;
    if (!code(s)) return false;
    s.bytes = body.bytes().size() - before;
    out.attributes.push_back(std::move(s));
    ++entries;
    return true;
  };

  // Per-corner attributes, on the decoded corners.
  std::vector<std::string> kept_h;
  if (mesh.has_property<Halfedge>(prop::kCornerTexCoord) ||
      mesh.has_property<Halfedge>(prop::kCornerNormal)) {
    const std::vector<Halfedge> input_he = input_corner_halfedges(mesh, flat);
    std::vector<Halfedge> he(corner_origin.size());
    for (std::size_t c = 0; c < he.size(); ++c) he[c] = input_he[corner_origin[c]];
    if (entry([&](AttributeStats& s) {
          return encode_corner<TexCoord>(body, mesh, false, options.texcoord_bits, vertex_uvs, he,
                                         decoded, s);
        }))
      kept_h.push_back(prop::kCornerTexCoord);
    if (entry([&](AttributeStats& s) {
          return encode_corner<Normal>(body, mesh, true, options.normal_bits, vertex_normals, he,
                                       decoded, s);
        }))
      kept_h.push_back(prop::kCornerNormal);
  }

  // Generic vertex properties.
  std::vector<Vertex> live;
  live.reserve(mesh.n_vertices());
  for (Vertex v : mesh.vertices()) live.push_back(v);
  for (const std::string& name : mesh.property_names<Vertex>()) {
    if (name == SurfaceMesh::kPositions || (name == prop::kVertexNormal && vertex_normals) ||
        (name == prop::kVertexTexCoord && vertex_uvs))
      continue;
    const std::uint8_t type = type_code(mesh, name);
    // v:normal / v:texcoord of their usual types were dropped on request (bits 0).
    const bool usual = (name == prop::kVertexNormal && mesh.get_property<Vertex, Normal>(name)) ||
                       (name == prop::kVertexTexCoord && mesh.get_property<Vertex, TexCoord>(name));
    if (type == kTypeCount || usual || options.attribute_bits == 0 || name.empty() ||
        name.size() > 255) {
      out.dropped.push_back(name);
      continue;
    }
    with_type(type, [&](auto tag) {
      using T = decltype(tag);
      entry([&](AttributeStats& s) {
        encode_generic<T>(body, mesh, name, type, options.attribute_bits, decoded, vertex_order,
                          live, s);
        return true;
      });
    });
  }
  if (corners.polys && !corners.rotation.empty()) {
    const std::size_t before = body.bytes().size();
    if (encode_rotation(body, decoded, *corners.polys, corners.rotation, corners.min_degree))
      ++entries;
    out.rotation_bytes = body.bytes().size() - before;
  }
  if (!options.loose_faces.empty()) {
    const std::size_t before = body.bytes().size();
    encode_loose(body, loose_in_decoded_order(options, vertex_order, mesh.n_faces()),
                 options.preserve_order);
    ++entries;
    out.loose_face_bytes = body.bytes().size() - before;
  }
  // Vertices that are one in the source: last, so that the attributes' offsets stay put.
  if (const auto split = split_copies(options.vertex_origin, vertex_order); !split.empty()) {
    encode_split(body, split);
    ++entries;
  }
  drop_all<Halfedge>(mesh, out.dropped, kept_h);
  drop_all<Edge>(mesh, out.dropped);
  drop_all<Face>(mesh, out.dropped);
  if (entries == 0) return out;
  ByteWriter w;
  w.varint(entries);
  w.append(body.bytes());
  out.bytes = std::move(w.bytes());
  return out;
}

namespace {

void decode_corner_entry(ByteReader& r, std::span<const std::uint8_t> stream,
                         const CornerTable& table, DecodedCornerAttribute& a, unsigned lanes) {
  a.bits = r.u8();
  if (a.normal ? (a.bits < 2 || a.bits > 20) : (a.bits < 1 || a.bits > 30))
    throw DecodeError(r.offset() - 1, "corner attribute bits out of range");
  if (!a.normal) {
    a.origin[0] = r.f64();
    a.origin[1] = r.f64();
    a.step = r.f64();
    const double top = static_cast<double>((std::uint64_t{1} << a.bits) - 1);
    if (!std::isfinite(a.origin[0]) || !std::isfinite(a.origin[1]) || !std::isfinite(a.step) ||
        !(a.step > 0) || !std::isfinite(a.origin[0] + a.step * top) ||
        !std::isfinite(a.origin[1] + a.step * top))
      throw DecodeError(r.offset() - 8, "corner texture coordinate grid not finite and positive");
  }
  const std::uint64_t rans_at = r.offset();
  const auto rans = r.take(r.varint());
  const auto raw = r.take(r.varint());
  if (table.vertex.empty()) {
    if (!rans.empty() || !raw.empty())
      throw DecodeError(rans_at, "corner attribute data for a mesh without faces");
    return;
  }
  RansDecoder rd(rans, static_cast<std::uint64_t>(rans.data() - stream.data()), lanes);
  BitReader br(raw, static_cast<std::uint64_t>(raw.data() - stream.data()));
  decode_corner_values(table, a.bits, rd, br, a.values);
  rd.finish();
}

void decode_generic_entry(ByteReader& r, std::span<const std::uint8_t> stream,
                          const CornerTable& table, std::size_t nv, DecodedGeneric& g,
                          unsigned lanes) {
  const std::uint8_t len = r.u8();
  if (len == 0) throw DecodeError(r.offset() - 1, "empty attribute name");
  const auto name = r.take(len);
  g.name.assign(reinterpret_cast<const char*>(name.data()), name.size());
  g.type = r.u8();
  if (g.type >= kTypeCount)
    throw DecodeError(r.offset() - 1, "unknown attribute type " + str(g.type));
  with_type(g.type, [&](auto tag) { g.dims = dims_of<decltype(tag)>(); });
  const unsigned bits = r.u8();
  if (bits < 1 || bits > 30) throw DecodeError(r.offset() - 1, "attribute bits outside 1–30");
  const double top = static_cast<double>((std::uint64_t{1} << bits) - 1);
  double origin[4], step[4];
  for (unsigned k = 0; k < g.dims; ++k) {
    origin[k] = r.f64();
    step[k] = r.f64();
    if (!std::isfinite(origin[k]) || !std::isfinite(step[k]) || !(step[k] > 0) ||
        !std::isfinite(origin[k] + step[k] * top))
      throw DecodeError(r.offset() - 8, "attribute grid not finite and positive");
    g.max_error = std::max(g.max_error, 0.5 * step[k]);
  }
  g.values.assign(nv * g.dims, 0.0);
  std::vector<QPoint> q;
  for (unsigned plane = 0; plane * 3 < g.dims; ++plane) {
    const std::uint64_t at = r.offset();
    const auto rans = r.take(r.varint());
    const auto raw = r.take(r.varint());
    if (nv == 0) {
      if (!rans.empty() || !raw.empty()) throw DecodeError(at, "attribute data for an empty mesh");
      continue;
    }
    if (nv > kMaxVerticesPerByte * rans.size() + 64)
      throw DecodeError(at, "attribute section too short for the vertex count");
    RansDecoder rd(rans, static_cast<std::uint64_t>(rans.data() - stream.data()), lanes);
    BitReader br(raw, static_cast<std::uint64_t>(raw.data() - stream.data()));
    decode_positions(table, nv, bits, Predictor::kMultiParallelogram, rd, br, q);
    rd.finish();
    for (std::size_t i = 0; i < nv; ++i)
      for (unsigned a = 0; a < 3; ++a) {
        const unsigned k = plane * 3 + a;
        if (k < g.dims)
          g.values[i * g.dims + k] = origin[k] + step[k] * q[i][a];
        else if (q[i][a] != 0)
          throw DecodeError(at, "attribute with a component beyond its type");
      }
  }
}

void decode_split_entry(ByteReader& r, std::size_t at, std::span<const QPoint> q,
                        std::vector<std::array<std::uint32_t, 2>>& split) {
  const std::size_t nv = q.size();
  if (!split.empty()) throw DecodeError(at, "split vertices given twice");
  const std::uint64_t n = r.varint();
  // Two bytes at least per copy, and every copy leaves a vertex before it.
  if (n == 0 || n >= std::max<std::size_t>(nv, 1) || n > r.remaining() / 2)
    throw DecodeError(at + 1, "split vertex count " + str(n) + " impossible");
  std::vector<std::uint8_t> is_copy(nv, 0);
  split.reserve(n);
  std::uint64_t next = 0;
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::size_t where = r.offset();
    const std::uint64_t gap = r.varint(), rep = r.varint();
    if (gap >= nv || next + gap >= nv)
      throw DecodeError(where, "split vertex beyond the vertex count");
    const std::uint64_t copy = next + gap;
    if (rep >= copy) throw DecodeError(where, "split vertex joined to a vertex not before it");
    if (is_copy[rep]) throw DecodeError(where, "split vertex joined to another split vertex");
    // build() gives a copy its source's position, so a copy elsewhere is a corrupt entry.
    if (q[copy] != q[rep]) throw DecodeError(where, "split vertex not at its representative's position");
    is_copy[copy] = 1;
    split.push_back({static_cast<std::uint32_t>(copy), static_cast<std::uint32_t>(rep)});
    next = copy + 1;
  }
}

/// Each decoded corner's halfedge on the rebuilt mesh.
std::vector<Halfedge> decoded_corner_halfedges(const SurfaceMesh& mesh, const CornerTable& t,
                                               std::span<const std::uint32_t> vertex_slot,
                                               std::span<const std::uint32_t> face_slot,
                                               std::uint64_t where) {
  const std::vector<std::uint32_t> poly = polygon_of_triangles(t);
  const std::size_t n = poly.empty() ? 0 : *std::max_element(poly.begin(), poly.end()) + 1;
  if (n != face_slot.size()) throw DecodeError(where, "polygon count disagrees with the faces");
  std::vector<Halfedge> out(t.vertex.size());
  for (std::size_t c = 0; c < out.size(); ++c) {
    const Vertex target(vertex_slot[t.vertex[c]]);
    for (Halfedge h : mesh.halfedges(Face(face_slot[poly[c / 3]])))
      if (mesh.to_vertex(h) == target) out[c] = h;
    if (!out[c].is_valid()) throw DecodeError(where, "corner not found on its face");
  }
  return out;
}

}  // namespace

ExtensionDecoding decode_extension(std::span<const std::uint8_t> stream, std::size_t begin,
                                   const CornerTable& table, std::span<const QPoint> q,
                                   bool vertex_normals, bool vertex_uvs, unsigned rans_lanes,
                                   std::size_t n_faces, bool order_preserved) {
  const std::size_t n_vertices = q.size();
  ByteReader r(stream);
  r.take(begin);
  ExtensionDecoding out;
  out.offset = begin;
  const std::uint64_t n = r.varint();
  if (n == 0 || n > r.remaining())
    throw DecodeError(begin, "extension entry count " + str(n) + " impossible");
  bool seen[2] = {false, false}, seen_loose = false;
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::size_t at = r.offset();
    const std::uint8_t kind = r.u8();
    if (kind == kCornerTexcoord || kind == kCornerNormal) {
      if (seen[kind]) throw DecodeError(at, "corner attribute given twice");
      seen[kind] = true;
      DecodedCornerAttribute a;
      a.normal = kind == kCornerNormal;
      const std::uint8_t mode = r.u8();
      if (mode > 1) throw DecodeError(at + 1, "unknown corner attribute mode " + str(mode));
      a.from_vertex = mode == 1;
      if (a.from_vertex && !(a.normal ? vertex_normals : vertex_uvs))
        throw DecodeError(at + 1, "corner attribute refers to a vertex attribute the stream lacks");
      if (!a.from_vertex) decode_corner_entry(r, stream, table, a, rans_lanes);
      a.bytes = r.offset() - at;
      out.corners.push_back(std::move(a));
    } else if (kind == kGeneric) {
      DecodedGeneric g;
      decode_generic_entry(r, stream, table, n_vertices, g, rans_lanes);
      for (const DecodedGeneric& o : out.generic)
        if (o.name == g.name) throw DecodeError(at, "attribute '" + g.name + "' given twice");
      g.bytes = r.offset() - at;
      out.generic.push_back(std::move(g));
    } else if (kind == kSplit) {
      decode_split_entry(r, at, q, out.split);
    } else if (kind == kEntryRotation) {
      if (order_preserved) throw DecodeError(at, "face rotations beside the order section");
      read_rotation(r, stream, at, out.rotation);
    } else if (kind == kEntryLooseFaces) {
      decode_loose(r, at, n_vertices, n_faces, order_preserved, out.loose, seen_loose);
    } else {
      throw DecodeError(at, "unknown extension entry kind " + str(kind));
    }
  }
  if (r.remaining() != 0) throw DecodeError(r.offset(), "trailing bytes after the extension block");
  return out;
}

void apply_extension(const ExtensionDecoding& ext, SurfaceMesh& mesh, const CornerTable& table,
                     std::span<const std::uint32_t> vertex_slot,
                     std::span<const std::uint32_t> face_slot, std::vector<AttributeStats>& stats,
                     std::vector<std::uint32_t>& representative) {
  if (!ext.split.empty()) {
    // Each copy to its representative, in mesh numbering; then each group to its lowest
    // vertex (with the order preserved, the source's own: build() numbers copies last).
    const std::size_t nv = vertex_slot.size();
    representative.resize(nv);
    for (std::uint32_t v = 0; v < nv; ++v) representative[v] = v;
    for (const auto& [copy, rep] : ext.split) representative[vertex_slot[copy]] = vertex_slot[rep];
    std::vector<std::uint32_t> lowest = representative;
    for (std::uint32_t v = 0; v < nv; ++v)
      lowest[representative[v]] = std::min(lowest[representative[v]], v);
    for (std::uint32_t& r : representative) r = lowest[r];
  }
  const std::vector<Halfedge> he =
      ext.corners.empty()
          ? std::vector<Halfedge>{}
          : decoded_corner_halfedges(mesh, table, vertex_slot, face_slot, ext.offset);
  for (const DecodedCornerAttribute& a : ext.corners) {
    const char* name = a.normal ? prop::kCornerNormal : prop::kCornerTexCoord;
    double err = a.normal ? 4.5 / std::ldexp(1.0, static_cast<int>(a.bits)) : 0.5 * a.step;
    if (a.normal) {
      auto p = mesh.add_property<Halfedge, Normal>(name);
      const auto pv = mesh.get_property<Vertex, Normal>(prop::kVertexNormal);
      for (std::size_t c = 0; c < he.size(); ++c)
        p[he[c]] = a.from_vertex
                       ? pv[mesh.to_vertex(he[c])]
                       : octahedral_dequantise({a.values[c][0], a.values[c][1], 0}, a.bits);
    } else {
      auto p = mesh.add_property<Halfedge, TexCoord>(name);
      const auto pv = mesh.get_property<Vertex, TexCoord>(prop::kVertexTexCoord);
      for (std::size_t c = 0; c < he.size(); ++c)
        p[he[c]] = a.from_vertex ? pv[mesh.to_vertex(he[c])]
                                 : TexCoord(a.origin[0] + a.step * a.values[c][0],
                                            a.origin[1] + a.step * a.values[c][1]);
    }
    if (a.from_vertex) err = 0;
    stats.push_back({name, a.bytes, err});
  }
  for (const DecodedGeneric& g : ext.generic) {
    if (mesh.has_property<Vertex>(g.name))
      throw DecodeError(ext.offset,
                        "attribute '" + g.name + "' clashes with a property of the mesh");
    with_type(g.type, [&](auto tag) {
      using T = decltype(tag);
      auto p = mesh.add_property<Vertex, T>(g.name);
      for (std::size_t i = 0; i < vertex_slot.size(); ++i) {
        T& v = p[Vertex(vertex_slot[i])];
        if constexpr (dims_of<T>() == 1)
          v = static_cast<T>(g.values[i]);
        else
          for (unsigned k = 0; k < g.dims; ++k)
            v[k] = static_cast<typename T::Scalar>(g.values[i * g.dims + k]);
      }
    });
    stats.push_back({g.name, g.bytes, g.max_error});
  }
}

bool has_split_vertices(std::span<const std::uint32_t> vertex_origin,
                        std::span<const Point> positions) {
  bool shared = false;
  for_each_repeat(
      vertex_origin.size(), [&](std::uint32_t v) { return vertex_origin[v]; },
      [&](std::uint32_t v, std::uint32_t first) {
        shared = true;
        if (positions[v] != positions[first])
          throw InvalidArgument("compress: vertices " + str(first) + " and " + str(v) +
                                " share vertex_origin " + str(vertex_origin[v]) +
                                " but not their position");
      });
  return shared;
}

std::size_t max_extension_size(std::size_t n_vertices, std::size_t n_triangle_corners,
                               std::size_t n_corner_attributes, std::size_t n_generic_components,
                               std::size_t n_split_copies, std::size_t n_faces,
                               std::size_t n_loose_faces, std::size_t n_loose_corners) {
  const std::size_t faces = max_face_entries_size(n_faces, n_loose_faces, n_loose_corners);
  if (n_corner_attributes + n_generic_components + n_split_copies == 0) return 10 + faces;
  // Split copies: a kind byte, a count and two varints of at most 5 bytes each.
  const std::size_t split = n_split_copies == 0 ? 0 : 6 + 10 * n_split_copies;
  // Every model symbol ≤ 11 bits, raw fields ≤ 29 bits. Per corner: half a seam bit's edge
  // (≤ 6 bits) and, per wedge (≤ one per corner), two residuals of a length symbol, a
  // modelled-bits symbol and ≤ 29 raw bits. Headers: kind, mode, bits, 24 grid bytes and
  // two section lengths.
  const std::size_t corner =
      (n_triangle_corners * (6 + 2 * (11 + 11 + 29)) + 7) / 8 + 16 + 2 + 25 + 20;
  // A generic component is at worst one plane of its own, coded like the positions, plus
  // its name (≤ 255 bytes and its length), kind, type, bits, 16 grid bytes and two section
  // lengths.
  const std::size_t plane = (n_vertices * (6 * 11 + 87) + 7) / 8 + 16;
  const std::size_t generic = plane + 256 + 3 + 16 + 20;
  return 10 + n_corner_attributes * corner + n_generic_components * generic + split + faces;
}

}  // namespace geom::codec::detail
