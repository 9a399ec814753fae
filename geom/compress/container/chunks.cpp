// Chunked streams (version 3): the spatial split and merge map on the way in, the parallel
// decode and the merge on the way out. FORMAT.md specifies the layout.
#include <geom/compress/container/chunks.h>

#include <geom/compress/container/stream.h>
#include <geom/compress/rans.h>
#include <geom/core/errors.h>
#include <geom/core/soup.h>

#include <Eigen/Geometry>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <bit>
#include <exception>
#include <string>
#include <unordered_map>

namespace geom::codec::detail {

namespace {

/// The merge map's models, in coding order (FORMAT.md, "Chunked streams").
struct MergeModels {
  GammaModel count, gap, chunk, target;
};

/// The table's edges with one triangle (as vertex pairs). open_corners: the corners without
/// an opposite, when known (then the opposites, long out of cache after a chunk's decode, are
/// not scanned again).
using Edges = std::vector<std::array<std::uint32_t, 2>>;

Edges open_edges(const CornerTable& t, const std::vector<std::uint32_t>* open_corners = nullptr) {
  Edges out;
  auto add = [&](std::uint32_t c) { out.push_back({t.vertex[next_corner(c)], t.vertex[prev_corner(c)]}); };
  if (open_corners) {
    for (std::uint32_t c : *open_corners) add(c);
  } else {
    for (std::uint32_t c = 0; c < t.vertex.size(); ++c)
      if (t.opposite[c] == kNone) add(c);
  }
  return out;
}

/// A boundary vertex's neighbours along the boundary, as sorted grid points: what tells
/// apart two boundary vertices on one grid point without the stream's numbering. (Along the
/// boundary only: a polygon's diagonals are never boundary edges, so the ring does not
/// depend on how the polygon was cut into triangles.)
using Ring = std::vector<QPoint>;

/// The rings of the vertices in `of` (ascending).
std::vector<Ring> rings(std::span<const std::uint32_t> of, const Edges& edges, std::span<const QPoint> q) {
  std::vector<Ring> out(of.size());
  auto add = [&](std::uint32_t v, std::uint32_t to) {
    const auto at = std::lower_bound(of.begin(), of.end(), v);
    if (at != of.end() && *at == v) out[static_cast<std::size_t>(at - of.begin())].push_back(q[to]);
  };
  for (const auto& [a, b] : edges) add(a, b), add(b, a);
  for (Ring& r : out) std::sort(r.begin(), r.end());
  return out;
}

/// A chunk's boundary vertices (the ends of its open edges; every vertex it shares with
/// another chunk is one), ordered by grid point, ties by ring, then by number. Point and
/// ring depend only on the chunk's geometry and connectivity, not on how its stream
/// numbered the vertices, so the merge map costs the same whatever configuration a level
/// picks for each chunk. `still_tied[i]`: ranked[i] and ranked[i + 1] share point and ring
/// (only their numbers order them).
struct RankedBoundary {
  std::vector<std::uint32_t> ranked;
  std::vector<std::uint8_t> still_tied;
};

RankedBoundary ranked_boundary(const Edges& edges, std::span<const QPoint> q) {
  RankedBoundary out;
  std::vector<std::uint32_t>& b = out.ranked;
  for (const auto& e : edges) b.insert(b.end(), e.begin(), e.end());
  std::sort(b.begin(), b.end(), [&](std::uint32_t x, std::uint32_t y) {
    return q[x] != q[y] ? q[x] < q[y] : x < y;
  });
  b.erase(std::unique(b.begin(), b.end()), b.end());  // each vertex ends two open edges or more
  out.still_tied.assign(b.size(), 0);
  std::vector<std::uint32_t> tied;  // rare: only a grid coarser than the seam's spacing has any
  for (std::size_t i = 0; i + 1 < b.size(); ++i)
    if (q[b[i]] == q[b[i + 1]]) tied.push_back(b[i]), tied.push_back(b[i + 1]);
  if (tied.empty()) return out;
  std::sort(tied.begin(), tied.end());
  tied.erase(std::unique(tied.begin(), tied.end()), tied.end());
  const std::vector<Ring> ring = rings(tied, edges, q);
  const auto ring_of = [&](std::uint32_t v) -> const Ring& {
    return ring[static_cast<std::size_t>(std::lower_bound(tied.begin(), tied.end(), v) - tied.begin())];
  };
  for (std::size_t i = 0; i < b.size();) {
    std::size_t e = i + 1;
    while (e < b.size() && q[b[e]] == q[b[i]]) ++e;
    std::stable_sort(b.begin() + static_cast<std::ptrdiff_t>(i), b.begin() + static_cast<std::ptrdiff_t>(e),
                     [&](std::uint32_t x, std::uint32_t y) { return ring_of(x) < ring_of(y); });
    for (std::size_t j = i; j + 1 < e; ++j) out.still_tied[j] = ring_of(b[j]) == ring_of(b[j + 1]);
    i = e;
  }
  return out;
}

// ---- encoder ------------------------------------------------------------------------------

/// A face and the point it is split by (its fan triangles' mean corner): kept together, so
/// the median searches move contiguous records instead of chasing face numbers.
struct Centroid {
  Point at;
  std::uint32_t face;
};

/// Median splits along the longest axis of the centroids' box, recursively, into `parts`
/// groups of near-equal face count; chunk_of[face] receives its group, numbered from
/// `first` in the order the splits leave them.
void split_faces(std::span<Centroid> items, std::size_t parts, std::uint32_t first,
                 std::vector<std::uint32_t>& chunk_of) {
  if (parts == 1) {
    for (const Centroid& c : items) chunk_of[c.face] = first;
    return;
  }
  Eigen::AlignedBox3d box;
  for (const Centroid& c : items) box.extend(c.at);
  int axis = 0;
  box.diagonal().maxCoeff(&axis);
  const std::size_t left = parts / 2, cut = items.size() * left / parts;
  std::nth_element(items.begin(), items.begin() + static_cast<std::ptrdiff_t>(cut), items.end(),
                   [&](const Centroid& a, const Centroid& b) {
                     return a.at[axis] != b.at[axis] ? a.at[axis] < b.at[axis] : a.face < b.face;
                   });
  split_faces(items.first(cut), left, first, chunk_of);
  split_faces(items.subspan(cut), parts - left, first + static_cast<std::uint32_t>(left), chunk_of);
}

struct Chunk {
  std::vector<std::uint32_t> faces;     // input (dense) faces, ascending
  std::vector<std::uint32_t> vertices;  // input (dense) vertex of each chunk vertex, ascending
  FlatMesh flat;                        // the chunk's faces on their own
  CompressResult result;
  std::vector<std::uint32_t> input_of;  // decoded vertex → input vertex
  std::vector<std::uint32_t> ranked;    // ranked_boundary, decoded numbering
};

/// Every face's centroid: the mean of its fan triangles' corners.
std::vector<Centroid> face_centroids(const FlatMesh& flat, std::span<const std::uint32_t> first_tri) {
  std::vector<Centroid> out(flat.n_faces);
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(flat.n_faces), 4096),
                    [&](const tbb::blocked_range<std::uint32_t>& r) {
                      for (std::uint32_t f = r.begin(); f != r.end(); ++f) {
                        Point sum = Point::Zero();
                        for (std::uint32_t i = 3 * first_tri[f]; i < 3 * first_tri[f + 1]; ++i)
                          sum += flat.positions[flat.table.vertex[i]];
                        out[f] = {sum / (3.0 * (first_tri[f + 1] - first_tri[f])), f};
                      }
                    });
  return out;
}

