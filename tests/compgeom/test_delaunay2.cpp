#include <geom/compgeom/delaunay2.h>
#include <geom/core/errors.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <set>

namespace {

using V2 = Eigen::Vector2d;

std::vector<V2> uniform(std::size_t n, std::uint64_t seed, double scale = 1, double offset = 0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<V2> p(n);
  for (auto& q : p) q = V2(offset + scale * u(rng), offset + scale * u(rng));
  return p;
}

std::vector<V2> grid(int w, int h, double step = 1, double offset = 0) {
  std::vector<V2> p;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) p.push_back({offset + step * x, offset + step * y});
  return p;
}

void expect_valid(const std::vector<V2>& p, const geom::DelaunayResult& r) {
  EXPECT_EQ(geom::check_delaunay_2d(p, r.triangles), "");
  ASSERT_EQ(r.vertex_of.size(), p.size());
  for (std::uint32_t i = 0; i < p.size(); ++i) EXPECT_EQ(p[r.vertex_of[i]], p[i]);
}

TEST(Delaunay2, RandomPointsGiveAValidTriangulation) {
  auto p = uniform(20000, 1);
  auto r = geom::delaunay_2d(p);
  expect_valid(p, r);
  EXPECT_FALSE(r.collinear);
  EXPECT_EQ(r.vertices, p.size());
  EXPECT_EQ(r.duplicates, 0u);
  EXPECT_LT(r.predicates.exact_rate(), 0.01);
}

TEST(Delaunay2, HugeOffsetAndTinyScale) {
  for (auto [scale, offset] : {std::pair{1.0, 1e9}, std::pair{1e-12, 0.0}, std::pair{1e-12, 1.0}}) {
    auto p = uniform(3000, 2, scale, offset);
    expect_valid(p, geom::delaunay_2d(p));
  }
}

// Found by fuzz_compgeom: with coordinates near 1e300 the products inside the exact
// predicates overflowed, and delaunay_2d threw "does not conflict with it (inexact
// predicates)" although its predicates are exact. The points are now scaled by a power of
// two into range first, which changes no predicate's sign: a cocircular grid scaled by
// 2^990 or 2^-990 gives the very triangles of the unscaled one. Coordinates too far apart
// for any double arithmetic (1 beside 1e300) are refused, naming the point.
TEST(Delaunay2, ExtremeScalesGiveTheUnscaledTrianglesOrAClearError) {
  auto p = grid(12, 12);
  std::shuffle(p.begin(), p.end(), std::mt19937(9));
  for (auto& q : uniform(100, 3, 11)) p.push_back(q);
  const auto r = geom::delaunay_2d(p);
  for (int e : {990, -990}) {
    auto scaled = p;
    for (auto& q : scaled) q *= std::ldexp(1.0, e);
    const auto rs = geom::delaunay_2d(scaled);
    EXPECT_EQ(geom::check_delaunay_2d(scaled, rs.triangles), "") << e;
    EXPECT_EQ(rs.triangles, r.triangles) << e;
    EXPECT_EQ(rs.cocircular, r.cocircular) << e;
  }
  const std::vector<V2> fuzz = {{1e300, 1e300}, {-1e300, 1}, {30, 0}, {1, 1}};
  try {
    geom::delaunay_2d(fuzz);
    ADD_FAILURE() << "no error";
  } catch (const geom::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("point 1 has a coordinate of magnitude"), std::string::npos) << e.what();
  }
}

TEST(Delaunay2, IntegerGridIsCocircularEverywhere) {
  auto p = grid(60, 60);
  std::shuffle(p.begin(), p.end(), std::mt19937(4));
  auto r = geom::delaunay_2d(p);
  expect_valid(p, r);
  EXPECT_EQ(r.triangles.size(), 2u * 59 * 59);
  EXPECT_GT(r.cocircular, 0u);
  // Deterministic: independent of insertion order given the same indices.
  auto r2 = geom::delaunay_2d(p);
  EXPECT_EQ(r.triangles, r2.triangles);
}

TEST(Delaunay2, GridWithOffsetAndRotatedLattice) {
  auto p = grid(40, 40, 1, 1e9);
  expect_valid(p, geom::delaunay_2d(p));
  std::vector<V2> q;
  const double c = std::cos(0.3), s = std::sin(0.3);
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) q.push_back({c * x - s * y, s * x + c * y});
  expect_valid(q, geom::delaunay_2d(q));
}

TEST(Delaunay2, RegularPolygonIsCocircular) {
  std::vector<V2> p;
  for (int i = 0; i < 1000; ++i) {
    double t = 2 * std::numbers::pi * i / 1000;
    p.push_back({std::cos(t), std::sin(t)});
  }
  auto r = geom::delaunay_2d(p);
  expect_valid(p, r);
  // With the centre added every triangle is a fan wedge or close to it; still valid.
  p.push_back({0, 0});
  expect_valid(p, geom::delaunay_2d(p));
}

TEST(Delaunay2, DuplicatesAreMergedIntoTheFirstCopy) {
  auto p = uniform(500, 3);
  auto base = p;
  for (int k = 0; k < 5; ++k) p.insert(p.end(), base.begin(), base.begin() + 100);
  for (int k = 0; k < 1000; ++k) p.push_back(base[7]);
  auto r = geom::delaunay_2d(p);
  expect_valid(p, r);
  EXPECT_EQ(r.vertices, 500u);
  EXPECT_EQ(r.duplicates, p.size() - 500);
  for (std::uint32_t i = 500; i < p.size(); ++i) EXPECT_LT(r.vertex_of[i], 500u);
  EXPECT_EQ(r.vertex_of.back(), 7u);
}

