#include <geom/compress/container/face_entries.h>

#include <geom/compress/container/stream.h>
#include <geom/core/errors.h>

#include <algorithm>
#include <string>

namespace geom::codec::detail {

namespace {


std::uint32_t degree(const Polygons& p, std::size_t j) { return p.offset[j + 1] - p.offset[j]; }

/// The rank of corner i of polygon j when its corners are sorted by diagonal count
/// (descending), then by place in the cycle: a fan's apex comes first, and the encoder fans
/// from the first corner whenever it can.
std::uint32_t rank_of(std::span<const std::uint32_t> count, std::uint32_t i) {
  std::uint32_t r = 0;
  for (std::uint32_t k = 0; k < count.size(); ++k)
    r += count[k] > count[i] || (count[k] == count[i] && k < i);
  return r;
}

/// The corner of rank `rank` (rank < count.size()); a sort, as a polygon may be large.
std::uint32_t corner_of_rank(std::span<const std::uint32_t> count, std::uint32_t rank,
                             std::vector<std::uint32_t>& order) {
  order.resize(count.size());
  for (std::uint32_t i = 0; i < count.size(); ++i) order[i] = i;
  std::nth_element(order.begin(), order.begin() + rank, order.end(),
                   [&](std::uint32_t a, std::uint32_t b) {
                     return count[a] > count[b] || (count[a] == count[b] && a < b);
                   });
  return order[rank];
}

/// The three symbol models: triangles, quads (their one diagonal leaves two candidates) and
/// larger polygons (a gamma value: mostly 0, the apex).
struct RotationModels {
  AdaptiveModel tri{3}, quad{4};
  GammaModel other;
};

}  // namespace

std::vector<std::uint32_t> polygon_of_triangles(const CornerTable& t) {
  const std::size_t nt = t.n_triangles();
  std::vector<std::uint32_t> poly(nt, kNone), stack;
  std::uint32_t n = 0;
  for (std::uint32_t t0 = 0; t0 < nt; ++t0) {
    if (poly[t0] != kNone) continue;
    poly[t0] = n;
    stack.push_back(t0);
    while (!stack.empty()) {
      const std::uint32_t tr = stack.back();
      stack.pop_back();
      for (std::uint32_t c = 3 * tr; c < 3 * tr + 3 && !t.diagonal.empty(); ++c) {
        const std::uint32_t o = t.opposite[c];
        if (t.diagonal[c] && o != kNone && poly[o / 3] == kNone) {
          poly[o / 3] = n;
          stack.push_back(o / 3);
        }
      }
    }
    ++n;
  }
  return poly;
}

std::vector<std::uint32_t> diagonal_counts(const CornerTable& table, const Polygons& polys) {
  std::vector<std::uint32_t> count(polys.vertex.size(), 0);
  if (table.diagonal.empty()) return count;
  const std::vector<std::uint32_t> poly = polygon_of_triangles(table);
  // Triangles bucketed by polygon, then each diagonal end found in its polygon's cycle.
  std::vector<std::uint32_t> start(polys.size() + 1, 0), tris(poly.size());
  for (std::uint32_t p : poly) ++start[p + 1];
  for (std::size_t j = 0; j < polys.size(); ++j) start[j + 1] += start[j];
  std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
  for (std::uint32_t tr = 0; tr < poly.size(); ++tr) tris[fill[poly[tr]]++] = tr;
  std::uint32_t top = 0;
  for (std::uint32_t v : polys.vertex) top = std::max(top, v + 1);
  std::vector<std::uint32_t> place(top, 0);  // a vertex's corner in the current polygon
  for (std::size_t j = 0; j < polys.size(); ++j) {
    const std::uint32_t b = polys.offset[j], k = degree(polys, j);
    if (k < 4) continue;
    for (std::uint32_t x = 0; x < k; ++x) place[polys.vertex[b + x]] = x;
    for (std::uint32_t i = start[j]; i < start[j + 1]; ++i)
      for (std::uint32_t c = 3 * tris[i]; c < 3 * tris[i] + 3; ++c) {
        if (!table.diagonal[c]) continue;
        for (std::uint32_t v : {table.vertex[next_corner(c)], table.vertex[prev_corner(c)]})
          if (v < top && place[v] < k && polys.vertex[b + place[v]] == v)  // (a corrupt table)
            ++count[b + place[v]];
      }
  }
  return count;
}

bool encode_rotation(ByteWriter& w, const CornerTable& table, const Polygons& polys,
                     std::span<const std::uint32_t> rotation, unsigned min_degree) {
  bool any = false;
  for (std::size_t j = 0; j < polys.size(); ++j)
    any = any || (degree(polys, j) >= min_degree && rotation[j] != 0);
  if (!any) return false;
  const std::vector<std::uint32_t> count = diagonal_counts(table, polys);
  RansEncoder re;
  BitWriter bw;
  RotationModels m;
  for (std::size_t j = 0; j < polys.size(); ++j) {
    const std::uint32_t k = degree(polys, j);
    if (k < min_degree) continue;
    const std::uint32_t s =
        rank_of(std::span(count).subspan(polys.offset[j], k), rotation[j]);
    if (k == 3)
      re.encode(m.tri, s);
    else if (k == 4)
      re.encode(m.quad, s);
    else
      m.other.encode(re, bw, s);
  }
  w.u8(kEntryRotation);
  w.u8(static_cast<std::uint8_t>(min_degree));
  write_section(w, re.symbols() > 0 ? re.finish() : std::vector<std::uint8_t>{});
  write_section(w, bw.finish());
  return true;
}

void read_rotation(ByteReader& r, std::span<const std::uint8_t> stream, std::size_t at,
                   RotationEntry& e) {
  if (e.min_degree != 0) throw DecodeError(at, "face rotations given twice");
  e.at = at;
  e.min_degree = r.u8();
  if (e.min_degree != 3 && e.min_degree != 4)
    throw DecodeError(at + 1, "face rotation degree " + std::to_string(e.min_degree) + " not 3 or 4");
  e.rans = r.take(r.varint());
  e.rans_at = static_cast<std::uint64_t>(e.rans.data() - stream.data());
  e.raw = r.take(r.varint());
  e.raw_at = static_cast<std::uint64_t>(e.raw.data() - stream.data());
}

std::vector<std::uint32_t> decode_rotation(const RotationEntry& e, const CornerTable& table,
                                           const Polygons& polys, unsigned lanes) {
  std::vector<std::uint32_t> rotation(polys.size(), 0);
  if (e.min_degree == 0) return rotation;
  std::size_t n = 0;
  for (std::size_t j = 0; j < polys.size(); ++j) n += degree(polys, j) >= e.min_degree;
  if (n == 0) {
    if (!e.rans.empty() || !e.raw.empty()) throw DecodeError(e.at, "face rotations for no faces");
    return rotation;
  }
  // Every symbol costs at least (n − 1)/710 bits of its model (FORMAT.md, adaptive models).
  if (n > 2048 * e.rans.size() + 16)
    throw DecodeError(e.rans_at, "face rotation section too short for the faces");
  const std::vector<std::uint32_t> count = diagonal_counts(table, polys);
  RansDecoder rd(e.rans, e.rans_at, lanes);
  BitReader br(e.raw, e.raw_at);
  RotationModels m;
  std::vector<std::uint32_t> order;
  for (std::size_t j = 0; j < polys.size(); ++j) {
    const std::uint32_t k = degree(polys, j);
    if (k < e.min_degree) continue;
    const std::uint32_t s = k == 3 ? rd.decode(m.tri) : k == 4 ? rd.decode(m.quad) : m.other.decode(rd, br);
    const std::uint32_t i =
        s < k ? corner_of_rank(std::span(count).subspan(polys.offset[j], k), s, order) : kNone;
    if (i == kNone) throw DecodeError(rd.offset(), "face rotation beyond the face's corners");
    rotation[j] = i;
  }
  rd.finish();
  return rotation;
}

void encode_loose(ByteWriter& w, const LooseFaces& loose, bool with_positions) {
  w.u8(kEntryLooseFaces);
  w.varint(loose.faces.size());
  std::int64_t first = 0;
  std::uint32_t next_position = 0;
  for (std::size_t i = 0; i < loose.faces.size(); ++i) {
    if (with_positions) {
      w.varint(loose.positions[i] - next_position);
      next_position = loose.positions[i] + 1;
    }
    const std::vector<std::uint32_t>& f = loose.faces[i];
    w.varint(f.size());
    // A face's corners lie near each other and near the previous face's in decoded order.
    std::int64_t prev = first;
    for (std::uint32_t v : f) {
      w.varint(zigzag(std::int64_t{v} - prev));
      prev = v;
    }
    if (!f.empty()) first = f.front();
  }
}

void decode_loose(ByteReader& r, std::size_t at, std::size_t n_vertices, std::size_t n_faces,
                  bool with_positions, LooseFaces& out, bool& seen) {
  if (seen) throw DecodeError(at, "loose faces given twice");
  seen = true;
  const std::uint64_t n = r.varint();
  if (n == 0 || n > r.remaining())
    throw DecodeError(at + 1, "loose face count " + std::to_string(n) + " impossible");
  out.faces.resize(n);
  std::int64_t first = 0;
  std::uint64_t next_position = 0;
  for (std::uint64_t i = 0; i < n; ++i) {
    const std::size_t where = r.offset();
    if (with_positions) {
      const std::uint64_t p = next_position + r.varint();
      if (p >= n_faces + n) throw DecodeError(where, "loose face position beyond the faces");
      out.positions.push_back(static_cast<std::uint32_t>(p));
      next_position = p + 1;
    }
    const std::uint64_t k = r.varint();
    if (k > r.remaining()) throw DecodeError(where, "loose face corner count impossible");
    std::int64_t prev = first;
    for (std::uint64_t c = 0; c < k; ++c) {
      const std::uint64_t z = r.varint();
      if (z > 0xffffffffu) throw DecodeError(where, "loose face vertex beyond the vertex count");
      prev += unzigzag(static_cast<std::uint32_t>(z));
      if (prev < 0 || prev >= static_cast<std::int64_t>(n_vertices))
        throw DecodeError(where, "loose face vertex beyond the vertex count");
      out.faces[i].push_back(static_cast<std::uint32_t>(prev));
    }
    if (k > 0) first = out.faces[i].front();
  }
}

LooseFaces loose_in_decoded_order(const CompressOptions& options,
                                  std::span<const std::uint32_t> vertex_order, std::size_t n_faces) {
  std::vector<std::uint32_t> decoded_id(vertex_order.size());
  for (std::uint32_t i = 0; i < vertex_order.size(); ++i) decoded_id[vertex_order[i]] = i;
  LooseFaces out;
  out.faces = options.loose_faces;
  for (auto& f : out.faces)
    for (std::uint32_t& v : f) v = decoded_id[v];
  if (options.preserve_order) out.positions = options.loose_face_positions;
  // Without places, the loose faces follow the mesh's.
  for (std::size_t i = out.positions.size(); options.preserve_order && i < out.faces.size(); ++i)
    out.positions.push_back(static_cast<std::uint32_t>(n_faces + i));
  return out;
}

void check_loose_faces(const CompressOptions& o, std::size_t n_vertices, std::size_t n_faces) {
  for (std::size_t i = 0; i < o.loose_faces.size(); ++i)
    for (std::uint32_t v : o.loose_faces[i])
      if (v >= n_vertices)
        throw InvalidArgument("compress: loose face " + std::to_string(i) + " names vertex " +
                              std::to_string(v) + " of " + std::to_string(n_vertices));
  if (!o.preserve_order || o.loose_face_positions.empty()) return;
  const std::vector<std::uint32_t>& p = o.loose_face_positions;
  bool ok = p.size() == o.loose_faces.size();
  for (std::size_t i = 0; ok && i < p.size(); ++i)
    ok = p[i] < n_faces + p.size() && (i == 0 || p[i] > p[i - 1]);
  if (!ok)
    throw InvalidArgument("compress: loose_face_positions must give each loose face its place "
                          "in the face list, ascending (preserve_order)");
}

std::size_t max_face_entries_size(std::size_t n_faces, std::size_t n_loose_faces,
                                  std::size_t n_loose_corners) {
  // Rotations: a symbol ≤ 11 bits and ≤ 31 raw bits per face, 8 state bytes, kind, degree
  // and two section lengths. Loose faces: kind, count, and per face a position and a degree,
  // per corner a varint, each at most 10 bytes.
  const std::size_t rotation = (n_faces * (11 + 31) + 7) / 8 + 16 + 2 + 20;
  const std::size_t loose =
      n_loose_faces == 0 ? 0 : 11 + 20 * n_loose_faces + 10 * n_loose_corners;
  return rotation + loose;
}

}  // namespace geom::codec::detail
