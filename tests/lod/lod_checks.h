#pragma once
// Invariant checks shared by the lod tests.

#include <geom/core/surface_mesh.h>
#include <geom/core/topology.h>
#include <geom/core/validate.h>
#include <geom/lod/simplify.h>
#include <geom/spatial/bvh.h>

#include <gtest/gtest.h>

#include <map>

namespace geom::test {

/// Faces of `simplified` whose normal points against the original surface's normal at
/// the closest original point to the face centroid.
inline std::size_t orientation_disagreements(const SurfaceMesh& original,
                                             const SurfaceMesh& simplified) {
  const TriangleBvh bvh(original);
  std::size_t bad = 0;
  for (Face f : simplified.faces()) {
    std::vector<Point> c;
    for (Vertex v : simplified.vertices(f)) c.push_back(simplified.position(v));
    const Eigen::Vector3d n = (c[1] - c[0]).cross(c[2] - c[0]);
    const Point centroid = (c[0] + c[1] + c[2]) / 3.0;
    const ClosestPoint cp = bvh.closest_point(centroid);
    auto [a, b, d] = bvh.triangle(cp.triangle);
    if (n.dot((b - a).cross(d - a)) < 0) ++bad;
  }
  return bad;
}

/// Topology the simplifier must keep: validity, manifoldness, boundary loops, genus,
/// components.
inline void expect_same_topology(const SurfaceMesh& original, const SurfaceMesh& simplified) {
  const ValidationReport report = validate(simplified);
  EXPECT_TRUE(report.ok()) << report.to_string();
  const TopologyReport a = analyze(original), b = analyze(simplified);
  EXPECT_TRUE(b.manifold);
  EXPECT_EQ(b.isolated_vertices, 0u);
  EXPECT_EQ(a.boundary_loops, b.boundary_loops);
  EXPECT_EQ(a.components, b.components);
  EXPECT_EQ(a.genus, b.genus);
  EXPECT_EQ(a.closed, b.closed);
  EXPECT_EQ(b.degenerate_faces, 0u);
}

inline double min_triangle_quality(const SurfaceMesh& m) {
  double q = 1.0;
  for (Face f : m.faces()) {
    std::vector<Point> c;
    for (Vertex v : m.vertices(f)) c.push_back(m.position(v));
    const double a2 = (c[1] - c[0]).cross(c[2] - c[0]).norm();
    const double s = (c[1] - c[0]).squaredNorm() + (c[2] - c[1]).squaredNorm() + (c[0] - c[2]).squaredNorm();
    q = std::min(q, 2.0 * std::sqrt(3.0) * a2 / s);
  }
  return q;
}

/// A cube [0, n]³ whose faces are n × n grids of triangles (closed, genus 0, coplanar
/// regions meeting at sharp edges).
inline SurfaceMesh subdivided_cube(int n) {
  SurfaceMesh m;
  std::map<std::array<int, 3>, Vertex> index;
  auto vertex = [&](std::array<int, 3> k) {
    auto it = index.find(k);
    if (it != index.end()) return it->second;
    Vertex v = m.add_vertex(Point(k[0], k[1], k[2]));
    index.emplace(k, v);
    return v;
  };
  // For each axis and side, a grid whose (u, w) winding faces outward.
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u_axis = (axis + 1) % 3, w_axis = (axis + 2) % 3;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto key = [&](int a, int b) {
            std::array<int, 3> k{};
            k[axis] = side * n;
            k[u_axis] = a;
            k[w_axis] = b;
            return vertex(k);
          };
          Vertex p00 = key(i, j), p10 = key(i + 1, j), p11 = key(i + 1, j + 1), p01 = key(i, j + 1);
          if (side == 1) {
            m.add_triangle(p00, p10, p11);
            m.add_triangle(p00, p11, p01);
          } else {
            m.add_triangle(p00, p11, p10);
            m.add_triangle(p00, p01, p11);
          }
        }
    }
  return m;
}

/// Lock every seventh vertex of m, simplify with `run(m, locked)`, and check that each
/// locked vertex is in the output, where it was.
template <class Run>
void expect_locked_vertices_stay(const SurfaceMesh& m, const Run& run) {
  std::vector<Vertex> locked;
  for (Vertex v : m.vertices())
    if (v.idx() % 7 == 0) locked.push_back(v);
  const SimplifyResult r = run(m, locked);
  expect_same_topology(m, r.mesh);
  std::size_t found = 0;
  for (Vertex v : r.mesh.vertices()) {
    const Vertex o = r.vertex_origin[v.idx()];
    if (o.idx() % 7 == 0) {
      ++found;
      EXPECT_EQ(r.mesh.position(v), m.position(o));
    }
  }
  EXPECT_EQ(found, locked.size());
}

}  // namespace geom::test
