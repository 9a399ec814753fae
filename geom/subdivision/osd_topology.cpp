// OpenSubdiv's edge instances and non-manifold tags of a soup, replayed corner by corner in
// its order so that edge numbers, orientations and tags are the ones Far would make.

#include <geom/subdivision/osd_topology.h>

#include <geom/subdivision/creases.h>
#include <geom/subdivision/union_find.h>

#include <algorithm>

namespace geom::detail::subdiv {
namespace {

constexpr std::uint32_t kNoEdge = 0xffffffffu;

class Replay {
 public:
  Replay(const PolygonSoup& soup, OsdTopology& t) : soup_(soup), t_(t) {
    vertex_edges_.resize(soup.positions.size());
  }

  // Far's edge creation: an edge is found among v0's edges; a degenerate edge, or one the
  // same face already used, is a new instance. A third face, a second face running the
  // same way, and both instances of a repeated edge are non-manifold.
  void create_edges() {
    const std::size_t nf = soup_.n_faces();
    t_.corner_edge.resize(soup_.face_indices.size());
    for (std::size_t f = 0; f < nf; ++f) {
      const std::uint32_t b = soup_.face_offsets[f], n = soup_.face_offsets[f + 1] - b;
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t v0 = soup_.face_indices[b + i];
        const std::uint32_t v1 = soup_.face_indices[b + (i + 1) % n];
        std::uint32_t e = v0 == v1 ? kNoEdge : find_edge(v0, v1);
        if (v0 == v1) nonmanifold_.push_back(static_cast<std::uint32_t>(t_.n_edges()));
        if (e != kNoEdge) {
          if (last_face_[e] == f) {
            nonmanifold_.push_back(e);
            nonmanifold_.push_back(static_cast<std::uint32_t>(t_.n_edges()));
            e = kNoEdge;
          } else if (t_.edge_faces[e] > 1 || t_.edge_vertices[e][0] == v0) {
            nonmanifold_.push_back(e);
          }
        }
        if (e == kNoEdge) e = new_edge(v0, v1);
        ++t_.edge_faces[e];
        last_face_[e] = static_cast<std::uint32_t>(f);
        t_.corner_edge[b + i] = e;
      }
    }
    t_.edge_nonmanifold.assign(t_.n_edges(), 0);
    t_.vertex_nonmanifold.assign(soup_.positions.size(), 0);
    for (std::uint32_t e : nonmanifold_) {
      t_.edge_nonmanifold[e] = 1;
      t_.vertex_nonmanifold[t_.edge_vertices[e][0]] = 1;
      t_.vertex_nonmanifold[t_.edge_vertices[e][1]] = 1;
    }
  }

  // A vertex no non-manifold edge touches is still non-manifold unless its corners form
  // one fan (joined across the two-face edges), or when no face uses it.
  void tag_fans() {
    const std::size_t nc = soup_.face_indices.size();
    UnionFind fans(nc);
    std::vector<std::uint32_t> first(t_.n_edges(), kNoEdge);
    for (std::size_t f = 0; f < soup_.n_faces(); ++f) {
      const std::uint32_t b = soup_.face_offsets[f], n = soup_.face_offsets[f + 1] - b;
      for (std::uint32_t i = 0; i < n; ++i) {
        const std::uint32_t c = b + i, e = t_.corner_edge[c];
        if (t_.edge_nonmanifold[e]) continue;
        if (first[e] == kNoEdge) {
          first[e] = c;
          continue;
        }
        // Corner d runs v0 → v1 in the first face; c runs v1 → v0 in this one.
        const std::uint32_t d = first[e];
        const std::uint32_t d_next = next_corner(d), c_next = b + (i + 1) % n;
        fans.unite(d, c_next);
        fans.unite(d_next, c);
      }
    }
    std::vector<std::uint32_t> root(soup_.positions.size(), kNoEdge);
    std::vector<std::uint8_t> used(soup_.positions.size(), 0);
    t_.corner_fan.resize(nc);
    for (std::uint32_t c = 0; c < nc; ++c) {
      const std::uint32_t v = soup_.face_indices[c], r = fans.find(c);
      t_.corner_fan[c] = r;
      used[v] = 1;
      if (root[v] == kNoEdge) root[v] = r;
      else if (root[v] != r) t_.vertex_nonmanifold[v] = 1;
    }
    for (std::size_t v = 0; v < used.size(); ++v)
      if (!used[v]) t_.vertex_nonmanifold[v] = 1;
  }

