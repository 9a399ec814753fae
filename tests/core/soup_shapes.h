#pragma once
// Procedural polygon soups with known topology, for the build and topology tests.

#include <geom/core/soup.h>

#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <tuple>
#include <vector>

namespace geom::test {

inline PolygonSoup tetrahedron_soup() {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  s.add_face({0, 2, 1});
  s.add_face({0, 1, 3});
  s.add_face({1, 2, 3});
  s.add_face({2, 0, 3});
  return s;
}

/// The outward-oriented boundary surface of a set of unit voxels (cells (x, y, z) with
/// filled(x, y, z)), as quads on the shared integer lattice.
template <class Filled>
PolygonSoup voxel_surface(int nx, int ny, int nz, Filled filled) {
  PolygonSoup s;
  std::map<std::tuple<int, int, int>, std::uint32_t> ids;
  auto vid = [&](int x, int y, int z) {
    auto [it, fresh] = ids.try_emplace({x, y, z}, static_cast<std::uint32_t>(s.positions.size()));
    if (fresh) s.positions.push_back(Point(x, y, z));
    return it->second;
  };
  auto in = [&](int x, int y, int z) {
    return x >= 0 && y >= 0 && z >= 0 && x < nx && y < ny && z < nz && filled(x, y, z);
  };
  for (int z = 0; z < nz; ++z)
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        if (!in(x, y, z)) continue;
        // For each axis and side, a quad counter-clockwise seen from outside.
        if (!in(x - 1, y, z))
          s.add_face({vid(x, y, z), vid(x, y, z + 1), vid(x, y + 1, z + 1), vid(x, y + 1, z)});
        if (!in(x + 1, y, z))
          s.add_face({vid(x + 1, y, z), vid(x + 1, y + 1, z), vid(x + 1, y + 1, z + 1), vid(x + 1, y, z + 1)});
        if (!in(x, y - 1, z))
          s.add_face({vid(x, y, z), vid(x + 1, y, z), vid(x + 1, y, z + 1), vid(x, y, z + 1)});
        if (!in(x, y + 1, z))
          s.add_face({vid(x, y + 1, z), vid(x, y + 1, z + 1), vid(x + 1, y + 1, z + 1), vid(x + 1, y + 1, z)});
        if (!in(x, y, z - 1))
          s.add_face({vid(x, y, z), vid(x, y + 1, z), vid(x + 1, y + 1, z), vid(x + 1, y, z)});
        if (!in(x, y, z + 1))
          s.add_face({vid(x, y, z + 1), vid(x + 1, y, z + 1), vid(x + 1, y + 1, z + 1), vid(x, y + 1, z + 1)});
      }
  return s;
}

inline PolygonSoup cube_soup() {
  return voxel_surface(1, 1, 1, [](int, int, int) { return true; });
}

/// A (2k+1) × 3 × 1 plate of voxels with k one-voxel holes: a closed surface of genus k.
inline PolygonSoup holed_plate(int k) {
  return voxel_surface(2 * k + 1, 3, 1, [](int x, int y, int) { return !(y == 1 && x % 2 == 1); });
}

/// A triangulated parametric torus with n × m quads split into triangles (closed, genus 1).
/// With `cut`, face pair 0 is left out (one hole: H = 1, G = 1).
inline PolygonSoup torus_soup(int n, int m, bool cut = false) {
  PolygonSoup s;
  const double pi = std::numbers::pi;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      double u = 2 * pi * i / n, v = 2 * pi * j / m;
      s.positions.push_back(Point((2 + std::cos(v)) * std::cos(u), (2 + std::cos(v)) * std::sin(u), std::sin(v)));
    }
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      if (cut && i == 0 && j == 0) continue;
      s.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.add_face({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return s;
}

/// An n × n grid of triangles in the plane z = 0: a disk (H = 1, G = 0).
inline PolygonSoup disk_soup(int n) {
  PolygonSoup s;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) s.positions.push_back(Point(i, j, 0));
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      s.add_face({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      s.add_face({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return s;
}

/// A planar ring of n × r quads (H = 2, G = 0).
inline PolygonSoup annulus_soup(int n, int r) {
  PolygonSoup s;
  const double pi = std::numbers::pi;
  for (int k = 0; k <= r; ++k)
    for (int i = 0; i < n; ++i) {
      double a = 2 * pi * i / n, rad = 1.0 + k;
      s.positions.push_back(Point(rad * std::cos(a), rad * std::sin(a), 0));
    }
  auto id = [&](int i, int k) { return static_cast<std::uint32_t>(k * n + (i % n)); };
  for (int k = 0; k < r; ++k)
    for (int i = 0; i < n; ++i) s.add_face({id(i, k), id(i + 1, k), id(i + 1, k + 1), id(i, k + 1)});
  return s;
}

/// A Möbius band of n quads (non-orientable, one boundary loop). Faces are listed with
/// consistent local orientation except across the twist, which no orientation can fix.
inline PolygonSoup moebius_soup(int n) {
  PolygonSoup s;
  const double pi = std::numbers::pi;
  for (int i = 0; i < n; ++i) {
    double u = 2 * pi * i / n;
    for (int side = 0; side < 2; ++side) {
      double t = side ? 0.5 : -0.5;
      s.positions.push_back(Point((2 + t * std::cos(u / 2)) * std::cos(u),
                                  (2 + t * std::cos(u / 2)) * std::sin(u), t * std::sin(u / 2)));
    }
  }
  for (int i = 0; i < n; ++i) {
    std::uint32_t a0 = 2 * i, a1 = 2 * i + 1;
    std::uint32_t b0 = 2 * ((i + 1) % n), b1 = b0 + 1;
    if (i == n - 1) std::swap(b0, b1);  // the half twist
    s.add_face({a0, b0, b1, a1});
  }
  return s;
}

/// Two triangles sharing only vertex 0.
inline PolygonSoup bowtie_soup() {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
  s.add_face({0, 1, 2});
  s.add_face({0, 3, 4});
  return s;
}

/// Three triangles on edge (0, 1).
inline PolygonSoup three_fin_soup() {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1}};
  s.add_face({0, 1, 2});
  s.add_face({1, 0, 3});
  s.add_face({0, 1, 4});
  return s;
}

/// Append b to a (indices shifted).
inline PolygonSoup merged(PolygonSoup a, const PolygonSoup& b) {
  auto shift = static_cast<std::uint32_t>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (std::size_t f = 0; f < b.n_faces(); ++f) {
    std::vector<std::uint32_t> c(b.face(f).begin(), b.face(f).end());
    for (auto& x : c) x += shift;
    a.add_face(c);
  }
  return a;
}

/// The soup with every vertex moved by `offset`.
inline PolygonSoup translated(PolygonSoup s, const Point& offset) {
  for (auto& p : s.positions) p += offset;
  return s;
}

}  // namespace geom::test
