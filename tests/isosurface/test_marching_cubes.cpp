#include "surface_check.h"

#include <geom/core/soup.h>
#include <geom/core/validate.h>
#include <geom/isosurface/implicit.h>
#include <geom/isosurface/marching_cubes.h>
#include <geom/isosurface/mc_tables.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <random>

using namespace geom;
using geom::test::boundary_edges_off_grid_boundary;
using geom::test::check_surface;
using geom::test::triangle_set;

namespace {

IsoSurface run(const ScalarGrid& g, MarchingCubesOptions o = {}) { return marching_cubes_arrays(g.view(), o); }

void expect_closed(const IsoSurface& s, long chi, const std::string& what) {
  auto c = check_surface(s);
  EXPECT_TRUE(c.closed_manifold()) << what << ": " << c.summary();
  EXPECT_EQ(c.euler(), chi) << what << ": " << c.summary();
  EXPECT_EQ(c.unused_vertices, 0u) << what;
  EXPECT_EQ(c.coincident_vertices, 0u) << what;
  EXPECT_GT(c.signed_volume, 0.0) << what << ": triangles must face increasing values (outward)";
  EXPECT_TRUE(s.stats.closed) << what;
  EXPECT_EQ(s.stats.vertices, s.positions.size());
  EXPECT_EQ(s.stats.triangles, s.triangles.size());
}

}  // namespace

TEST(McTables, EveryEntryIsAClosedOrientedPatchOnTheCubeSurface) {
  const auto& t = detail::mc_tables();
  std::size_t entries = 0;
  for (int ci = 0; ci < 256; ++ci) {
    const auto& mc = t.cases[ci];
    EXPECT_EQ(mc.edge_mask == 0, ci == 0 || ci == 255);
    for (int bits = 0; bits < (1 << mc.n_ambiguous); ++bits) {
      const auto& e = t.entries[mc.first_entry + bits];
      ++entries;
      // Directed edges: those between two edge vertices on one cube face are loop edges
      // (used once); all others must be used once in each direction inside the cube.
      std::map<std::pair<int, int>, int> directed;
      std::uint16_t used = 0;
      for (int k = 0; k < e.n_triangles; ++k)
        for (int j = 0; j < 3; ++j) {
          int a = t.refs[e.first_ref + 3 * k + j], b = t.refs[e.first_ref + 3 * k + (j + 1) % 3];
          ++directed[{a, b}];
          if (a < 12) used |= std::uint16_t(1u << a);
        }
      EXPECT_EQ(used, mc.edge_mask) << "case " << ci;
      for (const auto& [ab, n] : directed) {
        EXPECT_EQ(n, 1) << "case " << ci << " repeats edge " << ab.first << "→" << ab.second;
        bool reverse = directed.count({ab.second, ab.first}) > 0;
        bool on_face = false;
        if (ab.first < 12 && ab.second < 12) {
          // Two cube edges share a face when their corner sets span ≤ 4 corners on one face.
          auto corners = [](int e) { return detail::kEdgeCorners[e]; };
          for (int axis = 0; axis < 3; ++axis)
            for (int side = 0; side < 2; ++side) {
              bool all = true;
              for (int c : {corners(ab.first)[0], corners(ab.first)[1], corners(ab.second)[0],
                            corners(ab.second)[1]})
                all &= ((c >> axis) & 1) == side;
              on_face |= all;
            }
        }
        EXPECT_NE(on_face, reverse) << "case " << ci << " edge " << ab.first << "→" << ab.second;
      }
    }
  }
  EXPECT_GT(entries, 256u);
}

TEST(MarchingCubes, SphereIsClosedGenusZeroAndConverges) {
  double prev_max = std::numeric_limits<double>::infinity();
  for (std::size_t n : {8, 16, 33, 64, 128}) {
    implicit::Sphere sphere{Eigen::Vector3d(0.01, -0.02, 0.03), 0.8};
    ScalarGrid g = sample(sphere, cube_box(1.0, n));
    IsoSurface s = run(g);
    expect_closed(s, 2, "sphere n=" + std::to_string(n));
    double max_d = 0, mean_d = 0;
    for (const Point& p : s.positions) {
      double d = std::abs(sphere(p));
      max_d = std::max(max_d, d);
      mean_d += d;
    }
    mean_d /= double(s.positions.size());
    double h = 2.0 / double(n - 1);
    EXPECT_LT(max_d, 0.1 * h) << n;  // linear interpolation of a distance field
    EXPECT_LT(max_d, prev_max) << n;
    prev_max = max_d;
    auto c = check_surface(s);
    EXPECT_NEAR(c.signed_volume, 4.0 / 3.0 * std::numbers::pi * 0.512, 0.25 * h * 4 * std::numbers::pi * 0.64);
  }
}

