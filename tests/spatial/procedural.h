#pragma once
// Procedural test meshes shared by the spatial and lod tests (seeded, no files).

#include <geom/core/surface_mesh.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

namespace geom::test {

/// Torus with nu × nv quads split into triangles; noise > 0 jitters each vertex radially
/// by up to noise × r (seeded).
inline SurfaceMesh torus(int nu, int nv, double big_r = 1.0, double small_r = 0.35,
                         double noise = 0.0, unsigned seed = 7) {
  SurfaceMesh m;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  std::vector<Vertex> vs;
  vs.reserve(static_cast<std::size_t>(nu) * nv);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double a = 2 * std::numbers::pi * i / nu, b = 2 * std::numbers::pi * j / nv;
      const double rr = small_r * (1.0 + (noise > 0 ? noise * uni(rng) : 0.0));
      vs.push_back(m.add_vertex(Point((big_r + rr * std::cos(b)) * std::cos(a),
                                      (big_r + rr * std::cos(b)) * std::sin(a), rr * std::sin(b))));
    }
  auto at = [&](int i, int j) { return vs[static_cast<std::size_t>((i % nu) * nv + (j % nv))]; };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      m.add_triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      m.add_triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return m;
}

/// Flat n × n grid of unit-square cells split into triangles, in z = 0 (one boundary loop).
/// Cells (i, j) with skip(i, j) true are left out (holes).
template <class Skip>
SurfaceMesh grid(int n, Skip skip, double z_amplitude = 0.0) {
  SurfaceMesh m;
  std::vector<Vertex> vs;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      vs.push_back(m.add_vertex(Point(i, j, z_amplitude * std::sin(0.7 * i) * std::cos(0.5 * j))));
  auto at = [&](int i, int j) { return vs[static_cast<std::size_t>(j * (n + 1) + i)]; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (skip(i, j)) continue;
      m.add_triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      m.add_triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  // Isolated vertices of skipped cells are left for the code under test to ignore.
  return m;
}
inline SurfaceMesh grid(int n) {
  return grid(n, [](int, int) { return false; });
}

/// UV sphere with `rings` latitude bands and `segments` longitudes (poles are fans).
inline SurfaceMesh sphere(int rings, int segments, double radius = 1.0) {
  SurfaceMesh m;
  Vertex north = m.add_vertex(Point(0, 0, radius));
  std::vector<Vertex> vs;
  for (int r = 1; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const double th = std::numbers::pi * r / rings, ph = 2 * std::numbers::pi * s / segments;
      vs.push_back(m.add_vertex(radius * Point(std::sin(th) * std::cos(ph),
                                               std::sin(th) * std::sin(ph), std::cos(th))));
    }
  Vertex south = m.add_vertex(Point(0, 0, -radius));
  auto at = [&](int r, int s) { return vs[static_cast<std::size_t>((r - 1) * segments + (s % segments))]; };
  for (int s = 0; s < segments; ++s) m.add_triangle(north, at(1, s), at(1, s + 1));
  for (int r = 1; r < rings - 1; ++r)
    for (int s = 0; s < segments; ++s) {
      m.add_triangle(at(r, s), at(r + 1, s), at(r + 1, s + 1));
      m.add_triangle(at(r, s), at(r + 1, s + 1), at(r, s + 1));
    }
  for (int s = 0; s < segments; ++s) m.add_triangle(south, at(rings - 1, s + 1), at(rings - 1, s));
  return m;
}

/// The faces of sphere(rings, segments) whose corners' mean z is above 0: an open hemisphere
/// (one boundary circle). jitter > 0 scales each vertex radially by 1 ± jitter/2 (a fixed
/// linear congruential sequence in order of first use), so no two collapses tie exactly.
inline SurfaceMesh upper_hemisphere(int rings, int segments, double jitter = 0.0) {
  const SurfaceMesh sphere = test::sphere(rings, segments);
  SurfaceMesh m;
  std::vector<Vertex> map(sphere.vertices_size());
  std::uint32_t seed = 12345;
  for (Face f : sphere.faces()) {
    std::vector<Vertex> c;
    double z = 0;
    for (Vertex v : sphere.vertices(f)) c.push_back(v), z += sphere.position(v).z();
    if (z <= 0) continue;
    for (Vertex& v : c) {
      if (!map[v.idx()].is_valid()) {
        double scale = 1.0;
        if (jitter > 0) {
          seed = seed * 1664525u + 1013904223u;
          scale += jitter * (static_cast<double>(seed >> 8) / (1u << 24) - 0.5);
        }
        map[v.idx()] = m.add_vertex(sphere.position(v) * scale);
      }
      v = map[v.idx()];
    }
    m.add_triangle(c[0], c[1], c[2]);
  }
  return m;
}

/// Append `b` to `a` as a separate component, translated by offset.
inline void append(SurfaceMesh& a, const SurfaceMesh& b, const Point& offset = Point::Zero()) {
  std::vector<Vertex> map(b.vertices_size());
  for (Vertex v : b.vertices()) map[v.idx()] = a.add_vertex(b.position(v) + offset);
  for (Face f : b.faces()) {
    std::vector<Vertex> c;
    for (Vertex v : b.vertices(f)) c.push_back(map[v.idx()]);
    a.add_face(c);
  }
}

/// Scale and translate every position.
inline void transform(SurfaceMesh& m, double scale, const Point& offset = Point::Zero()) {
  for (Vertex v : m.vertices()) m.position(v) = m.position(v) * scale + offset;
}

}  // namespace geom::test
