#include <geom/core/from_triangles.h>

#include <cstddef>
#include <vector>

namespace geom {
namespace {

constexpr std::uint32_t kNone = ~std::uint32_t{0};

// Corner c of triangle c / 3 is the directed edge from its vertex to the next corner's vertex;
// on clean input every corner becomes the halfedge with the same source and target.
// Everything about a vertex is decided from its own list of outgoing corners: the corner
// arriving at v from x is the twin of v's outgoing corner towards x, so twins and fans are
// found without looking at any other vertex's list.
class TriangleLinker {
 public:
  TriangleLinker(std::span<const Point> positions,
                 std::span<const std::array<std::uint32_t, 3>> triangles)
      : positions_(positions), tris_(triangles), nv_(positions.size()), nc_(3 * triangles.size()) {}

  // Each step returns false when the input is not a clean oriented manifold.
  bool index_outgoing();
  bool link_rings();
  SurfaceMesh link();

 private:
  struct Out {
    std::uint32_t to, from;  // corner c is v -> to; prev(c) is from -> v
    std::uint32_t corner;
  };
  std::uint32_t source(std::size_t c) const { return tris_[c / 3][c % 3]; }
  std::uint32_t target(std::size_t c) const { return tris_[c / 3][(c % 3 + 1) % 3]; }
  static std::size_t next(std::size_t c) { return c - c % 3 + (c % 3 + 1) % 3; }
  static std::size_t prev(std::size_t c) { return c - c % 3 + (c % 3 + 2) % 3; }
  bool link_ring(std::size_t v, std::vector<std::uint32_t>& turn);

