#include <geom/compgeom/voronoi2.h>
#include <geom/core/errors.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace {

using V2 = Eigen::Vector2d;

double area(const std::vector<V2>& poly) {
  if (poly.size() < 3) return 0;
  double a = 0;
  for (std::size_t k = 1; k + 1 < poly.size(); ++k)
    a += (poly[k] - poly[0]).x() * (poly[k + 1] - poly[0]).y() -
         (poly[k] - poly[0]).y() * (poly[k + 1] - poly[0]).x();
  return a / 2;
}

bool inside(const std::vector<V2>& poly, const V2& q) {
  for (std::size_t k = 0; k < poly.size(); ++k) {
    const V2 &a = poly[k], &b = poly[(k + 1) % poly.size()];
    if ((b - a).x() * (q - a).y() - (b - a).y() * (q - a).x() < -1e-12 * (b - a).squaredNorm())
      return false;
  }
  return true;
}

void expect_tiling(const std::vector<V2>& p, const geom::VoronoiResult& r) {
  double total = 0;
  for (std::uint32_t i = 0; i < p.size(); ++i) {
    if (r.vertex_of[i] != i) {
      EXPECT_TRUE(r.cells[i].empty());
      continue;
    }
    EXPECT_GE(area(r.cells[i]), 0);
    total += area(r.cells[i]);
    if (inside(r.clip, p[i])) {
      EXPECT_TRUE(inside(r.cells[i], p[i])) << "point " << i;
    }
  }
  double clip = area(r.clip);
  EXPECT_NEAR(total, clip, 1e-9 * clip);
}

TEST(Voronoi2, RandomPointsTileTheDefaultBox) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<V2> p(5000);
  for (auto& q : p) q = {u(rng), u(rng)};
  auto r = geom::voronoi_2d(p);
  EXPECT_NEAR(area(r.clip), 1.44, 1e-2);  // the points' box is nearly the unit square
  expect_tiling(p, r);
}

TEST(Voronoi2, GridDuplicatesCollinearAndConvexClip) {
  std::vector<V2> g;
  for (int y = 0; y < 30; ++y)
    for (int x = 0; x < 30; ++x) g.push_back({double(x), double(y)});
  g.push_back(g[17]);
  expect_tiling(g, geom::voronoi_2d(g));
  std::vector<V2> line;
  for (int i = 0; i < 50; ++i) line.push_back({1e9 + i, 1e9 + 2.0 * i});
  expect_tiling(line, geom::voronoi_2d(line));
  std::vector<V2> hex;
  for (int k = 0; k < 6; ++k)
    hex.push_back({20 * std::cos(k * M_PI / 3) + 15, 20 * std::sin(k * M_PI / 3) + 15});
  auto r = geom::voronoi_2d(g, {.clip = hex});
  expect_tiling(g, r);
  std::vector<V2> one = {{3, 4}};
  auto r1 = geom::voronoi_2d(one);
  EXPECT_NEAR(area(r1.cells[0]), area(r1.clip), 1e-12);
}

TEST(Voronoi2, TinyScale) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1e-12);
  std::vector<V2> p(500);
  for (auto& q : p) q = {u(rng), u(rng)};
  expect_tiling(p, geom::voronoi_2d(p));
}

TEST(Voronoi2, BadClipAndNanAreRejected) {
  std::vector<V2> p = {{0, 0}, {1, 1}};
  EXPECT_THROW(geom::voronoi_2d(p, {.clip = {{0, 0}, {1, 0}}}), geom::InvalidArgument);
  EXPECT_THROW(geom::voronoi_2d(p, {.clip = {{0, 0}, {0, 1}, {1, 1}, {1, 0}}}),
               geom::InvalidArgument);
  p.push_back({NAN, 0});
  EXPECT_THROW(geom::voronoi_2d(p), geom::InvalidArgument);
}

}  // namespace