/// The faces of each group, ascending (input face order).
std::vector<std::vector<std::uint32_t>> group_faces(const std::vector<std::uint32_t>& chunk_of,
                                                    std::size_t parts) {
  std::vector<std::vector<std::uint32_t>> out(parts);
  for (auto& g : out) g.reserve(chunk_of.size() / parts + 1);
  for (std::uint32_t f = 0; f < chunk_of.size(); ++f) out[chunk_of[f]].push_back(f);
  return out;
}

/// Chunk k's faces as a FlatMesh of their own: triangles (with their diagonal flags) in input
/// order, vertices numbered in input order, opposites kept where both sides are in the chunk.
/// place[t] is triangle t's chunk (high half) and its place in the chunk (low half): one
/// read per opposite, which is anywhere in a shuffled input. local_of is scratch: kNone for
/// every input vertex on entry and on return.
void cut_chunk(Chunk& c, std::uint32_t k, const FlatMesh& flat,
               std::span<const std::uint32_t> first_tri, std::span<const std::uint64_t> place,
               std::vector<std::uint32_t>& local_of) {
  const CornerTable& in = flat.table;
  for (std::uint32_t f : c.faces)
    for (std::uint32_t i = 3 * first_tri[f]; i < 3 * first_tri[f + 1]; ++i)
      if (local_of[in.vertex[i]] == kNone) {
        local_of[in.vertex[i]] = 0;
        c.vertices.push_back(in.vertex[i]);
      }
  std::sort(c.vertices.begin(), c.vertices.end());
  for (std::uint32_t l = 0; l < c.vertices.size(); ++l) local_of[c.vertices[l]] = l;
  FlatMesh& out = c.flat;
  CornerTable& t = out.table;
  const bool diagonals = !in.diagonal.empty();
  std::size_t n_corners = 0;
  for (std::uint32_t f : c.faces) n_corners += 3 * (first_tri[f + 1] - first_tri[f]);
  t.vertex.reserve(n_corners);
  t.opposite.reserve(n_corners);
  for (std::uint32_t f : c.faces) {
    const auto face = static_cast<std::uint32_t>(out.n_faces++);
    out.face_first_vertex.push_back(local_of[flat.face_first_vertex[f]]);
    out.polygons |= first_tri[f + 1] - first_tri[f] > 1;
    for (std::uint32_t tri = first_tri[f]; tri < first_tri[f + 1]; ++tri) {
      out.triangle_face.push_back(face);
      for (std::uint32_t i = 3 * tri; i < 3 * tri + 3; ++i) {
        t.vertex.push_back(local_of[in.vertex[i]]);
        const std::uint32_t o = in.opposite[i];
        const std::uint64_t p = o == kNone ? 0 : place[o / 3];
        t.opposite.push_back(o != kNone && p >> 32 == k ? 3 * static_cast<std::uint32_t>(p) + o % 3 : kNone);
        if (diagonals) t.diagonal.push_back(in.diagonal[i]);
      }
    }
  }
  if (!out.polygons) t.diagonal.clear();
  for (std::uint32_t v : c.vertices) {
    out.positions.push_back(flat.positions[v]);
    local_of[v] = kNone;
  }
  t.n_vertices = static_cast<std::uint32_t>(out.positions.size());
}