TEST(MarchingCubes, TorusHasEulerCharacteristicZeroAndConverges) {
  double prev_mean = std::numeric_limits<double>::infinity();
  for (std::size_t n : {24, 48, 96, 160}) {
    implicit::Torus torus{Eigen::Vector3d::Zero(), 0.6, 0.25};
    IsoSurface s = run(sample(torus, cube_box(1.0, n, true)));
    expect_closed(s, 0, "torus n=" + std::to_string(n));
    double mean_d = 0;
    for (const Point& p : s.positions) mean_d += std::abs(torus(p));
    mean_d /= double(s.positions.size());
    EXPECT_LT(mean_d, prev_mean) << n;
    prev_mean = mean_d;
  }
}

TEST(MarchingCubes, Genus3SurfaceHasEulerCharacteristicMinusFour) {
  implicit::Genus3 f;
  for (std::size_t n : {72, 100, 150}) {
    SamplingBox box;
    box.min = Eigen::Vector3d(-1.2, -0.5, -0.2);
    box.max = Eigen::Vector3d(1.2, 0.5, 0.2);
    box.dims = {n, n * 10 / 24 + 1, n / 6 + 1};
    expect_closed(run(sample(f, box)), -4, "genus3 n=" + std::to_string(n));
  }
}

TEST(MarchingCubes, TwoSpheresAlmostTouchingStaySeparate) {
  auto f = [](const Eigen::Vector3d& p) {
    implicit::Sphere a{Eigen::Vector3d(-0.505, 0, 0), 0.5}, b{Eigen::Vector3d(0.505, 0, 0), 0.5};
    return std::min(a(p), b(p));
  };
  // Odd counts put a sample plane in the 0.01 gap, so the sampled field separates them.
  for (std::size_t n : {17, 33, 65, 129}) {
    SamplingBox box;
    box.min = Eigen::Vector3d(-1.1, -0.6, -0.6);
    box.max = Eigen::Vector3d(1.1, 0.6, 0.6);
    box.dims = {n, n / 2 + 1, n / 2 + 1};
    expect_closed(run(sample(f, box)), 4, "two spheres n=" + std::to_string(n));
  }
}

TEST(MarchingCubes, ClippedGyroidIsClosedAndManifold) {
  for (std::size_t n : {40, 64, 97}) {
    implicit::Gyroid gyroid{0.5, 0.9};
    IsoSurface s = run(sample(gyroid, cube_box(1.0, n)));
    auto c = check_surface(s);
    EXPECT_TRUE(c.closed_manifold()) << n << ": " << c.summary();
    EXPECT_EQ(c.euler() % 2, 0) << n;
    EXPECT_GT(c.signed_volume, 0.0);
  }
}

TEST(MarchingCubes, MetaballsMergeIntoOneClosedSurface) {
  implicit::Metaballs m;
  m.balls = {{Eigen::Vector3d(-0.3, 0, 0), 0.35}, {Eigen::Vector3d(0.3, 0, 0), 0.35},
             {Eigen::Vector3d(0, 0.35, 0.1), 0.3}};
  IsoSurface s = run(sample(m, cube_box(1.0, 48)));
  expect_closed(s, 2, "metaballs");
}

TEST(MarchingCubes, RandomNoiseIsManifoldAndCrackFree) {
  std::mt19937 rng(12345);
  for (int trial = 0; trial < 12; ++trial) {
    GridDims d{std::size_t(3 + trial * 3), std::size_t(5 + trial), std::size_t(4 + 2 * trial)};
    std::vector<float> v(d.size());
    std::uniform_real_distribution<float> u(-1.f, 1.f);
    for (auto& x : v) x = u(rng);
    ScalarGrid g(d, std::move(v));
    for (bool parallel : {false, true}) {
      IsoSurface s = run(g, {.level = 0.1 * (trial % 3), .parallel = parallel});
      auto c = check_surface(s);
      EXPECT_TRUE(c.manifold()) << "trial " << trial << ": " << c.summary();
      EXPECT_EQ(c.unused_vertices, 0u);
      EXPECT_EQ(c.coincident_vertices, 0u);
      EXPECT_EQ(boundary_edges_off_grid_boundary(g.view(), s), 0u) << "trial " << trial;
      EXPECT_EQ(s.stats.edge_vertices + s.stats.centroid_vertices, s.positions.size());
    }
    // Serial and parallel runs give the same surface (vertex numbering may differ: chunks
    // number their centroid vertices before the next chunk's first layer).
    IsoSurface a = run(g, {.parallel = false}), b = run(g, {.parallel = true});
    EXPECT_EQ(triangle_set(a), triangle_set(b));
  }
}