TEST(Delaunay2, CollinearInputGivesASortedChain) {
  std::vector<V2> p;
  for (int i = 0; i < 200; ++i)
    p.push_back({1e9 + 2.0 * ((i * 37) % 200), 5.0 + 3.0 * ((i * 37) % 200)});
  p.push_back(p[3]);
  auto r = geom::delaunay_2d(p);
  EXPECT_TRUE(r.collinear);
  EXPECT_TRUE(r.triangles.empty());
  ASSERT_EQ(r.chain.size(), 200u);
  for (std::size_t i = 1; i < r.chain.size(); ++i)
    EXPECT_LT(p[r.chain[i - 1]].x(), p[r.chain[i]].x());
  EXPECT_EQ(r.vertex_of[200], 3u);
  EXPECT_EQ(r.duplicates, 1u);
  // One point off the line by 1e-9 (relative to coordinates ~1): a fan of thin triangles.
  std::vector<V2> q;
  for (int i = 0; i < 100; ++i) q.push_back({double(i), double(i)});
  q.push_back({50.5, 50.5 + 1e-9});
  auto r2 = geom::delaunay_2d(q);
  expect_valid(q, r2);
  EXPECT_EQ(r2.triangles.size(), 99u);
}

TEST(Delaunay2, EmptyOneAndTwoPoints) {
  auto r0 = geom::delaunay_2d(std::vector<V2>{});
  EXPECT_TRUE(r0.collinear);
  EXPECT_TRUE(r0.triangles.empty());
  auto r1 = geom::delaunay_2d(std::vector<V2>{{1, 1}});
  EXPECT_EQ(r1.chain, std::vector<std::uint32_t>{0});
  auto r2 = geom::delaunay_2d(std::vector<V2>{{1, 1}, {0, 0}});
  EXPECT_EQ(r2.chain, (std::vector<std::uint32_t>{1, 0}));
  auto r3 = geom::delaunay_2d(std::vector<V2>{{0, 0}, {1, 0}, {0, 1}});
  ASSERT_EQ(r3.triangles.size(), 1u);
  EXPECT_EQ(r3.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  auto r4 = geom::delaunay_2d(std::vector<V2>{{0, 0}, {0, 1}, {1, 0}});
  EXPECT_EQ(r4.triangles[0], (std::array<std::uint32_t, 3>{0, 2, 1}));
}

TEST(Delaunay2, NanIsRejectedNamingThePoint) {
  std::vector<V2> p = uniform(10, 5);
  p[6].y() = std::numeric_limits<double>::quiet_NaN();
  try {
    geom::delaunay_2d(p);
    FAIL();
  } catch (const geom::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("point 6"), std::string::npos);
  }
  p[6].y() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(geom::delaunay_2d(p), geom::InvalidArgument);
}

TEST(Delaunay2, CheckerRejectsBrokenTriangulations) {
  std::vector<V2> p = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.6}};
  auto r = geom::delaunay_2d(p);
  ASSERT_EQ(geom::check_delaunay_2d(p, r.triangles), "");
  auto t = r.triangles;
  std::swap(t[0][1], t[0][2]);
  EXPECT_NE(geom::check_delaunay_2d(p, t), "");
  t = r.triangles;
  t.pop_back();
  EXPECT_NE(geom::check_delaunay_2d(p, t), "");
  // A non-Delaunay triangulation of a square with a far-off diagonal choice.
  std::vector<V2> q = {{0, 0}, {2, 0}, {2, 1}, {0, 1.5}};
  std::vector<std::array<std::uint32_t, 3>> bad = {{0, 1, 2}, {0, 2, 3}};
  std::vector<std::array<std::uint32_t, 3>> good = {{0, 1, 3}, {1, 2, 3}};
  EXPECT_NE(geom::check_delaunay_2d(q, bad) == "", geom::check_delaunay_2d(q, good) == "");
}

TEST(Delaunay2, CheckerNeedsTrianglesUnlessThePointsAreCollinear) {
  std::vector<V2> p;
  for (int i = 0; i < 256; ++i) p.push_back({i % 16 * 0.25, i / 16 * 0.5 + (i % 3) * 1e-3});
  const std::vector<std::array<std::uint32_t, 3>> none;
  EXPECT_NE(geom::check_delaunay_2d(p, none).find("not collinear"), std::string::npos);
  // One point off a line whose two extremes are repeated.
  std::vector<V2> line;
  for (int i = 0; i < 64; ++i) line.push_back({double(i), 2.0 * i});
  line.push_back({0, 0});
  line.push_back({63, 126});
  EXPECT_EQ(geom::check_delaunay_2d(line, none), "");
  line[10] = {3, 1};
  EXPECT_NE(geom::check_delaunay_2d(line, none).find("point 10"), std::string::npos);
  EXPECT_EQ(geom::check_delaunay_2d(std::vector<V2>(50, V2(1, 1)), none), "");
}

TEST(Delaunay2, CheckerRefusesNonFinitePointsNamingThem) {
  std::vector<V2> p = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.6}};
  const auto r = geom::delaunay_2d(p);
  for (double bad : {std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()}) {
    p[3].y() = bad;
    try {
      geom::check_delaunay_2d(p, r.triangles);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const geom::InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find("point 3 has a non-finite"), std::string::npos)
          << e.what();
    }
  }
  // The range refusal prints its magnitudes in shortest form, not 301 digits.
  std::vector<V2> far = {{0, 0}, {1, 0}, {0, 1e300}};
  try {
    geom::check_delaunay_2d(far, r.triangles);
    ADD_FAILURE();
  } catch (const geom::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("magnitude 1 beside 1e+300"), std::string::npos)
        << e.what();
  }
}

}  // namespace
