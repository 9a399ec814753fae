#pragma once
// Procedural meshes for the codec tests: open grids, closed tori, a voxel slab of high genus
// (quads or triangles), mixed polygons, several components, shuffled element order.

#include <geom/core/surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numeric>
#include <random>
#include <vector>

namespace geom::test {

/// A mesh as plain arrays, so tests can shuffle before building.
struct Arrays {
  std::vector<Point> points;
  std::vector<std::vector<std::uint32_t>> faces;

  void append(const Arrays& o, const Eigen::Vector3d& shift = Eigen::Vector3d::Zero()) {
    const auto base = static_cast<std::uint32_t>(points.size());
    for (const Point& p : o.points) points.push_back(p + shift);
    for (auto f : o.faces) {
      for (auto& v : f) v += base;
      faces.push_back(f);
    }
  }
  SurfaceMesh build() const {
    SurfaceMesh m;
    std::vector<Vertex> vs;
    for (const Point& p : points) vs.push_back(m.add_vertex(p));
    std::vector<Vertex> c;
    for (const auto& f : faces) {
      c.clear();
      for (auto v : f) c.push_back(vs[v]);
      m.add_face(c);
    }
    return m;
  }
  /// Random vertex numbering, face order and first corners.
  Arrays shuffled(unsigned seed) const {
    std::mt19937 rng(seed);
    std::vector<std::uint32_t> perm(points.size());
    std::iota(perm.begin(), perm.end(), 0u);
    std::shuffle(perm.begin(), perm.end(), rng);
    Arrays out;
    out.points.resize(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) out.points[perm[i]] = points[i];
    out.faces = faces;
    for (auto& f : out.faces) {
      for (auto& v : f) v = perm[v];
      std::rotate(f.begin(), f.begin() + rng() % f.size(), f.end());
    }
    std::shuffle(out.faces.begin(), out.faces.end(), rng);
    return out;
  }
};

inline Arrays grid(int nx, int ny, bool quads = false) {
  Arrays a;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) a.points.push_back({i * 1.0, j * 1.0, 0.1 * std::sin(i + 2.0 * j)});
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if (quads) {
        a.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      } else {
        a.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        a.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    }
  return a;
}

inline Arrays torus(int nu, int nv, double R = 3.0, double r = 1.0) {
  Arrays a;
  const double pi = std::acos(-1.0);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double u = 2 * pi * i / nu, v = 2 * pi * j / nv;
      a.points.push_back({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
                          r * std::sin(v)});
    }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>((j % nv) * nu + (i % nu)); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      a.faces.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      a.faces.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return a;
}

/// A spindle of `rings` rings of n vertices (radii wobbling), capped by an apex of valence n
/// at the top and, when closed, at the bottom too (else the last ring is a boundary loop):
/// vertices of hundreds of triangles, rare in scans but legal.
inline Arrays spindle(int n, int rings, bool closed) {
  Arrays a;
  const double pi = std::acos(-1.0);
  for (int k = 0; k < rings; ++k)
    for (int i = 0; i < n; ++i) {
      const double u = 2 * pi * i / n, r = 1.0 + 0.1 * std::sin(7.0 * u + k) + 0.3 * k;
      a.points.push_back({r * std::cos(u), r * std::sin(u), -0.5 * k});
    }
  auto id = [&](int k, int i) { return static_cast<std::uint32_t>(k * n + (i % n)); };
  const auto top = static_cast<std::uint32_t>(a.points.size());
  a.points.push_back({0.0, 0.0, 1.0});
  for (int i = 0; i < n; ++i) a.faces.push_back({top, id(0, i), id(0, i + 1)});
  for (int k = 0; k + 1 < rings; ++k)
    for (int i = 0; i < n; ++i) {
      a.faces.push_back({id(k, i), id(k + 1, i), id(k + 1, i + 1)});
      a.faces.push_back({id(k, i), id(k + 1, i + 1), id(k, i + 1)});
    }
  if (closed) {
    const auto bottom = static_cast<std::uint32_t>(a.points.size());
    a.points.push_back({0.0, 0.0, -0.5 * rings});
    for (int i = 0; i < n; ++i) a.faces.push_back({bottom, id(rings - 1, i + 1), id(rings - 1, i)});
  }
  return a;
}

/// The boundary of a (2k+1)×(2k+1)×1 voxel slab with a hole at every (odd, odd) column:
/// a closed quad mesh of genus k². Optionally triangulated.
inline Arrays holey_slab(int k, bool triangles) {
  const int n = 2 * k + 1;
  auto filled = [&](int x, int y, int z) {
    if (x < 0 || y < 0 || z != 0 || x >= n || y >= n) return false;
    return !(x % 2 == 1 && y % 2 == 1);
  };
  Arrays a;
  std::map<std::array<int, 3>, std::uint32_t> ids;
  auto id = [&](int x, int y, int z) {
    auto [it, fresh] = ids.try_emplace({x, y, z}, static_cast<std::uint32_t>(a.points.size()));
    if (fresh) a.points.push_back({x * 1.0, y * 1.0, z * 1.0});
    return it->second;
  };
  const int dirs[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (int x = 0; x < n; ++x)
    for (int y = 0; y < n; ++y) {
      if (!filled(x, y, 0)) continue;
      for (const auto& d : dirs) {
        if (filled(x + d[0], y + d[1], d[2])) continue;
        // The face on side d, wound counter-clockwise seen from outside.
        const int axis = d[0] ? 0 : d[1] ? 1 : 2;
        const int s = d[0] + d[1] + d[2];
        const int u = (axis + 1) % 3, v = (axis + 2) % 3;
        std::array<int, 3> base = {x, y, 0};
        if (s > 0) base[axis] += 1;
        std::array<std::array<int, 3>, 4> c;
        for (int q = 0; q < 4; ++q) c[q] = base;
        c[1][u] += 1;
        c[2][u] += 1;
        c[2][v] += 1;
        c[3][v] += 1;
        if (s < 0) std::swap(c[1], c[3]);
        std::vector<std::uint32_t> f;
        for (auto& p : c) f.push_back(id(p[0], p[1], p[2]));
        if (triangles) {
          a.faces.push_back({f[0], f[1], f[2]});
          a.faces.push_back({f[0], f[2], f[3]});
        } else {
          a.faces.push_back(f);
        }
      }
    }
  return a;
}

/// Triangles, quads and a pentagon: a fan of polygons around a centre.
inline Arrays mixed_polygons() {
  Arrays a;
  a.points = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {-2, 2, 0}, {-2, 0, 0},
              {-2, -2, 0}, {0, -2, 0}, {2, -2, 0}, {3, 1, 0}, {1, 3, 0.5}};
  a.faces = {{0, 1, 9, 2}, {0, 2, 10, 3}, {0, 3, 4, 5}, {0, 5, 6}, {0, 6, 7}, {0, 7, 8, 1}};
  return a;
}

}  // namespace geom::test