  // prepareComponentTagsAndSharpness: boundary and non-manifold edges become infinitely
  // sharp; a non-manifold vertex too, unless it lies inside a non-manifold crease (two
  // non-manifold edges, no boundary, more faces than edges).
  void sharpen(bool sharpen_corners) {
    const std::size_t nv = soup_.positions.size();
    t_.edge_sharpness.assign(t_.n_edges(), kSmooth);
    t_.vertex_sharpness.assign(nv, kSmooth);
    for (const EdgeSharpness& c : soup_.creases)
      if (c.a < nv && c.b < nv)
        if (std::uint32_t e = find_edge(c.a, c.b); e != kNoEdge)
          t_.edge_sharpness[e] = to_float(c.sharpness);
    for (const VertexSharpness& c : soup_.corners)
      if (c.v < nv) t_.vertex_sharpness[c.v] = to_float(c.sharpness);
    std::vector<std::uint32_t> faces(nv, 0), edges(nv, 0), boundary(nv, 0), nonmanifold(nv, 0);
    for (std::uint32_t v : soup_.face_indices) ++faces[v];
    for (std::size_t e = 0; e < t_.n_edges(); ++e) {
      const bool is_boundary = t_.edge_faces[e] < 2;
      if (is_boundary || t_.edge_nonmanifold[e]) t_.edge_sharpness[e] = kInfinite;
      for (std::uint32_t v : t_.edge_vertices[e]) {
        ++edges[v];
        boundary[v] += is_boundary;
        nonmanifold[v] += t_.edge_nonmanifold[e];
      }
    }
    for (std::size_t v = 0; v < nv; ++v) {
      const bool corner = faces[v] == 1 && edges[v] == 2;
      const bool crease_inside = nonmanifold[v] == 2 && boundary[v] == 0 && faces[v] > edges[v];
      if ((corner && sharpen_corners) || (t_.vertex_nonmanifold[v] && !crease_inside))
        t_.vertex_sharpness[v] = kInfinite;
    }
  }

 private:
  static float to_float(double s) {
    return s >= kInfinite ? kInfinite : (s > 0.0 ? static_cast<float>(s) : kSmooth);
  }

  std::uint32_t find_edge(std::uint32_t v0, std::uint32_t v1) const {
    for (std::uint32_t e : vertex_edges_[v0]) {
      const auto& ev = t_.edge_vertices[e];
      if (v0 != v1 ? (ev[0] == v1 || ev[1] == v1) : ev[0] == ev[1]) return e;
    }
    return kNoEdge;
  }

  std::uint32_t new_edge(std::uint32_t v0, std::uint32_t v1) {
    const auto e = static_cast<std::uint32_t>(t_.n_edges());
    t_.edge_vertices.push_back({v0, v1});
    t_.edge_faces.push_back(0);
    last_face_.push_back(kNoEdge);
    vertex_edges_[v0].push_back(e);
    vertex_edges_[v1].push_back(e);
    return e;
  }

  std::uint32_t next_corner(std::uint32_t c) const {
    const auto it = std::upper_bound(soup_.face_offsets.begin(), soup_.face_offsets.end(), c);
    const std::uint32_t end = *it, begin = *(it - 1);
    return c + 1 == end ? begin : c + 1;
  }

  const PolygonSoup& soup_;
  OsdTopology& t_;
  std::vector<std::vector<std::uint32_t>> vertex_edges_;
  std::vector<std::uint32_t> last_face_, nonmanifold_;
};

}  // namespace

std::size_t OsdTopology::nonmanifold_edges() const {
  return static_cast<std::size_t>(std::count(edge_nonmanifold.begin(), edge_nonmanifold.end(), 1));
}

std::size_t OsdTopology::degenerate_edges() const {
  return static_cast<std::size_t>(std::count_if(edge_vertices.begin(), edge_vertices.end(),
                                                [](const auto& ev) { return ev[0] == ev[1]; }));
}

std::size_t OsdTopology::nonmanifold_vertices() const {
  std::vector<std::uint8_t> touched(vertex_nonmanifold.size(), 0);
  for (const auto& ev : edge_vertices) touched[ev[0]] = touched[ev[1]] = 1;
  std::size_t n = 0;
  for (std::size_t v = 0; v < touched.size(); ++v) n += touched[v] && vertex_nonmanifold[v];
  return n;
}

OsdTopology osd_topology(const PolygonSoup& soup, bool sharpen_corners) {
  OsdTopology t;
  Replay replay(soup, t);
  replay.create_edges();
  replay.tag_fans();
  replay.sharpen(sharpen_corners);
  return t;
}

}  // namespace geom::detail::subdiv
