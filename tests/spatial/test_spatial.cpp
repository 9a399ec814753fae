#include <geom/spatial/bvh.h>
#include <geom/spatial/distance.h>

#include "spatial/procedural.h"

#include <gtest/gtest.h>

#include <random>

namespace geom {
namespace {

double brute_distance2(const TriangleBvh& bvh, const Point& q) {
  double best = std::numeric_limits<double>::infinity();
  for (std::uint32_t t = 0; t < bvh.n_triangles(); ++t) {
    auto [a, b, c] = bvh.triangle(t);
    best = std::min(best, (closest_point_on_triangle(q, a, b, c) - q).squaredNorm());
  }
  return best;
}

TEST(ClosestPointOnTriangle, KnownRegions) {
  const Point a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_TRUE(closest_point_on_triangle(Point(0.2, 0.2, 5), a, b, c).isApprox(Point(0.2, 0.2, 0)));
  EXPECT_EQ(closest_point_on_triangle(Point(-1, -1, 0), a, b, c), a);
  EXPECT_EQ(closest_point_on_triangle(Point(2, -1, 1), a, b, c), b);
  EXPECT_EQ(closest_point_on_triangle(Point(-1, 3, 0), a, b, c), c);
  EXPECT_TRUE(closest_point_on_triangle(Point(0.5, -2, 0), a, b, c).isApprox(Point(0.5, 0, 0)));
  EXPECT_TRUE(closest_point_on_triangle(Point(1, 1, 0), a, b, c).isApprox(Point(0.5, 0.5, 0)));
  EXPECT_TRUE(closest_point_on_triangle(Point(-3, 0.25, 0), a, b, c).isApprox(Point(0, 0.25, 0)));
}

TEST(ClosestPointOnTriangle, NeverFartherThanDenseSampling) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uni(-2, 2);
  for (int trial = 0; trial < 200; ++trial) {
    Point a(uni(rng), uni(rng), uni(rng)), b(uni(rng), uni(rng), uni(rng)), c(uni(rng), uni(rng), uni(rng));
    Point q(uni(rng), uni(rng), uni(rng));
    const Point p = closest_point_on_triangle(q, a, b, c);
    const double d = (p - q).norm();
    // p lies on the triangle: its barycentrics are in [0, 1].
    const Eigen::Vector3d n = (b - a).cross(c - a);
    EXPECT_NEAR(n.normalized().dot(p - a), 0.0, 1e-9);
    const int k = 60;
    for (int i = 0; i <= k; ++i)
      for (int j = 0; i + j <= k; ++j) {
        const Point s = a + (b - a) * (double(i) / k) + (c - a) * (double(j) / k);
        ASSERT_LE(d, (s - q).norm() + 1e-12);
      }
  }
}

TEST(ClosestPointOnTriangle, DegenerateTriangles) {
  const Point a(0, 0, 0), b(2, 0, 0);
  // Collinear corners: a segment from a to b.
  EXPECT_TRUE(closest_point_on_triangle(Point(1, 3, 0), a, b, Point(1, 0, 0)).isApprox(Point(1, 0, 0)));
  // All corners equal: a point.
  EXPECT_EQ(closest_point_on_triangle(Point(1, 3, 0), a, a, a), a);
}

TEST(TriangleBvh, ClosestPointMatchesBruteForce) {
  const SurfaceMesh m = test::torus(40, 24, 1.0, 0.3, 0.2);
  const TriangleBvh bvh(m);
  ASSERT_EQ(bvh.n_triangles(), m.n_faces());
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uni(-2, 2);
  for (int i = 0; i < 500; ++i) {
    const Point q(uni(rng), uni(rng), uni(rng) * 0.5);
    const ClosestPoint cp = bvh.closest_point(q);
    ASSERT_TRUE(cp.found());
    EXPECT_EQ(cp.distance_squared, brute_distance2(bvh, q));
    EXPECT_NEAR((cp.point - q).squaredNorm(), cp.distance_squared, 1e-15);
    EXPECT_TRUE(bvh.triangle_face(cp.triangle).is_valid());
  }
}

TEST(TriangleBvh, MaxDistanceBoundsTheSearch) {
  const SurfaceMesh m = test::grid(8);
  const TriangleBvh bvh(m);
  EXPECT_FALSE(bvh.closest_point(Point(4, 4, 3), 1.0).found());
  EXPECT_TRUE(bvh.closest_point(Point(4, 4, 3), 3.5).found());
}

TEST(TriangleBvh, RayHitsMatchBruteForce) {
  const SurfaceMesh m = test::sphere(16, 24);
  const TriangleBvh bvh(m);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uni(-1, 1);
  int hits = 0;
  for (int i = 0; i < 500; ++i) {
    const Point o(3 * uni(rng), 3 * uni(rng), 3 * uni(rng));
    // Half the rays aim at the sphere, half go anywhere.
    const Vector3 d = i % 2 ? Vector3(uni(rng), uni(rng), uni(rng))
                            : Vector3(Point(0.7 * uni(rng), 0.7 * uni(rng), 0.7 * uni(rng)) - o);
    std::optional<RayHit> best;
    for (std::uint32_t t = 0; t < bvh.n_triangles(); ++t) {
      auto [a, b, c] = bvh.triangle(t);
      auto h = intersect_triangle(o, d, 0.0, best ? best->t : 1e30, a, b, c);
      if (h) best = h, best->triangle = t;
    }
    const auto hit = bvh.intersect(o, d, 0.0, 1e30);
    ASSERT_EQ(hit.has_value(), best.has_value());
    EXPECT_EQ(bvh.any_hit(o, d, 0.0, 1e30), best.has_value());
    if (!hit) continue;
    ++hits;
    EXPECT_EQ(hit->t, best->t);
    auto [a, b, c] = bvh.triangle(hit->triangle);
    const Point p = (1 - hit->u - hit->v) * a + hit->u * b + hit->v * c;
    EXPECT_LT((p - (o + hit->t * d)).norm(), 1e-9);
  }
  EXPECT_GT(hits, 250);
}

TEST(TriangleBvh, RayAlongAxisAndTRange) {
  const SurfaceMesh m = test::grid(4);
  const TriangleBvh bvh(m);
  // Direction with zero components exercises the slab test's axis-parallel branch.
  auto hit = bvh.intersect(Point(1.5, 2.5, 5), Vector3(0, 0, -1));
  ASSERT_TRUE(hit);
  EXPECT_DOUBLE_EQ(hit->t, 5.0);
  EXPECT_FALSE(bvh.intersect(Point(1.5, 2.5, 5), Vector3(0, 0, -1), 0.0, 4.0));
  EXPECT_FALSE(bvh.any_hit(Point(1.5, 2.5, 5), Vector3(0, 0, 1)));
  EXPECT_FALSE(bvh.intersect(Point(9, 9, 5), Vector3(0, 0, -1)));
}

TEST(TriangleBvh, EmptyAndBadInput) {
  const TriangleBvh empty;
  EXPECT_FALSE(empty.closest_point(Point(0, 0, 0)).found());
  EXPECT_FALSE(empty.intersect(Point(0, 0, 0), Vector3(1, 0, 0)));
  EXPECT_FALSE(empty.any_hit(Point(0, 0, 0), Vector3(1, 0, 0)));
  EXPECT_THROW(TriangleBvh({Point(0, 0, 0)}, {{0, 1, 2}}), InvalidArgument);
}

TEST(TriangleBvh, CoincidentTrianglesAndHugeScale) {
  // Many triangles with identical centroids force the balanced fallback split.
  std::vector<Point> p;
  std::vector<std::array<std::uint32_t, 3>> t;
  for (int i = 0; i < 1000; ++i) {
    const auto b = static_cast<std::uint32_t>(p.size());
    const double s = 1e9 * (1 + i % 7);
    p.push_back(Point(-s, -s, 0)), p.push_back(Point(2 * s, -s, 0)), p.push_back(Point(-s, 2 * s, 0));
    t.push_back({b, b + 1, b + 2});
  }
  const TriangleBvh bvh(p, t);
  const ClosestPoint cp = bvh.closest_point(Point(0, 0, 3e9));
  EXPECT_DOUBLE_EQ(cp.distance_squared, 9e18);
  auto hit = bvh.intersect(Point(0, 0, 3e9), Vector3(0, 0, -1));
  ASSERT_TRUE(hit);
  EXPECT_DOUBLE_EQ(hit->t, 3e9);
}

TEST(MeshDistance, IdenticalMeshesHaveZeroDistance) {
  const SurfaceMesh m = test::torus(30, 20, 1.0, 0.3, 0.1);
  const MeshDistance d = mesh_distance(m, m, {.samples = 20000});
  // Samples inside a triangle carry round-off of the order of machine epsilon.
  EXPECT_LT(d.hausdorff, 1e-12);
  EXPECT_LT(d.rms, 1e-12);
  EXPECT_GT(d.diagonal, 0.0);
}

TEST(MeshDistance, ParallelPlanesAtKnownOffset) {
  SurfaceMesh a = test::grid(10);
  SurfaceMesh b = test::grid(10);
  test::transform(b, 1.0, Point(0, 0, 0.5));
  const MeshDistance d = mesh_distance(a, b, {.samples = 5000});
  EXPECT_NEAR(d.hausdorff, 0.5, 1e-12);
  EXPECT_NEAR(d.rms, 0.5, 1e-12);
  EXPECT_NEAR(d.a_to_b.mean, 0.5, 1e-12);
  EXPECT_NEAR(d.relative_hausdorff(), 0.5 / d.diagonal, 1e-15);
}

TEST(MeshDistance, HausdorffAgreesWithBruteForceOnVertices) {
  // A coarse sphere against a fine one: the coarse vertices lie on the fine sphere's
  // sphere, the fine one bulges out of the coarse facets. Brute force over the coarse
  // vertices and a dense set of fine vertices bounds the sampled answer from below.
  const SurfaceMesh coarse = test::sphere(6, 8), fine = test::sphere(24, 32);
  const MeshDistance d = mesh_distance(coarse, fine, {.samples = 50000});
  const TriangleBvh bc(coarse), bf(fine);
  double brute_fc = 0, brute_cf = 0;
  for (Vertex v : fine.vertices()) brute_fc = std::max(brute_fc, brute_distance2(bc, fine.position(v)));
  for (Vertex v : coarse.vertices()) brute_cf = std::max(brute_cf, brute_distance2(bf, coarse.position(v)));
  EXPECT_GE(d.b_to_a.max, std::sqrt(brute_fc));
  EXPECT_GE(d.a_to_b.max, std::sqrt(brute_cf));
  // The fine sphere's largest gap to the coarse facets is near a facet centre: within 5%
  // of the brute-force vertex figure.
  EXPECT_LT(d.b_to_a.max, 1.05 * std::sqrt(brute_fc));
  EXPECT_LE(d.rms, d.hausdorff);
}

// The same four corners, a non-planar quad, split along either diagonal: a roof (ridge from
// (1,0,h) to (0,1,h)) over a valley (fold from (0,0,0) to (1,1,0)). Every vertex lies on the
// other surface, so the whole gap is in the interior, largest at the two diagonals' midpoints:
// (1/2, 1/2, 0) is h / sqrt(1 + 2h²) from the roof's planes (normals (∓h, ∓h, 1)), and the
// ridge midpoint is as far from the valley by symmetry.
struct RoofAndValley {
  double h = 0.5;
  TriangleBvh roof, valley;
  double analytic() const { return h / std::sqrt(1 + 2 * h * h); }
};

RoofAndValley roof_and_valley() {
  RoofAndValley r;
  const std::vector<Point> p = {Point(0, 0, 0), Point(1, 0, r.h), Point(1, 1, 0), Point(0, 1, r.h)};
  r.roof = TriangleBvh(p, {{0, 1, 3}, {1, 2, 3}});
  r.valley = TriangleBvh(p, {{0, 1, 2}, {0, 2, 3}});
  return r;
}

TEST(MeshDistance, HausdorffAtAnEdgeMidpointIsExactWithFewSamples) {
  const RoofAndValley r = roof_and_valley();
  for (std::size_t samples : {0, 16}) {
    const MeshDistance d = mesh_distance(r.roof, r.valley, {.samples = samples});
    EXPECT_NEAR(d.a_to_b.max, r.analytic(), 1e-12 * r.analytic()) << samples;
    EXPECT_NEAR(d.b_to_a.max, r.analytic(), 1e-12 * r.analytic()) << samples;
    EXPECT_NEAR(d.hausdorff, r.analytic(), 1e-12 * r.analytic()) << samples;
  }
  // Measured points: 4 vertices + 5 edges (the shared diagonal once) per side, no area
  // samples, and 14 more points along the one edge whose middle is at the maximum.
  EXPECT_EQ(mesh_distance(r.roof, r.valley, {.samples = 0}).a_to_b.samples, 9u + 14u);
}

// A triangle over a V-shaped valley z = |x − 0.3| (its fold along y): one edge runs from
// (0, 0, 0.3) to (1, 0, 0.7), both ends on the valley, and is farthest from it above the
// fold, at 0.42 / √2 ≈ 0.297, 0.3 of the way along; its midpoint is only 0.3 / √2 ≈ 0.212
// away. The edges near the first pass's maximum are searched at 16ths of their length.
TEST(MeshDistance, PeakInsideAnEdgeAwayFromItsMiddleIsFound) {
  const std::vector<Point> vp = {Point(0, -1, 0.3), Point(0.3, -1, 0), Point(1, -1, 0.7),
                                 Point(0, 1, 0.3),  Point(0.3, 1, 0),  Point(1, 1, 0.7)};
  const TriangleBvh valley(vp, {{0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}});
  const std::vector<Point> tp = {Point(0, 0, 0.3), Point(1, 0, 0.7), Point(0.5, 0.9, 0.2)};
  const TriangleBvh tri(tp, {{0, 1, 2}});
  // The largest distance along the triangle's edges, by brute force (a superset of the
  // points the tool measures there), and at their ends and middles alone.
  double edge_max = 0, ends_and_middles = 0;
  for (int e = 0; e < 3; ++e) {
    const Point &a = tp[e], &b = tp[(e + 1) % 3];
    for (int k = 0; k <= 20000; ++k) {
      const double d = std::sqrt(valley.distance_squared(a + (b - a) * (k / 20000.0)));
      edge_max = std::max(edge_max, d);
      if (k % 10000 == 0) ends_and_middles = std::max(ends_and_middles, d);
    }
  }
  EXPECT_NEAR(edge_max, 0.42 / std::sqrt(2.0), 1e-4);
  EXPECT_LT(ends_and_middles, 0.75 * edge_max);  // midpoints alone would miss a quarter of it
  const MeshDistance d = mesh_distance(tri, valley, {.samples = 0});
  EXPECT_LE(d.a_to_b.max, edge_max);
  EXPECT_GT(d.a_to_b.max, 0.98 * edge_max);
}

TEST(MeshDistance, EdgeMidpointsDoNotEnterTheRms) {
  // With no area samples there is nothing to average: the midpoints feed only the maximum.
  const RoofAndValley r = roof_and_valley();
  const MeshDistance none = mesh_distance(r.roof, r.valley, {.samples = 0});
  EXPECT_EQ(none.rms, 0.0);
  EXPECT_GT(none.hausdorff, 0.0);
  // Dense area sampling never finds a point farther than the midpoint (the analytic maximum),
  // and its RMS is well below the maximum, as an area average of a tent-shaped gap must be.
  const MeshDistance dense = mesh_distance(r.roof, r.valley, {.samples = 200000});
  EXPECT_NEAR(dense.hausdorff, r.analytic(), 1e-12 * r.analytic());
  EXPECT_LT(dense.rms, 0.7 * r.analytic());
  EXPECT_GT(dense.rms, 0.1 * r.analytic());
}

TEST(MeshDistance, QuadFaceDiagonalMidpointIsMeasured) {
  // The same roof as a SurfaceMesh quad (fan-triangulated from its first corner, 0-1-2-3 ->
  // diagonal 0-2, the valley) against the roof triangles: the fan diagonal's midpoint counts.
  const RoofAndValley r = roof_and_valley();
  SurfaceMesh quad;
  std::vector<Vertex> v;
  for (const Point& p : r.roof.positions()) v.push_back(quad.add_vertex(p));
  quad.add_face({v[0], v[1], v[2], v[3]});
  const TriangleBvh q(quad);
  const MeshDistance d = mesh_distance(q, r.roof, {.samples = 0});
  EXPECT_NEAR(d.hausdorff, r.analytic(), 1e-12 * r.analytic());
}

TEST(MeshDistance, EmptyMeshes) {
  const SurfaceMesh empty, m = test::grid(2);
  EXPECT_THROW(mesh_distance(empty, m), InvalidArgument);
  EXPECT_THROW(mesh_distance(m, empty), InvalidArgument);
  EXPECT_EQ(mesh_distance(empty, empty).hausdorff, 0.0);
  EXPECT_THROW(one_sided_distance(TriangleBvh(m), TriangleBvh()), InvalidArgument);
}

}  // namespace
}  // namespace geom
