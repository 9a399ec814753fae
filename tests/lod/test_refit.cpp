// Refitting simplified vertices to the input surface (SimplifyOptions::refit_iterations).
#include <geom/lod/collapse.h>
#include <geom/lod/refit.h>
#include <geom/lod/simplify.h>
#include <geom/spatial/distance.h>

#include "lod/lod_checks.h"
#include "spatial/procedural.h"

#include <gtest/gtest.h>
#include <algorithm>
#include <random>
#include <tbb/global_control.h>

namespace geom {
namespace {

SimplifyResult simplify_torus(const SurfaceMesh& m, int refit) {
  return simplify(m, {.ratio = 0.1, .refit_iterations = refit});
}

TEST(Refit, LowersRmsOnACurvedSurfaceAndKeepsTheGuarantees) {
  const SurfaceMesh m = test::torus(80, 40);
  const SimplifyResult plain = simplify_torus(m, 0);
  const SimplifyResult fitted = simplify_torus(m, 1);
  // Same collapses, same connectivity: only positions differ.
  ASSERT_EQ(fitted.faces_after, plain.faces_after);
  ASSERT_EQ(fitted.mesh.n_vertices(), plain.mesh.n_vertices());
  test::expect_same_topology(m, fitted.mesh);
  EXPECT_EQ(test::orientation_disagreements(m, fitted.mesh), 0u);
  EXPECT_GE(test::min_triangle_quality(fitted.mesh), 0.02);
  std::size_t moved = 0;
  for (Vertex v : fitted.mesh.vertices())
    moved += fitted.mesh.position(v) != plain.mesh.position(v);
  EXPECT_GT(moved, fitted.mesh.n_vertices() / 2);
  const MeshDistance a = mesh_distance(m, plain.mesh, {.samples = 50000});
  const MeshDistance b = mesh_distance(m, fitted.mesh, {.samples = 50000});
  // Measured: RMS 1.30e-3 -> 1.03e-3, Hausdorff 3.22e-3 -> 3.00e-3 of the diagonal (the guard
  // keeps each vertex's local worst case from growing).
  EXPECT_LT(b.relative_rms(), 0.85 * a.relative_rms());
  EXPECT_LT(b.relative_hausdorff(), a.relative_hausdorff());
}

TEST(Refit, NoFaceTurnsAQuarterTurnOnANoisySurface) {
  // On a rough surface the nearest input triangle says little about orientation (see
  // Simplify.TorusKeepsTopologyAndReachesTarget); the refit's own promise is against the
  // collapses' output, whose connectivity it keeps.
  const SurfaceMesh m = test::torus(80, 40, 1.0, 0.35, 0.05);
  const SimplifyResult plain = simplify_torus(m, 0);
  const SimplifyResult fitted = simplify_torus(m, 1);
  ASSERT_EQ(fitted.mesh.n_faces(), plain.mesh.n_faces());
  auto normal = [](const SurfaceMesh& s, Face f) {
    std::vector<Point> c;
    for (Vertex v : s.vertices(f)) c.push_back(s.position(v));
    return Eigen::Vector3d((c[1] - c[0]).cross(c[2] - c[0]).normalized());
  };
  double worst = 1;
  for (Face f : fitted.mesh.faces())
    worst = std::min(worst, normal(fitted.mesh, f).dot(normal(plain.mesh, f)));
  EXPECT_GT(worst, 0.0);
  test::expect_same_topology(m, fitted.mesh);
}

TEST(Refit, IsAutomaticWhereTheInputVerticesSuffice) {
  // refit_iterations = -1 (the default): one round when the input has at least two vertices
  // per output triangle (here 10%), none when it has fewer (50%).
  const SurfaceMesh m = test::torus(80, 40);
  auto positions = [&](double ratio, int refit) {
    const SimplifyResult r = simplify(m, {.ratio = ratio, .refit_iterations = refit});
    std::vector<Point> p;
    for (Vertex v : r.mesh.vertices()) p.push_back(r.mesh.position(v));
    return p;
  };
  EXPECT_TRUE(positions(0.1, -1) == positions(0.1, 1));
  EXPECT_FALSE(positions(0.1, -1) == positions(0.1, 0));
  EXPECT_TRUE(positions(0.5, -1) == positions(0.5, 0));
  EXPECT_FALSE(positions(0.5, -1) == positions(0.5, 1));
  EXPECT_EQ(simplify(m, {.ratio = 0.1}).refit_rounds, 1);
  EXPECT_EQ(simplify(m, {.ratio = 0.5}).refit_rounds, 0);
  EXPECT_EQ(simplify(m, {.ratio = 0.5, .refit_iterations = 2}).refit_rounds, 2);
}

TEST(Refit, WithoutCollapseHistorySearchesTheWholeOutput) {
  // refit_to_surface called directly knows no survivors: every sample takes the tree search
  // instead of the walk simplify() uses. It fits as well.
  const SurfaceMesh m = test::torus(80, 40);
  const SimplifyResult plain = simplify_torus(m, 0);
  const SimplifyResult walked = simplify_torus(m, 1);
  SurfaceMesh searched = plain.mesh;
  refit_to_surface(searched, m);
  test::expect_same_topology(m, searched);
  EXPECT_EQ(test::orientation_disagreements(m, searched), 0u);
  const double rms_plain = mesh_distance(m, plain.mesh, {.samples = 50000}).relative_rms();
  const double rms_walked = mesh_distance(m, walked.mesh, {.samples = 50000}).relative_rms();
  const double rms_searched = mesh_distance(m, searched, {.samples = 50000}).relative_rms();
  EXPECT_LT(rms_searched, 0.85 * rms_plain);
  // On a smooth surface the walk finds the closest triangles too.
  EXPECT_NEAR(rms_walked, rms_searched, 0.02 * rms_searched);
}

TEST(Refit, BoundaryAndLockedVerticesStay) {
  // An open hemisphere (a boundary circle) with every 17th vertex locked.
  const SurfaceMesh m = test::upper_hemisphere(24, 48);
  std::vector<Vertex> locked;
  for (Vertex v : m.vertices())
    if (v.idx() % 17 == 0) locked.push_back(v);
  const SimplifyResult plain =
      simplify(m, {.ratio = 0.2, .locked = locked, .refit_iterations = 0});
  const SimplifyResult fitted =
      simplify(m, {.ratio = 0.2, .locked = locked, .refit_iterations = 2});
  ASSERT_EQ(fitted.mesh.n_vertices(), plain.mesh.n_vertices());
  test::expect_same_topology(m, fitted.mesh);
  EXPECT_EQ(test::orientation_disagreements(m, fitted.mesh), 0u);
  std::size_t kept = 0, moved = 0;
  for (Vertex v : fitted.mesh.vertices()) {
    const bool fixed =
        fitted.mesh.is_boundary(v) || fitted.vertex_origin[v.idx()].idx() % 17 == 0;
    if (fixed) {
      ++kept;
      EXPECT_EQ(fitted.mesh.position(v), plain.mesh.position(v));
    } else {
      moved += fitted.mesh.position(v) != plain.mesh.position(v);
    }
  }
  EXPECT_GT(kept, 0u);
  EXPECT_GT(moved, 0u);
  const MeshDistance a = mesh_distance(m, plain.mesh, {.samples = 50000});
  const MeshDistance b = mesh_distance(m, fitted.mesh, {.samples = 50000});
  EXPECT_LT(b.relative_rms(), 0.9 * a.relative_rms());  // measured 1.79e-3 -> 1.50e-3
}

/// simplify() on one thread and on all; the caller checks the sizes, then the positions.
struct OneAndAll {
  SimplifyResult one, all;
  std::size_t positions_differ() const {
    std::size_t differ = 0;
    for (Vertex v : one.mesh.vertices()) differ += one.mesh.position(v) != all.mesh.position(v);
    return differ;
  }
};

OneAndAll simplify_one_and_all(const SurfaceMesh& m, const SimplifyOptions& options) {
  OneAndAll r;
  {
    const tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
    r.one = simplify(m, options);
  }
  r.all = simplify(m, options);
  return r;
}

TEST(Refit, SameResultOnOneThreadAsOnAll) {
  // Blocks of vertices move in parallel, the vertices between blocks after them: the result
  // may not depend on the schedule. 2.5k output vertices make four blocks of 512.
  const OneAndAll r = simplify_one_and_all(test::torus(100, 50), {.ratio = 0.5, .refit_iterations = 1});
  ASSERT_EQ(r.one.mesh.n_vertices(), r.all.mesh.n_vertices());
  ASSERT_GT(r.one.mesh.n_vertices(), 2048u);
  EXPECT_EQ(r.positions_differ(), 0u);
}

TEST(Refit, SameResultOnOneThreadAsOnAllFromVertexSamples) {
  // The automatic round at 10% (input vertices as the only samples): the walks start from
  // a prepared fan, whichever sample came before, and the blocks move even ones first, then
  // odd ones. 4.5k output vertices make nine blocks of 512.
  const OneAndAll r = simplify_one_and_all(test::torus(300, 150, 1.0, 0.35, 0.01), {.ratio = 0.1});
  ASSERT_EQ(r.all.refit_rounds, 1);
  ASSERT_EQ(r.one.mesh.n_vertices(), r.all.mesh.n_vertices());
  ASSERT_GT(r.one.mesh.n_vertices(), 4096u);
  EXPECT_EQ(r.positions_differ(), 0u);
}

// m with its vertices renumbered at random (the faces keep their order): a scan like amo.ply,
// whose simplified vertices then come in no spatial order.
SurfaceMesh shuffled_vertices(const SurfaceMesh& m, unsigned seed) {
  std::vector<std::uint32_t> to(m.vertices_size());
  for (std::uint32_t i = 0; i < to.size(); ++i) to[i] = i;
  std::mt19937 rng(seed);
  std::shuffle(to.begin(), to.end(), rng);
  std::vector<Point> p(to.size());
  for (std::uint32_t i = 0; i < to.size(); ++i) p[to[i]] = m.position(Vertex(i));
  SurfaceMesh out;
  for (const Point& x : p) out.add_vertex(x);
  for (Face f : m.faces()) {
    std::vector<Vertex> c;
    for (Vertex v : m.vertices(f)) c.push_back(Vertex(to[v.idx()]));
    out.add_face(c);
  }
  return out;
}

TEST(Refit, SameResultOnOneThreadAsOnAllInRandomVertexOrder) {
  // Most vertices would be seam in index order; the blocks are cut along a Morton curve
  // instead, and that plan too may not depend on the schedule.
  const SurfaceMesh m = shuffled_vertices(test::torus(300, 150, 1.0, 0.35, 0.01), 7);
  const OneAndAll r = simplify_one_and_all(m, {.ratio = 0.1});
  ASSERT_EQ(r.all.refit_rounds, 1);
  ASSERT_EQ(r.one.mesh.n_vertices(), r.all.mesh.n_vertices());
  ASSERT_GT(r.one.mesh.n_vertices(), 4096u);
  EXPECT_EQ(r.positions_differ(), 0u);
  // And it still fits: lower RMS than without the round.
  const SimplifyResult plain = simplify(m, {.ratio = 0.1, .refit_iterations = 0});
  const MeshDistance a = mesh_distance(m, plain.mesh, {.samples = 50000});
  const MeshDistance b = mesh_distance(m, r.all.mesh, {.samples = 50000});
  EXPECT_LT(b.relative_rms(), 0.97 * a.relative_rms());
}

TEST(Refit, VertexSampleWeightsComeFromTheSetup) {
  // simplify() hands the refit each input vertex's third of its triangles' area from the
  // engine's setup, which has every triangle's area at hand; the refit's own sampling
  // (refit_to_surface without them) sums the same areas around each vertex.
  SurfaceMesh m = test::torus(40, 20, 1.0, 0.35, 0.02);
  const Vertex lone = m.add_vertex(Point(5, 5, 5));  // in no face: no sample
  std::vector<double> expected(m.vertices_size(), 0.0);
  double total = 0;
  for (Face f : m.faces()) {
    std::vector<Vertex> c;
    for (Vertex v : m.vertices(f)) c.push_back(v);
    const double area =
        0.5 * (m.position(c[1]) - m.position(c[0])).cross(m.position(c[2]) - m.position(c[0])).norm();
    for (Vertex v : c) expected[v.idx()] += area / 3;
    total += area;
  }
  const detail::CollapseEngine engine(m, {.refit_iterations = -1}, false);
  const std::vector<double> area = engine.input_vertex_areas(m.vertices_size());
  ASSERT_EQ(area.size(), m.vertices_size());
  double sum = 0;
  for (Vertex v : m.vertices()) {
    EXPECT_NEAR(area[v.idx()], expected[v.idx()], 1e-12 * total) << v.idx();
    sum += area[v.idx()];
  }
  EXPECT_EQ(area[lone.idx()], 0.0);
  EXPECT_NEAR(sum, total, 1e-12 * total);
  // Without a refit to come, the setup keeps none.
  EXPECT_TRUE(detail::CollapseEngine(m, {.refit_iterations = 0}, false)
                  .input_vertex_areas(m.vertices_size())
                  .empty());
}

TEST(Refit, RejectsNegativeIterations) {
  const SurfaceMesh m = test::torus(20, 10);
  EXPECT_THROW(simplify(m, {.refit_iterations = -2}), InvalidArgument);
}

}  // namespace
}  // namespace geom
