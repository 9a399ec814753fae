#pragma once
// Small control meshes for the subdivision tests, built face by face.

#include <geom/core/soup.h>
#include <geom/core/surface_mesh.h>

#include <cmath>
#include <vector>

namespace geom::test {

inline SurfaceMesh mesh_from(const std::vector<Point>& points,
                             const std::vector<std::vector<int>>& faces) {
  SurfaceMesh m;
  for (const Point& p : points) m.add_vertex(p);
  for (const auto& f : faces) {
    std::vector<Vertex> vs;
    for (int i : f) vs.push_back(Vertex(static_cast<std::uint32_t>(i)));
    m.add_face(vs);
  }
  return m;
}

inline SurfaceMesh tetrahedron() {
  return mesh_from({{1, 1, 1}, {-1, -1, 1}, {-1, 1, -1}, {1, -1, -1}},
                   {{0, 1, 2}, {0, 3, 1}, {0, 2, 3}, {1, 3, 2}});
}

inline SurfaceMesh cube() {
  return mesh_from({{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                    {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}},
                   {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6},
                    {3, 0, 4, 7}});
}

/// An nx × ny grid of quads in the z = 0 plane, slightly perturbed in x/y so that nothing
/// is symmetric by accident; with `bump` the interior is lifted out of the plane.
inline SurfaceMesh quad_grid(int nx, int ny, bool bump = true) {
  std::vector<Point> pts;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      double z = bump ? 0.3 * std::sin(1.3 * i) * std::cos(0.7 * j) : 0.0;
      pts.emplace_back(i + 0.1 * std::sin(3.0 * j + i), j + 0.1 * std::cos(2.0 * i - j), z);
    }
  std::vector<std::vector<int>> faces;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      int a = j * (nx + 1) + i;
      faces.push_back({a, a + 1, a + nx + 2, a + nx + 1});
    }
  return mesh_from(pts, faces);
}

/// A closed pentagonal prism with one side quad split into two triangles: triangles,
/// quads and pentagons together.
inline SurfaceMesh mixed_polygons() {
  std::vector<Point> pts;
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < 5; ++i) {
      double a = 2.0 * M_PI * i / 5.0;
      pts.emplace_back(std::cos(a) * (1.0 + 0.1 * i), std::sin(a), k * 1.5 + 0.05 * i);
    }
  std::vector<std::vector<int>> faces = {{4, 3, 2, 1, 0}, {5, 6, 7, 8, 9}};
  for (int i = 0; i < 5; ++i) {
    int j = (i + 1) % 5;
    if (i == 2) {
      faces.push_back({i, j, j + 5});
      faces.push_back({i, j + 5, i + 5});
    } else {
      faces.push_back({i, j, j + 5, i + 5});
    }
  }
  return mesh_from(pts, faces);
}

/// A closed pyramid over an n-gon whose base is fanned around a centre vertex: the apex and
/// the base centre have valence n, all faces are triangles.
inline SurfaceMesh bipyramid_fan(int n) {
  std::vector<Point> pts = {{0, 0, 1.2}, {0, 0, -0.3}};
  for (int i = 0; i < n; ++i) {
    double a = 2.0 * M_PI * i / n;
    pts.emplace_back(std::cos(a), std::sin(a) * (1.0 + 0.05 * i), 0.0);
  }
  std::vector<std::vector<int>> faces;
  for (int i = 0; i < n; ++i) {
    int a = 2 + i, b = 2 + (i + 1) % n;
    faces.push_back({0, a, b});
    faces.push_back({1, b, a});
  }
  return mesh_from(pts, faces);
}

/// A closed pyramid over an n-gon: apex valence n, one n-gon face (Catmull-Clark).
inline SurfaceMesh pyramid(int n) {
  std::vector<Point> pts = {{0.1, -0.05, 1.0}};
  for (int i = 0; i < n; ++i) {
    double a = 2.0 * M_PI * i / n;
    pts.emplace_back(std::cos(a), std::sin(a), 0.02 * i);
  }
  std::vector<std::vector<int>> faces;
  std::vector<int> base;
  for (int i = n - 1; i >= 0; --i) base.push_back(1 + i);
  faces.push_back(base);
  for (int i = 0; i < n; ++i) faces.push_back({0, 1 + i, 1 + (i + 1) % n});
  return mesh_from(pts, faces);
}

inline SurfaceMesh icosahedron() {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  return mesh_from({{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}},
                   {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9},
                    {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2},
                    {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10},
                    {8, 6, 7}, {9, 8, 1}});
}

/// An open strip of 2n triangles.
inline SurfaceMesh triangle_strip(int n) {
  std::vector<Point> pts;
  for (int i = 0; i <= n; ++i) {
    pts.emplace_back(i, 0.0, 0.2 * std::sin(i));
    pts.emplace_back(i + 0.5, 1.0, 0.2 * std::cos(i));
  }
  std::vector<std::vector<int>> faces;
  for (int i = 0; i < n; ++i) {
    int a = 2 * i;
    faces.push_back({a, a + 2, a + 1});
    faces.push_back({a + 1, a + 2, a + 3});
  }
  return mesh_from(pts, faces);
}

/// Set "e:sharpness" of the edge (a, b).
inline void set_crease(SurfaceMesh& m, int a, int b, double s) {
  auto p = m.get_or_add_property<Edge, double>(prop::kEdgeSharpness, 0.0);
  p[m.find_edge(Vertex(static_cast<std::uint32_t>(a)), Vertex(static_cast<std::uint32_t>(b)))] = s;
}
inline void set_corner(SurfaceMesh& m, int v, double s) {
  auto p = m.get_or_add_property<Vertex, double>(prop::kVertexSharpness, 0.0);
  p[Vertex(static_cast<std::uint32_t>(v))] = s;
}

/// The cube with semi-sharp 0.5, 1.5, 2.7 edges, an infinitely sharp edge chain and a
/// corner.
inline SurfaceMesh creased_cube() {
  SurfaceMesh m = cube();
  set_crease(m, 4, 5, 0.5);
  set_crease(m, 5, 6, 1.5);
  set_crease(m, 6, 7, 2.7);
  set_crease(m, 0, 1, 10.0);
  set_crease(m, 1, 2, 10.0);
  set_corner(m, 3, 2.0);
  return m;
}

}  // namespace geom::test
