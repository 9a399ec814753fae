#pragma once
// Independent topology checks for triangle arrays (edge counting; no geom::core analysis), so
// the iso-surface tests do not trust the code they test.

#include <geom/isosurface/marching_cubes.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace geom::test {

struct SurfaceCheck {
  std::size_t vertices = 0, edges = 0, faces = 0;
  std::size_t boundary_edges = 0;          ///< directed edges without a reverse
  std::size_t repeated_directed_edges = 0; ///< a→b used by two triangles (orientation or >2 faces)
  std::size_t nonmanifold_vertices = 0;    ///< link is not one cycle/chain
  std::size_t unused_vertices = 0;
  std::size_t degenerate_triangles = 0;    ///< repeated index or zero area
  std::size_t coincident_vertices = 0;     ///< distinct vertices at the same position
  double signed_volume = 0;                ///< Σ over triangles of det(a, b, c)/6
  long euler() const { return long(vertices) - long(edges) + long(faces); }
  bool manifold() const {
    return repeated_directed_edges == 0 && nonmanifold_vertices == 0 && degenerate_triangles == 0;
  }
  bool closed_manifold() const { return manifold() && boundary_edges == 0; }
  std::string summary() const {
    return "V=" + std::to_string(vertices) + " E=" + std::to_string(edges) +
           " F=" + std::to_string(faces) + " boundary=" + std::to_string(boundary_edges) +
           " repeated=" + std::to_string(repeated_directed_edges) +
           " nonmanifold_v=" + std::to_string(nonmanifold_vertices) +
           " unused=" + std::to_string(unused_vertices) +
           " degenerate=" + std::to_string(degenerate_triangles) +
           " coincident=" + std::to_string(coincident_vertices) +
           " chi=" + std::to_string(euler());
  }
};

inline SurfaceCheck check_surface(const std::vector<Point>& positions,
                                  const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  SurfaceCheck r;
  r.vertices = positions.size();
  r.faces = triangles.size();
  std::vector<std::uint64_t> directed;
  directed.reserve(3 * triangles.size());
  std::vector<std::uint8_t> used(positions.size(), 0);
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) {
      directed.push_back(std::uint64_t(t[k]) << 32 | t[(k + 1) % 3]);
      used[t[k]] = 1;
    }
    const Point &a = positions[t[0]], &b = positions[t[1]], &c = positions[t[2]];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || (b - a).cross(c - a).norm() == 0.0)
      ++r.degenerate_triangles;
    r.signed_volume += a.dot(b.cross(c)) / 6.0;
  }
  for (auto u : used) r.unused_vertices += u == 0;
  std::sort(directed.begin(), directed.end());
  for (std::size_t i = 0; i + 1 < directed.size(); ++i)
    r.repeated_directed_edges += directed[i] == directed[i + 1];
  std::size_t twice = 0;
  for (std::uint64_t e : directed) {
    std::uint64_t rev = (e << 32) | (e >> 32);
    if (std::binary_search(directed.begin(), directed.end(), rev))
      ++twice;
    else
      ++r.boundary_edges;
  }
  r.edges = twice / 2 + r.boundary_edges;

  // Vertex links: around v, triangle (v, a, b) contributes link edge a → b. A manifold vertex
  // has a link that is one cycle, or one chain on the boundary.
  std::vector<std::vector<std::pair<std::uint32_t, std::uint32_t>>> link(positions.size());
  for (const auto& t : triangles)
    for (int k = 0; k < 3; ++k) link[t[k]].push_back({t[(k + 1) % 3], t[(k + 2) % 3]});
  for (std::size_t v = 0; v < positions.size(); ++v) {
    auto& l = link[v];
    if (l.empty()) continue;
    // Walk from a chain start (a link vertex with no incoming link edge) or anywhere.
    std::size_t start = 0;
    for (std::size_t i = 0; i < l.size(); ++i) {
      bool has_in = false;
      for (const auto& e : l) has_in |= e.second == l[i].first;
      if (!has_in) start = i;
    }
    std::size_t visited = 0;
    std::uint32_t cur = l[start].first;
    std::vector<bool> seen(l.size(), false);
    for (;;) {
      std::size_t found = l.size();
      for (std::size_t i = 0; i < l.size(); ++i)
        if (!seen[i] && l[i].first == cur) found = i;
      if (found == l.size()) break;
      seen[found] = true;
      ++visited;
      cur = l[found].second;
    }
    if (visited != l.size()) ++r.nonmanifold_vertices;
  }

  std::vector<std::size_t> order(positions.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto less = [&](std::size_t a, std::size_t b) {
    const Point &p = positions[a], &q = positions[b];
    return std::tie(p.x(), p.y(), p.z()) < std::tie(q.x(), q.y(), q.z());
  };
  std::sort(order.begin(), order.end(), less);
  for (std::size_t i = 0; i + 1 < order.size(); ++i)
    r.coincident_vertices += positions[order[i]] == positions[order[i + 1]];
  return r;
}

inline SurfaceCheck check_surface(const IsoSurface& s) { return check_surface(s.positions, s.triangles); }

/// Boundary edges whose two ends are not on one outer face of the grid (a surface cut by
/// the grid ends there and nowhere else).
inline std::size_t boundary_edges_off_grid_boundary(const GridView& g, const IsoSurface& s) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> count;
  for (const auto& t : s.triangles)
    for (int k = 0; k < 3; ++k) ++count[{std::min(t[k], t[(k + 1) % 3]), std::max(t[k], t[(k + 1) % 3])}];
  std::size_t bad = 0;
  for (const auto& [e, c] : count) {
    if (c != 1) continue;
    const Point &a = s.positions[e.first], &b = s.positions[e.second];
    // Both ends on the same outer plane.
    bool same_plane = false;
    for (int k = 0; k < 3; ++k) {
      std::size_t n = k == 0 ? g.dims.nx : k == 1 ? g.dims.ny : g.dims.nz;
      double lo = g.geometry.origin[k], hi = lo + g.geometry.spacing[k] * double(n - 1);
      same_plane |= (a[k] == lo && b[k] == lo) || (a[k] == hi && b[k] == hi);
    }
    bad += !same_plane;
  }
  return bad;
}

/// Triangles as position triples, each rotated to start at its smallest corner, sorted.
inline std::vector<std::array<std::array<double, 3>, 3>> triangle_set(const IsoSurface& s) {
  std::vector<std::array<std::array<double, 3>, 3>> out;
  for (const auto& t : s.triangles) {
    std::array<std::array<double, 3>, 3> tri;
    for (int k = 0; k < 3; ++k) {
      const Point& p = s.positions[t[k]];
      tri[k] = {p.x(), p.y(), p.z()};
    }
    while (!(tri[0] <= tri[1] && tri[0] <= tri[2])) std::rotate(tri.begin(), tri.begin() + 1, tri.end());
    out.push_back(tri);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace geom::test
