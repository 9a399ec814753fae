#include <geom/compgeom/hull3.h>
#include <geom/core/errors.h>
#include <geom/core/validate.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>
#include <map>
#include <random>

namespace {

using V3 = Eigen::Vector3d;
using Idx = std::vector<std::uint32_t>;

// Checks a closed, consistently oriented surface with every point on or below every face.
void expect_convex_closed(const std::vector<V3>& p, const geom::Hull3Result& h) {
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> dir;
  for (const auto& t : h.triangles)
    for (int i = 0; i < 3; ++i) ++dir[{t[i], t[(i + 1) % 3]}];
  for (const auto& [e, c] : dir) {
    EXPECT_EQ(c, 1);
    EXPECT_EQ(dir.count({e.second, e.first}), 1u);
  }
  EXPECT_EQ(h.triangles.size(), 2 * h.vertices.size() - 4);
  for (const auto& t : h.triangles) {
    for (const V3& q : p) ASSERT_GE(geom::orient3d(p[t[0]], p[t[1]], p[t[2]], q), 0);
  }
}

double volume(const std::vector<V3>& p, const geom::Hull3Result& h) {
  V3 c = p[h.vertices[0]];
  double v = 0;
  for (const auto& t : h.triangles) v += (p[t[0]] - c).dot((p[t[1]] - c).cross(p[t[2]] - c)) / 6;
  return v;
}

TEST(Hull3, RandomBallAndOffset) {
  for (double offset : {0.0, 1e8}) {
    std::mt19937_64 rng(1);
    std::normal_distribution<double> g;
    std::vector<V3> p;
    for (int i = 0; i < 3000; ++i) p.push_back(V3(g(rng), g(rng), g(rng)) + V3::Constant(offset));
    auto h = geom::convex_hull_3d(p);
    EXPECT_EQ(h.dimension, 3);
    expect_convex_closed(p, h);
  }
}

TEST(Hull3, CubeLatticeKeepsOnlyTheCorners) {
  std::vector<V3> p;
  for (int z = 0; z < 6; ++z)
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 6; ++x) p.push_back({double(x), double(y), double(z)});
  p.push_back({5, 5, 5});
  auto h = geom::convex_hull_3d(p);
  EXPECT_EQ(h.vertices, (Idx{0, 5, 30, 35, 180, 185, 210, 215}));
  EXPECT_EQ(h.triangles.size(), 12u);
  expect_convex_closed(p, h);
  EXPECT_DOUBLE_EQ(volume(p, h), 125.0);
}

// Coordinates near the double range's end (2^990): the hull is that of the unscaled set
// (the exact predicates see a power-of-two scaling of it; before, their products overflowed).
TEST(Hull3, CoordinatesNearTheDoubleRangeEndGiveTheUnscaledHull) {
  std::vector<V3> p;
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) p.push_back({double(x), double(y * y), double(z + x * y)});
  auto huge = p;
  for (auto& q : huge) q *= std::ldexp(1.0, 990);
  const auto h = geom::convex_hull_3d(p), hh = geom::convex_hull_3d(huge);
  expect_convex_closed(p, h);
  EXPECT_EQ(hh.dimension, 3);
  EXPECT_EQ(hh.vertices, h.vertices);
  EXPECT_EQ(hh.triangles, h.triangles);
}

TEST(Hull3, SpherePointsAreAllVertices) {
  std::mt19937_64 rng(2);
  std::normal_distribution<double> g;
  std::vector<V3> p;
  for (int i = 0; i < 2000; ++i) p.push_back(V3(g(rng), g(rng), g(rng)).normalized());
  auto h = geom::convex_hull_3d(p);
  expect_convex_closed(p, h);
  EXPECT_GT(h.vertices.size(), 1900u);  // rounding can push a few points just inside
}

TEST(Hull3, DuplicatesAndPointsOnFaces) {
  std::vector<V3> p = {{0, 0, 0},     {1, 0, 0}, {0, 1, 0}, {0, 0, 1},      {0.25, 0.25, 0},
                       {0.5, 0, 0.5}, {0, 0, 0}, {1, 0, 0}, {0.1, 0.1, 0.1}};
  auto h = geom::convex_hull_3d(p);
  EXPECT_EQ(h.vertices, (Idx{0, 1, 2, 3}));
  EXPECT_EQ(h.triangles.size(), 4u);
  // Octahedron with face centres and edge midpoints added first (so they enter the first
  // pass as extreme points and must be removed).
  std::vector<V3> q = {{0.5, 0.5, 0}, {0, 0, 0},     {1, 0, 0},   {1, 1, 0},
                       {0, 1, 0},     {0.5, 0.5, 1}, {0.5, 0, 0}, {0.25, 0.25, 0}};
  auto hq = geom::convex_hull_3d(q);
  EXPECT_EQ(hq.vertices, (Idx{1, 2, 3, 4, 5}));
  EXPECT_EQ(hq.triangles.size(), 6u);
  expect_convex_closed(q, hq);
}

TEST(Hull3, CoplanarCollinearSingleEmpty) {
  std::vector<V3> p;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) p.push_back(V3(i, j, 0) + V3(0, 0, i + j));  // plane z = x + y
  auto h = geom::convex_hull_3d(p);
  EXPECT_TRUE(h.planar);
  EXPECT_EQ(h.dimension, 2);
  EXPECT_EQ(h.polygon.size(), 4u);
  EXPECT_TRUE(h.triangles.empty());
  ASSERT_GE(h.projection_axis, 0);
  const int x = (h.projection_axis + 1) % 3, y = (h.projection_axis + 2) % 3;
  for (std::size_t k = 0; k < h.polygon.size(); ++k) {
    const V3 &a = p[h.polygon[k]], &b = p[h.polygon[(k + 1) % 4]], &c = p[h.polygon[(k + 2) % 4]];
    double pa[2] = {a[x], a[y]}, pb[2] = {b[x], b[y]}, pc[2] = {c[x], c[y]};
    EXPECT_GT(geom::orient2d(pa, pb, pc), 0);
  }
  std::vector<V3> line = {{0, 0, 0}, {2, 2, 2}, {1, 1, 1}, {2, 2, 2}};
  auto hl = geom::convex_hull_3d(line);
  EXPECT_EQ(hl.dimension, 1);
  EXPECT_EQ(hl.vertices, (Idx{0, 1}));
  auto h1 = geom::convex_hull_3d(std::vector<V3>{{1, 2, 3}, {1, 2, 3}});
  EXPECT_EQ(h1.dimension, 0);
  EXPECT_EQ(h1.vertices, Idx{0});
  EXPECT_EQ(geom::convex_hull_3d(std::vector<V3>{}).dimension, -1);
}

TEST(Hull3, NanIsRejected) {
  std::vector<V3> p = {
      {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, std::numeric_limits<double>::quiet_NaN()}};
  try {
    geom::convex_hull_3d(p);
    FAIL();
  } catch (const geom::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("point 3"), std::string::npos);
  }
}

TEST(Hull3, MeshIsAValidClosedSurface) {
  std::vector<V3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  auto h = geom::convex_hull_3d(p);
  geom::SurfaceMesh m = geom::hull_mesh(p, h);
  EXPECT_EQ(m.n_vertices(), h.vertices.size());
  EXPECT_EQ(m.n_faces(), h.triangles.size());
  for (auto v : m.vertices()) EXPECT_FALSE(m.is_boundary(v));
}

}  // namespace
