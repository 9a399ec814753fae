#include <geom/compgeom/delaunay2.h>
#include <geom/core/errors.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

namespace {

using V2 = Eigen::Vector2d;

bool has_edge(const geom::DelaunayResult& r, std::uint32_t a, std::uint32_t b) {
  for (const auto& t : r.triangles)
    for (int i = 0; i < 3; ++i)
      if ((t[i] == a && t[(i + 1) % 3] == b) || (t[i] == b && t[(i + 1) % 3] == a)) return true;
  return false;
}

std::vector<V2> uniform(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<V2> p(n);
  for (auto& q : p) q = {u(rng), u(rng)};
  return p;
}

TEST(Cdt2, LongSegmentsAcrossRandomPoints) {
  auto p = uniform(3000, 1);
  p.push_back({0.01, 0.5});   // 3000
  p.push_back({0.99, 0.52});  // 3001
  p.push_back({0.5, 0.02});   // 3002
  p.push_back({0.51, 0.98});  // 3003 (crosses 3000-3001: not used together)
  p.push_back({0.02, 0.02});  // 3004
  std::vector<geom::Segment> segs = {{3000, 3001}, {3002, 3004}};
  auto r = geom::constrained_delaunay_2d(p, segs);
  EXPECT_TRUE(has_edge(r, 3000, 3001));
  EXPECT_TRUE(has_edge(r, 3002, 3004));
  EXPECT_EQ(geom::check_delaunay_2d(p, r.triangles, r.constrained_edges), "");
  EXPECT_EQ(r.constrained_edges.size(), 2u);
  // Without constraints the long edge is not Delaunay, so flips did happen.
  EXPECT_FALSE(has_edge(geom::delaunay_2d(p), 3000, 3001));
}

TEST(Cdt2, StarPolygonBoundaryWithInteriorPoints) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  for (int round = 0; round < 20; ++round) {
    std::vector<V2> p;
    const int m = 300;
    for (int k = 0; k < m; ++k) {
      double t = 2 * M_PI * k / m, r = 0.3 + 0.7 * u(rng);
      p.push_back({r * std::cos(t), r * std::sin(t)});
    }
    for (int k = 0; k < 500; ++k) p.push_back({2 * u(rng) - 1, 2 * u(rng) - 1});
    std::vector<geom::Segment> segs;
    for (std::uint32_t k = 0; k < m; ++k) segs.push_back({k, (k + 1) % m});
    auto r = geom::constrained_delaunay_2d(p, segs);
    for (const auto& s : segs) ASSERT_TRUE(has_edge(r, s.a, s.b));
    ASSERT_EQ(geom::check_delaunay_2d(p, r.triangles, r.constrained_edges), "");
  }
}

TEST(Cdt2, PolygonWithHole) {
  std::vector<V2> p = {{0, 0}, {10, 0}, {10, 10}, {0, 10}, {4, 4}, {6, 4}, {6, 6}, {4, 6}};
  auto extra = uniform(200, 2);
  for (auto& q : extra) p.push_back(q * 10);
  std::vector<geom::Segment> segs = {{0, 1}, {1, 2}, {2, 3}, {3, 0},
                                     {4, 5}, {5, 6}, {6, 7}, {7, 4}};
  // Points inside the hole would cross nothing; remove those that lie on the hole's edges.
  auto r = geom::constrained_delaunay_2d(p, segs);
  for (const auto& s : r.constrained_edges) EXPECT_TRUE(has_edge(r, s.a, s.b));
  EXPECT_EQ(geom::check_delaunay_2d(p, r.triangles, r.constrained_edges), "");
}

TEST(Cdt2, SegmentThroughVerticesIsSplit) {
  std::vector<V2> g;
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 11; ++x) g.push_back({double(x), double(y)});
  std::vector<geom::Segment> segs = {{0, 120}, {10, 13}};  // diagonal, and (10,0)-(2,1)
  auto r = geom::constrained_delaunay_2d(g, segs);
  EXPECT_EQ(r.split_segments, 1u);
  EXPECT_EQ(r.constrained_edges.size(), 11u);
  for (int k = 0; k < 10; ++k) EXPECT_TRUE(has_edge(r, 12 * k, 12 * (k + 1)));
  EXPECT_TRUE(has_edge(r, 10, 13));
  EXPECT_EQ(geom::check_delaunay_2d(g, r.triangles, r.constrained_edges), "");
}

TEST(Cdt2, CrossingSegmentsAreReportedByName) {
  std::vector<V2> p = {{0, 0}, {1, 1}, {0, 1}, {1, 0}, {0.5, 0.2}};
  std::vector<geom::Segment> segs = {{0, 1}, {2, 3}};
  try {
    geom::constrained_delaunay_2d(p, segs);
    FAIL();
  } catch (const geom::InvalidArgument& e) {
    std::string m = e.what();
    EXPECT_NE(m.find("segment 1 (2, 3)"), std::string::npos) << m;
    EXPECT_NE(m.find("segment 0 (0, 1)"), std::string::npos) << m;
  }
}

TEST(Cdt2, BadSegmentsAreRejected) {
  std::vector<V2> p = {{0, 0}, {1, 0}, {0, 1}, {0, 0}};
  EXPECT_THROW(geom::constrained_delaunay_2d(p, std::vector<geom::Segment>{{0, 4}}),
               geom::InvalidArgument);
  EXPECT_THROW(geom::constrained_delaunay_2d(p, std::vector<geom::Segment>{{0, 3}}),
               geom::InvalidArgument);
  p[1].x() = NAN;
  EXPECT_THROW(geom::constrained_delaunay_2d(p, std::vector<geom::Segment>{}),
               geom::InvalidArgument);
}

TEST(Cdt2, CollinearInputAndDuplicatesInSegments) {
  std::vector<V2> p = {{0, 0}, {2, 2}, {1, 1}, {3, 3}, {2, 2}};
  auto r = geom::constrained_delaunay_2d(p, std::vector<geom::Segment>{{0, 4}});
  EXPECT_TRUE(r.collinear);
  EXPECT_EQ(r.constrained_edges.size(), 2u);
  EXPECT_EQ(r.split_segments, 1u);
  std::vector<V2> q = {{0, 0}, {4, 0}, {2, 3}, {2, 1}, {4, 0}};
  auto r2 = geom::constrained_delaunay_2d(q, std::vector<geom::Segment>{{0, 4}, {2, 3}});
  EXPECT_TRUE(has_edge(r2, 0, 1));
  EXPECT_EQ(r2.constrained_edges.size(), 2u);
}

}  // namespace