/// The input's vertices no face uses go to the last chunk (the codec codes them last).
void add_isolated(Chunk& c, const FlatMesh& flat) {
  std::vector<std::uint8_t> used(flat.positions.size(), 0);
  for (std::uint32_t v : flat.table.vertex) used[v] = 1;
  for (std::uint32_t v = 0; v < flat.positions.size(); ++v)
    if (!used[v]) {
      c.vertices.push_back(v);
      c.flat.positions.push_back(flat.positions[v]);
    }
  c.flat.table.n_vertices = static_cast<std::uint32_t>(c.flat.positions.size());
}

/// Whether every vertex that chunks share has a grid point and ring (ranked_boundary) of its
/// own among its chunk's boundary vertices, so that the merge map can name it by rank. Not
/// when two copies of a surface touch, or on a grid far coarser than the seam's spacing:
/// then the mesh is coded as one stream.
bool seams_distinct(const std::vector<Chunk>& chunks, std::size_t n_vertices,
                    const Quantiser& grid) {
  std::vector<std::uint8_t> chunks_of(n_vertices, 0);
  for (const Chunk& c : chunks)
    for (std::uint32_t v : c.vertices) chunks_of[v] = static_cast<std::uint8_t>(std::min(chunks_of[v] + 1, 2));
  for (const Chunk& c : chunks) {
    std::vector<QPoint> q(c.flat.positions.size());
    for (std::size_t v = 0; v < q.size(); ++v) q[v] = grid.quantise(c.flat.positions[v]);
    const RankedBoundary r = ranked_boundary(open_edges(c.flat.table), q);
    const auto shared = [&](std::size_t i) { return chunks_of[c.vertices[r.ranked[i]]] > 1; };
    for (std::size_t i = 0; i + 1 < r.ranked.size(); ++i)
      if (r.still_tied[i] && (shared(i) || shared(i + 1))) return false;
  }
  return true;
}