TEST(MarchingCubes, PaddedNoiseIsClosedWithAmbiguousFacesEverywhere) {
  std::mt19937 rng(7);
  GridDims d{24, 20, 22};
  ScalarGrid g(d);
  std::uniform_real_distribution<double> u(-1, 1);
  for (std::size_t z = 1; z + 1 < d.nz; ++z)
    for (std::size_t y = 1; y + 1 < d.ny; ++y)
      for (std::size_t x = 1; x + 1 < d.nx; ++x) g.set(x, y, z, u(rng));
  for (std::size_t x = 0; x < d.nx; ++x)  // outer shell below the level
    for (std::size_t y = 0; y < d.ny; ++y)
      for (std::size_t z = 0; z < d.nz; ++z)
        if (x == 0 || y == 0 || z == 0 || x + 1 == d.nx || y + 1 == d.ny || z + 1 == d.nz) g.set(x, y, z, -2);
  IsoSurface s = run(g);
  auto c = check_surface(s);
  EXPECT_TRUE(c.closed_manifold()) << c.summary();
  EXPECT_GT(s.stats.ambiguous_faces, 100u);
  EXPECT_GT(s.stats.centroid_vertices, 0u);
  EXPECT_EQ(c.euler() % 2, 0);
}

TEST(MarchingCubes, IntegerVolumeWithLevelOnSamplesIsWatertight) {
  // scikit-image's hole case: samples equal to the level. Rule: value == level is "above".
  std::mt19937 rng(99);
  for (int trial = 0; trial < 6; ++trial) {
    GridDims d{14, 12, 13};
    ScalarGrid g(d);
    std::uniform_int_distribution<int> u(0, 2);
    for (std::size_t z = 1; z + 1 < d.nz; ++z)
      for (std::size_t y = 1; y + 1 < d.ny; ++y)
        for (std::size_t x = 1; x + 1 < d.nx; ++x) g.set(x, y, z, u(rng));
    for (double level : {1.0, 2.0}) {
      // Shell is 0 (below both levels); invert so "inside" is high: faces toward decreasing.
      IsoSurface s = run(g, {.level = level, .normals_toward = NormalDirection::kDecreasing});
      auto c = check_surface(s);
      EXPECT_TRUE(c.closed_manifold()) << "trial " << trial << " level " << level << ": " << c.summary();
      EXPECT_EQ(c.degenerate_triangles, 0u);
      EXPECT_EQ(c.coincident_vertices, 0u);
      EXPECT_GT(c.signed_volume, 0.0);
      EXPECT_EQ(c.euler() % 2, 0);
    }
  }
}

TEST(MarchingCubes, SingleVoxelEveryCase) {
  // All 256 sign patterns of one cube, with magnitudes that exercise both face decisions.
  std::mt19937 rng(3);
  for (int ci = 0; ci < 256; ++ci)
    for (int rep = 0; rep < 4; ++rep) {
      std::vector<double> v(8);
      std::uniform_real_distribution<double> u(0.05, 1.0);
      for (int c = 0; c < 8; ++c) v[c] = ((ci >> c) & 1) ? u(rng) : -u(rng);
      if (rep == 0)
        for (int c = 0; c < 8; ++c) v[c] = ((ci >> c) & 1) ? 0.0 : -1.0;  // ties
      ScalarGrid g({2, 2, 2}, std::move(v));
      IsoSurface s = run(g);
      auto c = check_surface(s);
      EXPECT_TRUE(c.manifold()) << "case " << ci << ": " << c.summary();
      EXPECT_EQ(c.coincident_vertices, 0u);
      EXPECT_EQ(boundary_edges_off_grid_boundary(g.view(), s), 0u) << "case " << ci;
      EXPECT_EQ(s.triangles.empty(), ci == 0 || ci == 255);
      EXPECT_EQ(s.stats.closed, ci == 0 || ci == 255);
    }
  ScalarGrid one({2, 2, 2}, std::vector<float>{1, -1, -1, -1, -1, -1, -1, -1});
  IsoSurface s = run(one);
  EXPECT_EQ(s.positions.size(), 3u);
  ASSERT_EQ(s.triangles.size(), 1u);
  for (const Point& p : s.positions) EXPECT_NEAR(p.sum(), 0.5, 1e-12);  // t = 0.5 on each edge
  // Corner 0 is above: the triangle faces it.
  const auto& t = s.triangles[0];
  Eigen::Vector3d n = (s.positions[t[1]] - s.positions[t[0]]).cross(s.positions[t[2]] - s.positions[t[0]]);
  EXPECT_LT(n.dot(Eigen::Vector3d(1, 1, 1)), 0.0);
}

