// Geometry helpers: exact collinearity, normals, areas, angles, fans.

#include <geom/core/build.h>
#include <geom/core/geometry.h>
#include <geom/core/weld.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "soup_shapes.h"

namespace geom {
namespace {

using namespace geom::test;
constexpr double kPi = std::numbers::pi;

TEST(Geometry, CollinearityIsExact) {
  EXPECT_TRUE(is_collinear({0, 0, 0}, {1, 1, 1}, {2, 2, 2}));
  EXPECT_TRUE(is_collinear({0, 0, 0}, {0, 0, 0}, {5, 1, 2}));
  EXPECT_FALSE(is_collinear({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  // 0.1 + 0.2 style rounding: points on a line in decimal are not on one in binary.
  EXPECT_FALSE(is_collinear({0.1, 0.1, 0}, {0.2, 0.2, 0}, {0.3, 0.30000000000000004, 0}));
  // A nudge of one ulp off the line is detected; exact multiples are collinear.
  const double x = 0.3;
  EXPECT_TRUE(is_collinear({0, 0, 0}, {x, x, x}, {2 * x, 2 * x, 2 * x}));
  EXPECT_FALSE(is_collinear({0, 0, 0}, {x, x, x}, {2 * x, std::nextafter(2 * x, 1.0), 2 * x}));
  // Huge and tiny coordinates.
  for (double s : {1e-300, 1e-200, 1e200, 1e300}) {
    EXPECT_TRUE(is_collinear({0, 0, 0}, {s, 2 * s, 3 * s}, {2 * s, 4 * s, 6 * s})) << s;
    EXPECT_FALSE(is_collinear({0, 0, 0}, {s, 2 * s, 3 * s}, {2 * s, std::nextafter(4 * s, 0.0), 6 * s})) << s;
  }
  // Non-finite input is undecidable, not degenerate.
  EXPECT_FALSE(is_collinear({0, 0, 0}, {1, 1, 1}, {std::nan(""), 0, 0}));
}

TEST(Geometry, CollinearityAgreesWithRationalCheckOnRandomSmallIntegers) {
  // Integer points: the cross product in doubles is exact, so it is an oracle.
  std::mt19937 rng(42);
  for (int i = 0; i < 20000; ++i) {
    Point p(rng() % 5, rng() % 5, rng() % 5), q(rng() % 5, rng() % 5, rng() % 5), r(rng() % 5, rng() % 5, rng() % 5);
    bool oracle = (q - p).cross(r - p).isZero(0.0);
    ASSERT_EQ(is_collinear(p, q, r), oracle) << p.transpose() << " | " << q.transpose() << " | " << r.transpose();
  }
}

TEST(Geometry, ZeroAreaPolygon) {
  std::vector<Point> line = {{0, 0, 0}, {1, 0, 0}, {3, 0, 0}, {2, 0, 0}};
  EXPECT_TRUE(is_zero_area_polygon(line));
  std::vector<Point> same = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};
  EXPECT_TRUE(is_zero_area_polygon(same));
  std::vector<Point> quad = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  EXPECT_FALSE(is_zero_area_polygon(quad));
  std::vector<Point> two = {{0, 0, 0}, {1, 0, 0}};
  EXPECT_TRUE(is_zero_area_polygon(two));
}

TEST(Geometry, CubeNormalsAreasAndAngles) {
  auto m = build(cube_soup()).mesh;
  for (Face f : m.faces()) {
    Normal n = face_normal(m, f);
    EXPECT_NEAR(n.norm(), 1.0, 1e-15);
    // Outward: points away from the cube's centre.
    EXPECT_GT(n.dot(face_centroid(m, f) - Point(0.5, 0.5, 0.5)), 0.0);
    EXPECT_DOUBLE_EQ(face_area(m, f), 1.0);
  }
  EXPECT_DOUBLE_EQ(surface_area(m), 6.0);
  for (Edge e : m.edges()) {
    EXPECT_DOUBLE_EQ(edge_length(m, e), 1.0);
    EXPECT_NEAR(dihedral_angle(m, e), kPi / 2, 1e-12);  // convex
  }
  EXPECT_DOUBLE_EQ(mean_edge_length(m), 1.0);
  for (Vertex v : m.vertices()) {
    Normal n = vertex_normal(m, v);
    Normal expect = (m.position(v) - Point(0.5, 0.5, 0.5)).normalized();
    EXPECT_NEAR((n - expect).norm(), 0.0, 1e-12);
  }
  auto box = bounds(m);
  EXPECT_EQ(box.min(), Point(0, 0, 0));
  EXPECT_EQ(box.max(), Point(1, 1, 1));
}

TEST(Geometry, DihedralAngleSignAndBoundary) {
  // Two triangles folded along the x axis: a valley (concave) or a ridge (convex).
  for (double z : {0.5, -0.5}) {
    PolygonSoup s;
    s.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, z}, {0.5, -1, z}};
    s.add_face({0, 1, 2});
    s.add_face({1, 0, 3});
    auto m = build(s).mesh;
    Edge e = m.find_edge(Vertex(0), Vertex(1));
    double a = dihedral_angle(m, e);
    EXPECT_NEAR(std::abs(a), 2 * std::atan(0.5), 1e-12);
    EXPECT_EQ(a < 0, z > 0) << z;  // corners raised above the shared edge: a valley
    Edge b = m.find_edge(Vertex(0), Vertex(2));
    EXPECT_EQ(dihedral_angle(m, b), 0.0);
  }
}

TEST(Geometry, PolygonNewellAreaAndFan) {
  // An L-shaped hexagon (non-convex) of area 3.
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {1, 1, 0}, {1, 2, 0}, {0, 2, 0}};
  s.add_face({0, 1, 2, 3, 4, 5});
  auto m = build(s).mesh;
  EXPECT_DOUBLE_EQ(face_area(m, Face(0)), 3.0);
  EXPECT_EQ(face_normal(m, Face(0)), Normal(0, 0, 1));
  auto fan = triangulate_fan(m, Face(0));
  ASSERT_EQ(fan.size(), 4u);
  EXPECT_EQ(fan[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(fan[3], (std::array<std::uint32_t, 3>{0, 4, 5}));
  auto fv = triangulate_fan_vertices(m, Face(0));
  ASSERT_EQ(fv.size(), 4u);
  EXPECT_EQ(fv[3][2], Vertex(5));
  EXPECT_NEAR(face_centroid(m, Face(0)).x(), 1.0, 1e-15);
}

TEST(Geometry, TorusAreaConvergesAndIsolatedVertexNormalIsZero) {
  auto s = torus_soup(64, 32);
  s.positions.push_back({10, 10, 10});
  auto m = build(s).mesh;
  // Exact area of the (R = 2, r = 1) torus: 4π²Rr; the inscribed mesh is slightly smaller.
  double exact = 4 * kPi * kPi * 2;
  double a = surface_area(m);
  EXPECT_LT(a, exact);
  EXPECT_GT(a, 0.99 * exact);
  EXPECT_EQ(vertex_normal(m, Vertex(static_cast<std::uint32_t>(s.positions.size() - 1))), Normal::Zero());
  EXPECT_EQ(mean_edge_length(SurfaceMesh()), 0.0);
  EXPECT_TRUE(bounds(SurfaceMesh()).isEmpty());
}

}  // namespace
}  // namespace geom

namespace geom {
namespace {

TEST(Weld, ExactAndToleranceMaps) {
  std::vector<Point> p = {{0, 0, 0}, {1, 0, 0}, {-0.0, 0, 0}, {1, 0, 1e-9}, {1, 0, 2e-9}, {5, 5, 5}};
  auto exact = weld_map(p, 0);
  EXPECT_EQ(exact, (std::vector<std::uint32_t>{0, 1, 0, 3, 4, 5}));
  // Chains merge: 1–3 and 3–4 are within 1.5e-9, 1–4 is not.
  auto close = weld_map(p, 1.5e-9);
  EXPECT_EQ(close, (std::vector<std::uint32_t>{0, 1, 0, 1, 1, 5}));
  p.push_back({std::nan(""), 0, 0});
  p.push_back({std::nan(""), 0, 0});
  auto with_nan = weld_map(p, 0.1);
  EXPECT_EQ(with_nan[6], 6u);
  EXPECT_EQ(with_nan[7], 7u);
  EXPECT_TRUE(weld_map(std::vector<Point>{}, 0).empty());
}

TEST(Weld, ThrowsOnNegativeOrNonFiniteTolerance) {
  std::vector<Point> p = {{0, 0, 0}};
  EXPECT_THROW(weld_map(p, -1.0), InvalidArgument);
  EXPECT_THROW(weld_map(p, std::numeric_limits<double>::infinity()), InvalidArgument);
  EXPECT_THROW(weld_map(p, std::nan("")), InvalidArgument);
}

}  // namespace
}  // namespace geom
