#pragma once
// Procedural meshes for the render tests.

#include <geom/core/surface_mesh.h>

#include <array>
#include <map>
#include <memory>

namespace geom::test {

/// Icosahedron subdivided `levels` times, projected to a sphere of radius r at c.
inline std::shared_ptr<SurfaceMesh> icosphere(int levels, double r = 1.0, Point c = Point::Zero()) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  std::vector<Point> p = {{-1, t, 0}, {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                          {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<std::uint32_t, 3>> f = {
      {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
      {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& q : p) q.normalize();
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto m = [&](std::uint32_t a, std::uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back((p[a] + p[b]).normalized());
      return mid[key] = static_cast<std::uint32_t>(p.size() - 1);
    };
    std::vector<std::array<std::uint32_t, 3>> g;
    for (auto [a, b, c2] : f) {
      std::uint32_t ab = m(a, b), bc = m(b, c2), ca = m(c2, a);
      g.push_back({a, ab, ca});
      g.push_back({b, bc, ab});
      g.push_back({c2, ca, bc});
      g.push_back({ab, bc, ca});
    }
    f.swap(g);
  }
  auto mesh = std::make_shared<SurfaceMesh>();
  for (const auto& q : p) mesh->add_vertex(c + r * q);
  for (auto [a, b, c2] : f) mesh->add_triangle(Vertex(a), Vertex(b), Vertex(c2));
  return mesh;
}

/// Axis-aligned cube of quads, side 2·h, centred at c.
inline std::shared_ptr<SurfaceMesh> cube(double h = 1.0, Point c = Point::Zero()) {
  auto m = std::make_shared<SurfaceMesh>();
  Vertex v[8];
  for (int i = 0; i < 8; ++i)
    v[i] = m->add_vertex(c + h * Point(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1));
  m->add_quad(v[0], v[2], v[3], v[1]);
  m->add_quad(v[4], v[5], v[7], v[6]);
  m->add_quad(v[0], v[1], v[5], v[4]);
  m->add_quad(v[2], v[6], v[7], v[3]);
  m->add_quad(v[0], v[4], v[6], v[2]);
  m->add_quad(v[1], v[3], v[7], v[5]);
  return m;
}

/// The unit corner tetrahedron (0, x, y, z), outward-facing.
inline std::shared_ptr<SurfaceMesh> tetrahedron() {
  auto m = std::make_shared<SurfaceMesh>();
  const Vertex a = m->add_vertex({0, 0, 0}), b = m->add_vertex({1, 0, 0}),
               c = m->add_vertex({0, 1, 0}), d = m->add_vertex({0, 0, 1});
  m->add_triangle(a, c, b);
  m->add_triangle(a, b, d);
  m->add_triangle(b, c, d);
  m->add_triangle(c, a, d);
  return m;
}

}  // namespace geom::test