/// Codes every later chunk's shared boundary vertices against the first chunk that has
/// them; returns the global (decoded) numbering's input vertices.
std::vector<std::uint32_t> code_merges(std::vector<Chunk>& chunks, std::size_t n_vertices,
                                       const Quantiser& grid, Streams& out) {
  tbb::parallel_for(std::size_t{0}, chunks.size(), [&](std::size_t k) {
    Chunk& c = chunks[k];
    const std::vector<std::uint32_t>& perm = c.result.vertex_permutation;
    c.input_of.resize(perm.size());
    std::vector<QPoint> q(perm.size());
    std::vector<std::uint32_t> decoded_of(perm.size());
    for (std::uint32_t l = 0; l < perm.size(); ++l) {
      c.input_of[l] = c.vertices[perm[l]];
      q[l] = grid.quantise(c.flat.positions[perm[l]]);
      decoded_of[perm[l]] = l;
    }
    Edges edges = open_edges(c.flat.table);
    for (auto& e : edges) e = {decoded_of[e[0]], decoded_of[e[1]]};
    c.ranked = ranked_boundary(edges, q).ranked;
  });
  std::vector<std::uint32_t> first_chunk(n_vertices, kNone), first_local(n_vertices, kNone);
  for (std::uint32_t k = 0; k < chunks.size(); ++k)
    for (std::uint32_t l = 0; l < chunks[k].input_of.size(); ++l)
      if (first_chunk[chunks[k].input_of[l]] == kNone)
        first_chunk[chunks[k].input_of[l]] = k, first_local[chunks[k].input_of[l]] = l;
  std::vector<std::vector<std::uint32_t>> rank(chunks.size());
  for (std::size_t k = 0; k < chunks.size(); ++k) {
    rank[k].assign(chunks[k].input_of.size(), kNone);
    for (std::uint32_t r = 0; r < chunks[k].ranked.size(); ++r) rank[k][chunks[k].ranked[r]] = r;
  }
  RansEncoder re;
  BitWriter bw;
  MergeModels m;
  std::vector<std::uint32_t> global;
  for (std::uint32_t k = 0; k < chunks.size(); ++k) {
    const Chunk& c = chunks[k];
    for (std::uint32_t l = 0; l < c.input_of.size(); ++l)
      if (first_chunk[c.input_of[l]] == k && first_local[c.input_of[l]] == l) global.push_back(c.input_of[l]);
    if (k == 0) continue;
    std::vector<std::uint32_t> merged;  // ranks in chunk k of vertices an earlier chunk has
    for (std::uint32_t r = 0; r < c.ranked.size(); ++r)
      if (first_chunk[c.input_of[c.ranked[r]]] < k) merged.push_back(r);
    m.count.encode(re, bw, static_cast<std::uint32_t>(merged.size()));
    std::vector<std::int64_t> last(k, -1);
    std::int64_t prev = -1;
    for (std::uint32_t r : merged) {
      const std::uint32_t v = c.input_of[c.ranked[r]], j = first_chunk[v];
      const std::uint32_t t = rank[j][first_local[v]];
      if (t == kNone) throw Error("compress: a shared vertex is not on its first chunk's boundary");
      m.gap.encode(re, bw, static_cast<std::uint32_t>(r - prev - 1));
      m.chunk.encode(re, bw, k - 1 - j);
      m.target.encode(re, bw, zigzag(std::int64_t{t} - last[j] - 1));
      last[j] = t;
      prev = r;
    }
  }
  out.rans = re.finish();
  out.raw = bw.finish();
  return global;
}

std::vector<std::string> dropped_names(const SurfaceMesh& mesh) {
  std::vector<std::string> out;
  for (auto names : {mesh.property_names<Halfedge>(), mesh.property_names<Edge>(),
                     mesh.property_names<Face>()})
    out.insert(out.end(), names.begin(), names.end());
  return out;
}

bool has_attributes(const SurfaceMesh& mesh) {
  for (const std::string& n : mesh.property_names<Vertex>())
    if (n != SurfaceMesh::kPositions) return true;
  return mesh.has_property<Halfedge>(prop::kCornerNormal) ||
         mesh.has_property<Halfedge>(prop::kCornerTexCoord);
}

CompressResult write_chunked(std::vector<Chunk>& chunks, const Streams& merges,
                             std::vector<std::uint32_t> global, const Quantiser& grid,
                             const SurfaceMesh& mesh) {
  ByteWriter w;
  for (std::uint8_t b : kMagic) w.u8(b);
  w.u8(kVersionChunked);
  w.u8(kFlagTwoLanes);  // of the merge map's rANS section; each chunk has its own flags
  w.varint(chunks.size());
  write_section(w, merges.rans);
  write_section(w, merges.raw);
  CompressResult r;
  CompressStats& s = r.stats;
  for (Chunk& c : chunks) {
    write_section(w, c.result.bytes);
    s.connectivity_bytes += c.result.stats.connectivity_bytes;
    s.geometry_bytes += c.result.stats.geometry_bytes;
    for (std::uint32_t f : c.result.face_permutation) r.face_permutation.push_back(c.faces[f]);
  }
  r.bytes = std::move(w.bytes());
  s.header_bytes = r.bytes.size() - s.connectivity_bytes - s.geometry_bytes;
  s.chunks = chunks.size();
  s.bits = grid.bits;
  s.step = grid.step;
  s.max_error = grid.max_error();
  s.predictor = chunks[0].result.stats.predictor;
  s.traversal = chunks[0].result.stats.traversal;
  s.dropped_properties = dropped_names(mesh);
  r.vertex_permutation = std::move(global);
  return r;
}

// ---- decoder ------------------------------------------------------------------------------

/// Decodes chunk k, naming offsets in the whole stream.
void decode_chunk(std::span<const std::uint8_t> bytes, std::span<const std::uint8_t> chunk,
                  std::size_t k, Core& core, Scratch& scratch) {
  const auto base = static_cast<std::uint64_t>(chunk.data() - bytes.data());
  try {
    decode_core_into(chunk, core, scratch, /*open_corners=*/true);
    const std::uint8_t extras = kFlagPreserveOrder | kFlagNormals | kFlagTexcoords | kFlagExtension;
    if (core.h.flags & extras)
      throw DecodeError(5, "a chunk may not carry attributes or an order section");
  } catch (const DecodeError& e) {
    const std::string what = e.what();
    const std::size_t colon = what.find(": ");
    throw DecodeError(base + e.offset(), "chunk " + std::to_string(k) + ": " +
                                             (colon == std::string::npos ? what : what.substr(colon + 2)));
  }
}

