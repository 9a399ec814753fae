#include <geom/compgeom/hull2.h>
#include <geom/core/errors.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace {

using V2 = Eigen::Vector2d;
using Idx = std::vector<std::uint32_t>;

TEST(Hull2, SquareWithInteriorEdgeAndDuplicatePoints) {
  std::vector<V2> p = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}, {0.5, 0}, {1, 1}, {0, 0}};
  auto r = geom::convex_hull_2d(p);
  EXPECT_EQ(r.vertices, (Idx{0, 1, 2, 3}));
  EXPECT_FALSE(r.degenerate);
}

TEST(Hull2, EmptyOneTwoAndCollinear) {
  EXPECT_TRUE(geom::convex_hull_2d(std::vector<V2>{}).vertices.empty());
  EXPECT_EQ(geom::convex_hull_2d(std::vector<V2>{{1, 2}}).vertices, Idx{0});
  EXPECT_EQ(geom::convex_hull_2d(std::vector<V2>{{1, 2}, {1, 2}, {1, 2}}).vertices, Idx{0});
  EXPECT_EQ(geom::convex_hull_2d(std::vector<V2>{{1, 2}, {0, 0}}).vertices, (Idx{1, 0}));
  std::vector<V2> line;
  for (int i = 0; i < 100; ++i) line.push_back({1e9 + 3 * i, 1e9 + 7 * i});
  std::shuffle(line.begin(), line.end(), std::mt19937(3));
  auto r = geom::convex_hull_2d(line);
  ASSERT_EQ(r.vertices.size(), 2u);
  EXPECT_TRUE(r.degenerate);
  EXPECT_EQ(line[r.vertices[0]], V2(1e9, 1e9));
  EXPECT_EQ(line[r.vertices[1]], V2(1e9 + 297, 1e9 + 693));
  // One point 1e-9 off the line makes a triangle.
  line.push_back({1e9 + 150, 1e9 + 350 + 1e-6});
  EXPECT_EQ(geom::convex_hull_2d(line).vertices.size(), 3u);
}

TEST(Hull2, RegularPolygonAndGridAndTinyScale) {
  std::vector<V2> p;
  for (int i = 0; i < 1000; ++i) {
    double t = 2 * std::numbers::pi * i / 1000;
    p.push_back({1e-12 * std::cos(t), 1e-12 * std::sin(t)});
  }
  for (int i = 0; i < 5000; ++i) p.push_back({0.5e-12 * std::cos(i), 0.5e-12 * std::sin(i)});
  auto r = geom::convex_hull_2d(p);
  // Rounded points of a regular polygon are in convex position except where rounding makes
  // three nearly collinear points exactly collinear or concave; count against the brute force.
  std::size_t brute = 0;
  for (std::uint32_t i = 0; i < 1000; ++i) {
    bool extreme = true;
    const V2& prev = p[(i + 999) % 1000];
    const V2& next = p[(i + 1) % 1000];
    if (geom::orient2d(prev, p[i], next) <= 0) extreme = false;
    brute += extreme;
  }
  EXPECT_EQ(r.vertices.size(), brute);
  std::vector<V2> grid;
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 60; ++x) grid.push_back({double(x), double(y)});
  auto g = geom::convex_hull_2d(grid);
  EXPECT_EQ(g.vertices, (Idx{0, 59, 3599, 3540}));
}

TEST(Hull2, PrefilterDoesNotChangeTheResult) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<V2> p;
  for (int i = 0; i < 20000; ++i) {
    V2 q(u(rng), u(rng));
    if (q.squaredNorm() <= 1) p.push_back(q);
  }
  auto a = geom::convex_hull_2d(p);
  auto b = geom::convex_hull_2d(p, {.prefilter = false});
  EXPECT_EQ(a.vertices, b.vertices);
  EXPECT_LT(a.candidates, p.size() / 2);
  // Every point is on the inner side of every hull edge.
  const auto& h = a.vertices;
  for (std::size_t k = 0; k < h.size(); ++k)
    for (const V2& q : p) ASSERT_GE(geom::orient2d(p[h[k]], p[h[(k + 1) % h.size()]], q), 0);
}

TEST(Hull2, NanIsRejectedNamingThePoint) {
  std::vector<V2> p = {{0, 0}, {1, 0}, {0, std::numeric_limits<double>::quiet_NaN()}};
  try {
    geom::convex_hull_2d(p);
    FAIL();
  } catch (const geom::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("point 2"), std::string::npos);
  }
}

}  // namespace