  std::span<const Point> positions_;
  std::span<const std::array<std::uint32_t, 3>> tris_;
  std::size_t nv_, nc_;
  std::vector<std::uint32_t> first_;  // outgoing corners of v: out_[first_[v] .. first_[v + 1])
  std::vector<Out> out_;
  std::vector<std::uint32_t> twin_;    // the corner walking the same edge the other way
  std::vector<std::uint32_t> border_;  // the corner arriving at v with no twin, if any
};

bool TriangleLinker::index_outgoing() {
  // Corner and vertex indices must fit in 32 bits with room for kNone and a flag bit.
  if (nv_ >= kNone || nc_ >= kNone / 2) return false;
  first_.assign(nv_ + 1, 0);
  for (const auto& t : tris_) {
    if (t[0] >= nv_ || t[1] >= nv_ || t[2] >= nv_) return false;
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) return false;
    for (std::uint32_t v : t) ++first_[v + 1];
  }
  for (std::size_t v = 0; v < nv_; ++v) first_[v + 1] += first_[v];
  out_.resize(nc_);
  std::vector<std::uint32_t> cursor(first_.begin(), first_.end() - 1);
  for (std::uint32_t t = 0; t < tris_.size(); ++t)
    for (std::uint32_t i = 0; i < 3; ++i)
      out_[cursor[tris_[t][i]]++] = {tris_[t][(i + 1) % 3], tris_[t][(i + 2) % 3], 3 * t + i};
  return true;
}

// turn[i] is the ring position of the face after face i counter-clockwise around v.
bool TriangleLinker::link_ring(std::size_t v, std::vector<std::uint32_t>& turn) {
  const Out* ring = out_.data() + first_[v];
  const std::uint32_t degree = first_[v + 1] - first_[v];
  if (degree == 0) return true;  // isolated: kept, with no halfedge
  turn.assign(degree, kNone);
  std::uint32_t open = 0, start = 0;
  for (std::uint32_t i = 0; i < degree; ++i) {
    std::uint32_t to_from = kNone;
    for (std::uint32_t j = 0; j < degree; ++j) {
      if (j != i && ring[j].to == ring[i].to) return false;  // v -> to twice: flipped or a fin
      if (ring[j].to == ring[i].from) to_from = j;
    }
    const std::uint32_t in = static_cast<std::uint32_t>(prev(ring[i].corner));
    if (to_from == kNone) {
      ++open;
      border_[v] = in;
    } else {
      twin_[in] = ring[to_from].corner;
      turn[i] = to_from;
    }
  }
  if (open > 1) return false;  // several boundary gaps at v
  // With a gap, the fan starts at the face whose outgoing edge nothing turns onto.
  if (open == 1) {
    std::vector<std::uint8_t> reached(degree, 0);
    for (std::uint32_t t : turn)
      if (t != kNone) reached[t] = 1;
    while (reached[start]) ++start;
  }
  std::uint32_t seen = 0;
  for (std::uint32_t i = start;;) {
    ++seen;
    i = turn[i];
    if (i == kNone || i == start || seen > degree) break;
  }
  return seen == degree;  // otherwise a second fan (closed or not) shares v
}

bool TriangleLinker::link_rings() {
  twin_.assign(nc_, kNone);
  border_.assign(nv_, kNone);
  std::vector<std::uint32_t> turn;
  for (std::size_t v = 0; v < nv_; ++v)
    if (!link_ring(v, turn)) return false;
  return true;
}

SurfaceMesh TriangleLinker::link() {
  // Halfedge of each corner, in place of its twin; edges numbered in order of first use, as
  // add_triangle numbers them. The top bit marks a corner on the boundary.
  constexpr std::uint32_t kOpen = 0x80000000u, kId = ~kOpen;
  std::uint32_t edges = 0;
  std::vector<std::uint32_t>& he = twin_;
  for (std::size_t c = 0; c < nc_; ++c) {
    const std::uint32_t t = twin_[c];
    he[c] = t == kNone ? (2 * edges++) | kOpen : t < c ? (he[t] & kId) ^ 1u : 2 * edges++;
  }

  SurfaceMesh mesh;
  mesh.resize(nv_, edges, tris_.size());
  auto points = mesh.positions();
  for (std::size_t v = 0; v < nv_; ++v) points[Vertex(static_cast<std::uint32_t>(v))] = positions_[v];
  for (std::size_t c = 0; c < nc_; ++c) {
    const Halfedge h(he[c] & kId);
    const Face f(static_cast<std::uint32_t>(c / 3));
    mesh.set_vertex(h, Vertex(target(c)));
    mesh.set_face(h, f);
    mesh.set_next(h, Halfedge(he[next(c)] & kId));
    if (c % 3 == 2) mesh.set_halfedge(f, h);  // ends at the first corner, as add_face does
    if (!(he[c] & kOpen)) continue;
    // The boundary halfedge b -> a continues along the boundary halfedge leaving a.
    const Halfedge border(h.idx() ^ 1u);
    mesh.set_vertex(border, Vertex(source(c)));
    mesh.set_next(border, Halfedge((he[border_[source(c)]] & kId) ^ 1u));
  }
  for (std::size_t v = 0; v < nv_; ++v) {
    if (first_[v] == first_[v + 1]) continue;
    const Vertex vh(static_cast<std::uint32_t>(v));
    if (border_[v] != kNone)
      mesh.set_halfedge(vh, Halfedge((he[border_[v]] & kId) ^ 1u));
    else
      mesh.set_halfedge(vh, Halfedge(he[out_[first_[v]].corner] & kId));
  }
  return mesh;
}

SurfaceMesh add_one_by_one(std::span<const Point> positions,
                           std::span<const std::array<std::uint32_t, 3>> triangles) {
  SurfaceMesh mesh;
  mesh.reserve(positions.size(), triangles.size() * 3 / 2 + 3, triangles.size());
  for (const Point& p : positions) mesh.add_vertex(p);
  for (const auto& t : triangles) mesh.add_triangle(Vertex(t[0]), Vertex(t[1]), Vertex(t[2]));
  return mesh;
}

}  // namespace

SurfaceMesh mesh_from_triangles(std::span<const Point> positions,
                                std::span<const std::array<std::uint32_t, 3>> triangles) {
  TriangleLinker linker(positions, triangles);
  if (linker.index_outgoing() && linker.link_rings()) return linker.link();
  return add_one_by_one(positions, triangles);
}

}  // namespace geom