struct ChunkedLayout {
  std::span<const std::uint8_t> merge_rans, merge_raw;
  unsigned merge_lanes = 1;
  std::uint64_t merge_at = 0;
  std::vector<std::span<const std::uint8_t>> chunks;
};

ChunkedLayout read_layout(std::span<const std::uint8_t> bytes) {
  ByteReader r(bytes);
  for (int i = 0; i < 5; ++i) r.u8();  // magic and version: is_chunked
  const std::uint8_t flags = r.u8();
  if (flags & ~kFlagTwoLanes) throw DecodeError(r.offset() - 1, "unknown flags for version 3");
  const std::uint64_t n = r.varint();
  if (n < 2 || n > kMaxChunks || n > r.remaining())
    throw DecodeError(r.offset() - 1, "chunk count " + std::to_string(n) + " outside 2–" +
                                          std::to_string(kMaxChunks) + " or beyond the stream");
  ChunkedLayout l;
  l.merge_lanes = rans_lanes(flags);
  l.merge_at = r.offset();
  l.merge_rans = r.take(r.varint());
  l.merge_raw = r.take(r.varint());
  for (std::uint64_t k = 0; k < n; ++k) l.chunks.push_back(r.take(r.varint()));
  if (r.remaining() != 0) throw DecodeError(r.offset(), "trailing bytes after the last chunk");
  return l;
}

void check_chunks_agree(const std::vector<Core>& cores, const ChunkedLayout& l,
                        std::span<const std::uint8_t> bytes) {
  const Quantiser& g = cores[0].h.quantiser;
  for (std::size_t k = 0; k < cores.size(); ++k) {
    const auto at = static_cast<std::uint64_t>(l.chunks[k].data() - bytes.data());
    const Quantiser& c = cores[k].h.quantiser;
    if (c.bits != g.bits || c.step != g.step || c.origin != g.origin)
      throw DecodeError(at, "chunk " + std::to_string(k) + " has a grid other than chunk 0's");
    if (k + 1 < cores.size() && cores[k].h.n_isolated != 0)
      throw DecodeError(at, "chunk " + std::to_string(k) + " has isolated vertices (only the last may)");
  }
  // As for one stream: numbers and corners stay well inside 32 bits.
  std::uint64_t vertices = 0, triangles = 0;
  for (const Core& c : cores) vertices += c.h.n_vertices, triangles += c.h.n_triangles;
  if (vertices > (1u << 30) || triangles > (1u << 30))
    throw DecodeError(l.merge_at, "chunks hold more than 2^30 vertices or triangles in all");
}

/// One merged vertex: chunk k's vertex src is chunk j's vertex dst.
struct Merge {
  std::uint32_t src, j, dst;
};

/// Reads the merge map, checking that each merged pair has one grid point. ranked[k] is
/// chunk k's ranked_boundary.
std::vector<std::vector<Merge>> read_merges(const std::vector<Core>& cores,
                                            const std::vector<std::vector<std::uint32_t>>& ranked,
                                            const ChunkedLayout& l,
                                            std::span<const std::uint8_t> bytes) {
  const auto base = [&](std::span<const std::uint8_t> s) {
    return static_cast<std::uint64_t>(s.data() - bytes.data());
  };
  RansDecoder rd(l.merge_rans, base(l.merge_rans), l.merge_lanes);
  BitReader br(l.merge_raw, base(l.merge_raw));
  MergeModels m;
  std::vector<std::vector<Merge>> merges(cores.size());
  for (std::size_t k = 1; k < cores.size(); ++k) {
    const std::uint32_t count = m.count.decode(rd, br);
    if (count > ranked[k].size())
      throw DecodeError(rd.offset(), "more merged vertices than chunk boundary vertices");
    std::vector<std::int64_t> last(k, -1);
    std::int64_t prev = -1;
    for (std::uint32_t e = 0; e < count; ++e) {
      const std::int64_t r = prev + 1 + m.gap.decode(rd, br);
      const std::uint32_t back = m.chunk.decode(rd, br);
      if (r >= static_cast<std::int64_t>(ranked[k].size()) || back >= k)
        throw DecodeError(rd.offset(), "merge map entry out of range");
      const auto j = static_cast<std::uint32_t>(k - 1 - back);
      const std::int64_t t = last[j] + 1 + unzigzag(m.target.decode(rd, br));
      if (t < 0 || t >= static_cast<std::int64_t>(ranked[j].size()))
        throw DecodeError(rd.offset(), "merge map target out of range");
      const Merge e_k{ranked[k][static_cast<std::size_t>(r)], j, ranked[j][static_cast<std::size_t>(t)]};
      if (cores[k].q[e_k.src] != cores[j].q[e_k.dst])
        throw DecodeError(rd.offset(), "merge map joins vertices at different grid points");
      merges[k].push_back(e_k);
      last[j] = t;
      prev = r;
    }
  }
  rd.finish();
  return merges;
}