TEST(MarchingCubes, AllBelowOrAllAboveGivesEmptyResult) {
  ScalarGrid below({5, 6, 7}, std::vector<float>(210, -1.f));
  ScalarGrid above({5, 6, 7}, std::vector<float>(210, 0.f));  // == level counts as above
  for (const ScalarGrid* g : {&below, &above}) {
    IsoSurface s = run(*g);
    EXPECT_TRUE(s.positions.empty());
    EXPECT_TRUE(s.triangles.empty());
    EXPECT_TRUE(s.stats.closed);
    EXPECT_EQ(s.stats.cells, 4u * 5u * 6u);
    MarchingCubesResult r = marching_cubes(g->view());
    EXPECT_TRUE(r.mesh.is_empty());
  }
  ScalarGrid flat({5, 1, 7}, std::vector<float>(35, 1.f));
  EXPECT_TRUE(run(flat).triangles.empty());
}

TEST(MarchingCubes, NaNIsRejectedNamingTheSample) {
  ScalarGrid g = sample(implicit::Sphere{}, cube_box(1.5, 20));
  g.set(7, 11, 13, std::numeric_limits<double>::quiet_NaN());
  g.set(9, 11, 13, std::numeric_limits<double>::quiet_NaN());
  for (bool parallel : {false, true}) {
    try {
      run(g, {.parallel = parallel});
      ADD_FAILURE() << "expected InvalidArgument";
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find("(x=7, y=11, z=13)"), std::string::npos) << e.what();
    }
  }
  ScalarGrid line({4, 1, 1}, std::vector<double>{0, 1, std::nan(""), 2});
  EXPECT_THROW(run(line), InvalidArgument);
}

TEST(MarchingCubes, InfinitiesAreFarValues) {
  ScalarGrid g({3, 3, 3}, std::vector<double>(27, -std::numeric_limits<double>::infinity()));
  g.set(1, 1, 1, std::numeric_limits<double>::infinity());
  auto c = check_surface(run(g));
  EXPECT_TRUE(c.closed_manifold()) << c.summary();
  EXPECT_EQ(c.euler(), 2);
  EXPECT_EQ(c.coincident_vertices, 0u);
}

TEST(MarchingCubes, BadArgumentsThrow) {
  ScalarGrid g = sample(implicit::Sphere{}, cube_box(1.5, 8));
  EXPECT_THROW(run(g, {.level = std::numeric_limits<double>::infinity()}), InvalidArgument);
  EXPECT_THROW(run(g, {.level = std::nan("")}), InvalidArgument);
  GridView v = g.view();
  v.geometry.spacing = Eigen::Vector3d(1, 0, 1);
  EXPECT_THROW(marching_cubes_arrays(v), InvalidArgument);
  v = g.view();
  v.dims.nx = 9;
  EXPECT_THROW(marching_cubes_arrays(v), InvalidArgument);
  v = g.view();
  v.geometry.origin.x() = std::numeric_limits<double>::infinity();
  EXPECT_THROW(marching_cubes_arrays(v), InvalidArgument);
  EXPECT_THROW(ScalarGrid({0, 2, 2}), InvalidArgument);
  EXPECT_THROW(ScalarGrid({2, 2, 2}, std::vector<float>(7)), InvalidArgument);
  EXPECT_THROW(sample(implicit::Sphere{}, cube_box(1, 1)), InvalidArgument);
  EXPECT_THROW(sample(ScalarFunction{}, cube_box(1, 4)), InvalidArgument);
  EXPECT_THROW(sample(implicit::Sphere{}, cube_box(0, 4)), InvalidArgument);
  EXPECT_THROW(g.doubles(), InvalidArgument);
}