/// Global numbers: chunk 0's vertices, then each later chunk's unmerged ones, in order.
/// New numbers per chunk in parallel, then the (few) merged ones in chunk order, so a
/// merge into a vertex that is itself merged follows it.
std::vector<std::vector<std::uint32_t>> number_vertices(const std::vector<Core>& cores,
                                                        const std::vector<std::vector<Merge>>& merges,
                                                        std::vector<std::uint32_t>& first,
                                                        std::uint32_t& total) {
  const std::size_t n = cores.size();
  std::vector<std::vector<std::uint32_t>> global(n);
  first.assign(n + 1, 0);
  for (std::size_t k = 0; k < n; ++k)
    first[k + 1] = first[k] + static_cast<std::uint32_t>(cores[k].q.size() - merges[k].size());
  total = first[n];
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) {
    std::vector<std::uint32_t>& g = global[k];
    g.assign(cores[k].q.size(), 0);
    for (const Merge& e : merges[k]) g[e.src] = kNone;
    std::uint32_t next = first[k];
    for (std::uint32_t& x : g) x = x == kNone ? kNone : next++;
  });
  for (std::size_t k = 1; k < n; ++k)
    for (const Merge& e : merges[k]) global[k][e.src] = global[e.j][e.dst];
  return global;
}

/// Pairs the boundary corners (of different chunks) that face one edge from both sides.
void zip_seams(CornerTable& t, const std::vector<std::vector<std::uint32_t>>& open_corners,
               std::uint64_t where) {
  std::unordered_map<std::uint64_t, std::uint32_t> open;
  auto key = [](std::uint64_t a, std::uint64_t b) { return (a << 32) | b; };
  for (const auto& corners : open_corners)
    for (std::uint32_t c : corners)
      if (!open.emplace(key(t.vertex[next_corner(c)], t.vertex[prev_corner(c)]), c).second)
        throw DecodeError(where, "chunks repeat a directed edge");
  for (auto [k, c] : open) {
    if (t.opposite[c] != kNone) continue;
    const auto it = open.find(key(k & 0xffffffffu, k >> 32));
    if (it == open.end()) continue;
    t.opposite[c] = it->second;
    t.opposite[it->second] = c;
  }
}

Core merge(std::vector<Core>& cores, const std::vector<std::vector<std::uint32_t>>& global,
           std::uint32_t total, std::uint64_t where) {
  Core out;
  out.h = cores[0].h;
  out.h.flags = 0;
  out.h.n_faces = out.h.n_triangles = out.h.n_vertices = 0;
  std::vector<std::size_t> corner_at(cores.size() + 1, 0);
  for (std::size_t k = 0; k < cores.size(); ++k) {
    out.h.flags |= cores[k].h.flags & kFlagPolygons;
    out.h.n_faces += cores[k].h.n_faces;
    out.h.n_triangles += cores[k].h.n_triangles;
    corner_at[k + 1] = corner_at[k] + cores[k].table.vertex.size();
  }
  out.h.n_vertices = total;
  out.h.n_isolated = cores.back().h.n_isolated;
  // Chunk 0 keeps its numbers (it has no merges), so its arrays become the merged ones.
  CornerTable& t = out.table;
  t = std::move(cores[0].table);
  t.n_vertices = static_cast<std::uint32_t>(total - out.h.n_isolated);
  t.vertex.resize(corner_at.back());
  t.opposite.resize(corner_at.back());
  const bool polygons = out.h.flags & kFlagPolygons;
  if (polygons) t.diagonal.resize(corner_at.back(), 0);
  out.q = std::move(cores[0].q);
  out.q.resize(total);
  std::vector<std::vector<std::uint32_t>> open_corners(cores.size());
  tbb::parallel_for(std::size_t{0}, cores.size(), [&](std::size_t k) {
    const auto b = static_cast<std::uint32_t>(corner_at[k]);
    // The open corners the chunk's decode found (else a scan of its opposites, long out
    // of cache by now), in the merged numbering.
    const bool known = cores[k].open_corners_known;
    if (known) {
      open_corners[k] = std::move(cores[k].open_corners);
      for (std::uint32_t& c : open_corners[k]) c += b;
    }
    if (k == 0) {
      for (std::uint32_t i = 0; !known && i < corner_at[1]; ++i)
        if (t.opposite[i] == kNone) open_corners[0].push_back(i);
      return;
    }
    const CornerTable& c = cores[k].table;
    // Raw pointers: through the vectors, every push_back below might alias them, and the
    // compiler reloads their data pointers for every corner.
    const std::uint32_t *cv = c.vertex.data(), *co = c.opposite.data(), *g = global[k].data();
    std::uint32_t *tv = t.vertex.data() + b, *to = t.opposite.data() + b;
    for (std::uint32_t i = 0; i < c.vertex.size(); ++i) {
      tv[i] = g[cv[i]];
      to[i] = co[i] == kNone ? kNone : b + co[i];
      if (!known && co[i] == kNone) open_corners[k].push_back(b + i);
    }
    if (polygons && !c.diagonal.empty()) std::copy(c.diagonal.begin(), c.diagonal.end(), t.diagonal.begin() + b);
    QPoint* const q = out.q.data();
    for (std::size_t l = 0; l < cores[k].q.size(); ++l) q[g[l]] = cores[k].q[l];
    cores[k].table = {};
  });
  zip_seams(t, open_corners, where);
  out.connectivity_offset = where;
  return out;
}

}  // namespace

std::optional<CompressResult> compress_chunked(const SurfaceMesh& mesh,
                                               const CompressOptions& options,
                                               const FlatMesh& flat, const Quantiser& grid) {
  const std::size_t n_tri = flat.table.n_triangles();
  if (options.chunk_triangles == 0 || options.preserve_order ||
      n_tri < 2 * options.chunk_triangles || has_attributes(mesh) ||
      !options.vertex_origin.empty() ||  // compress() keeps it only when it joins vertices
      !options.loose_faces.empty() || options.keep_triangle_corners ||
      (options.keep_corner_order && flat.polygons))  // a chunk has no extension block
    return std::nullopt;
  // A power of two, so that the chunks share 2, 4, 8... cores evenly (3 chunks on 2 cores
  // would wait for the third).
  const std::size_t parts = std::bit_floor(std::min<std::size_t>(n_tri / options.chunk_triangles, kMaxChunks));
  std::vector<std::uint32_t> first_tri(flat.n_faces + 1, 0);  // a face's fan is consecutive
  for (std::uint32_t f : flat.triangle_face) ++first_tri[f + 1];
  for (std::size_t f = 0; f < flat.n_faces; ++f) first_tri[f + 1] += first_tri[f];
  std::vector<std::uint32_t> chunk_of(flat.n_faces);
  {
    std::vector<Centroid> centroids = face_centroids(flat, first_tri);
    split_faces(centroids, parts, 0, chunk_of);
  }
  std::vector<std::vector<std::uint32_t>> groups = group_faces(chunk_of, parts);
  std::vector<Chunk> chunks(parts);
  std::vector<std::uint64_t> place(n_tri);
  for (std::uint32_t k = 0; k < parts; ++k) {
    chunks[k].faces = std::move(groups[k]);
    std::uint32_t n = 0;
    for (std::uint32_t f : chunks[k].faces)
      for (std::uint32_t t = first_tri[f]; t < first_tri[f + 1]; ++t) place[t] = (std::uint64_t{k} << 32) | n++;
  }
  // One vertex map per thread (cut_chunk leaves it blank), not one per chunk.
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> local_of(
      [&] { return std::vector<std::uint32_t>(flat.positions.size(), kNone); });
  tbb::parallel_for(std::uint32_t{0}, static_cast<std::uint32_t>(parts), [&](std::uint32_t k) {
    cut_chunk(chunks[k], k, flat, first_tri, place, local_of.local());
  });
  add_isolated(chunks.back(), flat);
  if (!seams_distinct(chunks, flat.positions.size(), grid)) return std::nullopt;
  CompressOptions one = options;
  one.chunk_triangles = 0;
  const SurfaceMesh no_attributes;  // the chunks carry positions only
  tbb::parallel_for(std::size_t{0}, parts, [&](std::size_t k) {
    chunks[k].result = compress_on_grid(no_attributes, one, chunks[k].flat, grid);
  });
  Streams merges;
  std::vector<std::uint32_t> global = code_merges(chunks, flat.positions.size(), grid, merges);
  return write_chunked(chunks, merges, std::move(global), grid, mesh);
}

bool is_chunked(std::span<const std::uint8_t> bytes) {
  return bytes.size() > 4 && std::equal(kMagic, kMagic + 4, bytes.begin()) &&
         bytes[4] == kVersionChunked;
}