TEST(MarchingCubes, OrientationAndNormalsFollowTheOption) {
  implicit::Sphere sphere{Eigen::Vector3d::Zero(), 0.7};
  ScalarGrid g = sample(sphere, cube_box(1.0, 40));
  IsoSurface up = run(g, {.compute_normals = true});
  IsoSurface down = run(g, {.normals_toward = NormalDirection::kDecreasing, .compute_normals = true});
  ASSERT_EQ(up.normals.size(), up.positions.size());
  EXPECT_GT(check_surface(up).signed_volume, 0);
  EXPECT_LT(check_surface(down).signed_volume, 0);
  double worst = 1;
  for (std::size_t i = 0; i < up.positions.size(); ++i) {
    worst = std::min(worst, up.normals[i].dot(up.positions[i].normalized()));
    EXPECT_NEAR(down.normals[i].dot(up.normals[i]), -1.0, 1e-12);
  }
  EXPECT_GT(worst, 0.99);
  EXPECT_TRUE(run(g).normals.empty());  // only computed when asked
}

TEST(MarchingCubes, SpacingAndOriginPlaceTheSurface) {
  GridGeometry geo{Eigen::Vector3d(10, 20, 30), Eigen::Vector3d(0.5, 2.0, 1.0)};
  ScalarGrid g({2, 2, 2}, std::vector<float>{1, -1, -1, -1, -1, -1, -1, -1}, geo);
  IsoSurface s = run(g);
  ASSERT_EQ(s.positions.size(), 3u);
  for (const Point& p : s.positions) {
    Eigen::Vector3d local = (p - geo.origin).cwiseQuotient(geo.spacing);
    EXPECT_NEAR(local.sum(), 0.5, 1e-12);
  }
}

TEST(MarchingCubes, FloatAndDoubleStorageAgree) {
  implicit::Torus torus;
  ScalarGrid f = sample(torus, cube_box(1.0, 30));
  std::vector<double> dv(f.floats().begin(), f.floats().end());
  ScalarGrid d(f.dims(), std::move(dv), f.geometry());
  IsoSurface a = run(f, {.level = 0.01}), b = run(d, {.level = 0.01});
  EXPECT_EQ(a.triangles, b.triangles);
  ASSERT_EQ(a.positions.size(), b.positions.size());
  // Float classification uses the level rounded up to a float: identical signs.
  ScalarGrid ties({2, 2, 2}, std::vector<float>{0.1f, -1, -1, -1, -1, -1, -1, -1});
  EXPECT_EQ(run(ties, {.level = double(0.1f)}).triangles.size(), 1u);
  EXPECT_EQ(run(ties, {.level = std::nextafter(double(0.1f), 1.0)}).triangles.size(), 0u);
}

TEST(MarchingCubes, MeshOutputIsValidAndMatchesArrays) {
  ScalarGrid g = sample(implicit::Torus{}, cube_box(1.0, 40));
  MarchingCubesResult r = marching_cubes(g.view(), {.compute_normals = true});
  IsoSurface s = run(g);
  EXPECT_EQ(r.mesh.n_vertices(), s.positions.size());
  EXPECT_EQ(r.mesh.n_faces(), s.triangles.size());
  auto report = validate(r.mesh);
  EXPECT_TRUE(report.ok()) << report.to_string();
  for (Vertex v : r.mesh.vertices()) EXPECT_FALSE(r.mesh.is_boundary(v));
  EXPECT_TRUE(r.mesh.has_property<Vertex>(prop::kVertexNormal));
  EXPECT_EQ(long(r.mesh.n_vertices()) - long(r.mesh.n_edges()) + long(r.mesh.n_faces()), 0);

  // An open surface (cut by the grid) links its boundary loops.
  ScalarGrid half = sample(implicit::Sphere{Eigen::Vector3d(0, 0, 1.0), 0.8}, cube_box(1.0, 30));
  MarchingCubesResult open = marching_cubes(half.view());
  EXPECT_FALSE(open.stats.closed);
  auto rep2 = validate(open.mesh);
  EXPECT_TRUE(rep2.ok()) << rep2.to_string();
}