namespace {

/// Every chunk decoded (in parallel), checked against the others, and numbered globally.
struct DecodedChunks {
  explicit DecodedChunks(std::vector<Core>& in) : cores(in) {}
  std::vector<Core>& cores;  // the workspace's
  std::vector<std::vector<std::uint32_t>> global;  // per chunk: its vertices' global numbers
  std::vector<std::uint32_t> first;  // per chunk: its first own (unmerged) global number
  std::uint32_t total = 0;
  std::uint64_t where = 0;  // chunk 0's offset, for errors about the merged mesh
};

/// flat: the caller reads no opposites (see Workspace::spare_opposite).
DecodedChunks decode_chunks(std::span<const std::uint8_t> bytes, Workspace& ws, bool flat) {
  const ChunkedLayout l = read_layout(bytes);
  DecodedChunks d(ws.cores);
  d.cores.resize(l.chunks.size());
  std::vector<std::vector<std::uint32_t>> ranked(d.cores.size());
  std::vector<std::exception_ptr> failed(d.cores.size());
  tbb::parallel_for(std::size_t{0}, d.cores.size(), [&](std::size_t k) {
    try {
      Core& c = d.cores[k];
      std::vector<std::uint32_t>* spare = flat ? &ws.spare_opposite.local() : nullptr;
      if (spare) std::swap(c.table.opposite, *spare);
      decode_chunk(bytes, l.chunks[k], k, c, ws.scratch.local());
      ranked[k] = ranked_boundary(open_edges(c.table, c.open_corners_known ? &c.open_corners : nullptr), c.q).ranked;
      if (spare) std::swap(c.table.opposite, *spare);
    } catch (...) {
      failed[k] = std::current_exception();
    }
  });
  for (const std::exception_ptr& e : failed)  // the first chunk's error, whatever finished first
    if (e) std::rethrow_exception(e);
  check_chunks_agree(d.cores, l, bytes);
  const auto merges = read_merges(d.cores, ranked, l, bytes);
  d.global = number_vertices(d.cores, merges, d.first, d.total);
  d.where = static_cast<std::uint64_t>(l.chunks[0].data() - bytes.data());
  return d;
}

}  // namespace

Core decode_chunked(std::span<const std::uint8_t> bytes) {
  Workspace ws;
  DecodedChunks d = decode_chunks(bytes, ws, false);
  return merge(d.cores, d.global, d.total, d.where);
}

void decode_chunked_flat(std::span<const std::uint8_t> bytes, Workspace& ws, FlatDecode& out) {
  DecodedChunks d = decode_chunks(bytes, ws, true);
  if (ws.one_shot) {
    ws.scratch.clear();
    ws.spare_opposite.clear();
  }
  const std::size_t n = d.cores.size();
  std::vector<std::size_t> corner_at(n + 1, 0);
  for (std::size_t k = 0; k < n; ++k) corner_at[k + 1] = corner_at[k] + d.cores[k].table.vertex.size();
  // Sized without clearing (every element is written below), in the capacity of out's
  // previous contents when it has them (cleared first: growing then copies nothing). Sized
  // on two threads, so that a one-shot decode's allocations can take the blocks the chunks'
  // scratch left free in either thread's allocator arena rather than fresh pages.
  tbb::parallel_invoke(
      [&] {
        out.positions.clear();
        out.positions.resize(3 * std::size_t{d.total});
      },
      [&] {
        out.triangles.clear();
        out.triangles.resize(corner_at.back());
      });
  out.normals.clear();
  out.texcoords.clear();
  out.corner_normals.clear();  // chunks carry no extension block
  out.corner_texcoords.clear();
  const Quantiser& grid = d.cores[0].h.quantiser;  // every chunk's (check_chunks_agree)
  // No merged table: flat output needs no opposites, so the seams are never zipped. Each
  // chunk writes its own corners and its own vertices (merged ones are an earlier chunk's,
  // numbered below first[k], and written there), so no two tasks write one place.
  tbb::parallel_for(std::size_t{0}, n, [&](std::size_t k) {
    const Core& c = d.cores[k];
    const std::vector<std::uint32_t>& g = d.global[k];
    std::uint32_t* tri = out.triangles.data() + corner_at[k];
#pragma GCC unroll 4  // a load, a load and a store a corner: the loop's own steps count
    for (const std::uint32_t v : c.table.vertex) *tri++ = g[v];
    // Copies, which the compiler keeps in registers: the originals were reloaded per vertex.
    const Quantiser on = grid;
    float* const positions = out.positions.data();
    const std::uint32_t first = d.first[k];
    for (std::size_t v = 0; v < c.q.size(); ++v)
      if (g[v] >= first) on.dequantise_into(c.q[v], positions + 3 * std::size_t{g[v]});
  });
}

}  // namespace geom::codec::detail
