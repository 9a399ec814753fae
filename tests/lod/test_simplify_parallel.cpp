// The region-parallel collapses (collapse_loop.cpp). Only meshes of 100k triangles take
// that path in simplify(); these tests call detail::simplify with the threshold at 0, so
// that meshes of a few ten thousand triangles take it and the tests stay fast.

#include <geom/core/soup.h>
#include <geom/core/topology.h>
#include <geom/lod/collapse.h>
#include <geom/lod/simplify.h>
#include <geom/spatial/distance.h>

#include "lod/lod_checks.h"
#include "spatial/procedural.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <numbers>
#include <vector>

namespace geom {
namespace {

constexpr std::size_t kAlways = 0;
constexpr double kPi = std::numbers::pi;

SimplifyResult parallel_simplify(const SurfaceMesh& m, const SimplifyOptions& options) {
  return detail::simplify(m, options, kAlways);
}

bool takes_parallel_path(const SurfaceMesh& m) {
  return detail::CollapseEngine(m, {}, false, kAlways).n_parts() > 0;
}

// FNV-1a over the output's position bits and face corners.
std::uint64_t hash(const SurfaceMesh& m) {
  std::uint64_t h = 1469598103934665603ull;
  auto add = [&](const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  };
  for (Vertex v : m.vertices()) add(m.position(v).data(), 3 * sizeof(double));
  for (Face f : m.faces())
    for (Vertex v : m.vertices(f)) {
      const std::uint32_t i = v.idx();
      add(&i, sizeof i);
    }
  return h;
}

SurfaceMesh noisy_torus() { return test::torus(160, 80, 1.0, 0.35, 0.01); }

SurfaceMesh holey_grid() {
  // A wavy grid with 400 single-cell holes: open, many boundary loops across every part.
  return test::grid(120, [](int i, int j) { return i % 6 == 3 && j % 6 == 3; }, 0.1);
}

SurfaceMesh three_components() {
  // Two spheres touching at a point (coincident but distinct vertices), a torus close by.
  SurfaceMesh m = test::sphere(60, 80);
  test::append(m, test::sphere(60, 80), Point(0, 0, 2));
  test::append(m, test::torus(120, 60, 1.0, 0.2), Point(0.5, 0, 1));
  return m;
}

TEST(SimplifyParallel, SameResultOnOneThreadAsOnAll) {
  // Parts collapse concurrently and the seam between steps: the schedule may not matter.
  const SurfaceMesh m = noisy_torus();
  ASSERT_TRUE(takes_parallel_path(m));
  for (double ratio : {0.5, 0.05}) {
    SimplifyResult one;
    {
      const tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
      one = parallel_simplify(m, {.ratio = ratio});
    }
    const SimplifyResult all = parallel_simplify(m, {.ratio = ratio});
    EXPECT_EQ(one.faces_after, all.faces_after);
    EXPECT_EQ(one.collapses, all.collapses);
    EXPECT_EQ(hash(one.mesh), hash(all.mesh)) << "ratio " << ratio;
  }
}

TEST(SimplifyParallel, KeepsTopologyOrientationAndTarget) {
  // At 10%: the last 10k triangles go in the one-core order, so at 50% little would be
  // left to the parts on these meshes.
  for (const SurfaceMesh& m : {noisy_torus(), holey_grid(), three_components()}) {
    ASSERT_TRUE(takes_parallel_path(m));
    for (double ratio : {0.1}) {
      const SimplifyResult r = parallel_simplify(m, {.ratio = ratio});
      test::expect_same_topology(m, r.mesh);
      // Faces facing against the input's nearest point: the serial order leaves a few on the
      // grid (beside its holes) and the touching spheres too; the parallel order may not
      // leave notably more.
      const std::size_t reversed = test::orientation_disagreements(m, r.mesh);
      const std::size_t serial =
          test::orientation_disagreements(m, simplify(m, {.ratio = ratio}).mesh);
      EXPECT_LE(reversed, serial + serial / 4 + 2) << "ratio " << ratio;
      const auto target = static_cast<std::size_t>(std::llround(ratio * r.faces_before));
      EXPECT_EQ(r.stop, SimplifyStop::kTargetReached);
      EXPECT_LE(r.faces_after, target);
      EXPECT_GE(r.faces_after + 1, target);
    }
  }
}

TEST(SimplifyParallel, ErrorStaysNearTheSerialOrder) {
  // Seam collapses wait for the end of a step and parts stop at their share: the order is
  // not the serial one, but the error may not suffer for it.
  const SurfaceMesh m = noisy_torus();
  for (double ratio : {0.1}) {
    const SimplifyResult serial = simplify(m, {.ratio = ratio});
    const SimplifyResult parallel = parallel_simplify(m, {.ratio = ratio});
    const MeshDistance ds = mesh_distance(m, serial.mesh, {.samples = 20000});
    const MeshDistance dp = mesh_distance(m, parallel.mesh, {.samples = 20000});
    EXPECT_LT(dp.relative_hausdorff(), 1.1 * ds.relative_hausdorff()) << "ratio " << ratio;
    EXPECT_LT(dp.relative_rms(), 1.05 * ds.relative_rms()) << "ratio " << ratio;
  }
}

TEST(SimplifyParallel, StopsAtMaxErrorAndSaysWhy) {
  const SurfaceMesh m = noisy_torus();
  const SimplifyResult r = parallel_simplify(m, {.target_faces = 4, .max_error = 1e-3});
  EXPECT_EQ(r.stop, SimplifyStop::kMaxError);
  EXPECT_LE(r.max_quadric_error, 1e-3);
  EXPECT_GT(r.faces_after, 4u);
  test::expect_same_topology(m, r.mesh);
}

TEST(SimplifyParallel, LockedVerticesNeverMove) {
  test::expect_locked_vertices_stay(noisy_torus(), [](const SurfaceMesh& m, std::vector<Vertex> locked) {
    return parallel_simplify(m, {.ratio = 0.1, .locked = std::move(locked)});
  });
}

// The noisy torus with per-corner texture coordinates from its angles, cut along u = 0 and
// v = 0 (a face across a cut takes u + 1 or v + 1 at its corners below it): two seams that
// cross every part.
SurfaceMesh uv_torus() {
  SurfaceMesh m = noisy_torus();
  auto uv = m.add_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  auto chart = [&](Vertex v) {
    const Point& p = m.position(v);
    const double rho = std::hypot(p.x(), p.y());
    auto turn = [](double a) { return a < 0 ? a / (2 * kPi) + 1 : a / (2 * kPi); };
    return TexCoord(turn(std::atan2(p.y(), p.x())), turn(std::atan2(p.z(), rho - 1)));
  };
  for (Face f : m.faces()) {
    std::vector<Halfedge> hs;
    for (Halfedge h : m.halfedges(f)) hs.push_back(h);
    std::vector<TexCoord> t;
    for (Halfedge h : hs) t.push_back(chart(m.to_vertex(h)));
    for (int x = 0; x < 2; ++x) {
      double hi = 0;
      for (const TexCoord& c : t) hi = std::max(hi, c[x]);
      for (TexCoord& c : t)
        if (hi - c[x] > 0.5) c[x] += 1;
    }
    for (std::size_t k = 0; k < hs.size(); ++k) uv[hs[k]] = t[k];
  }
  return m;
}

TEST(SimplifyParallel, AttributesSameResultOnOneThreadAsOnAllAndSeamsKept) {
  // Wedge data belongs to a vertex and corner wedges to a triangle, so attribute collapses
  // keep to their part as the geometric ones do (collapse_loop.cpp).
  const SurfaceMesh m = uv_torus();
  SimplifyOptions o{.ratio = 0.1};
  o.attributes.texcoords.enabled = true;
  ASSERT_GT(detail::CollapseEngine(m, o, false, kAlways).n_parts(), 0u);
  SimplifyResult one;
  {
    const tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
    one = parallel_simplify(m, o);
  }
  const SimplifyResult all = parallel_simplify(m, o);
  EXPECT_EQ(one.collapses, all.collapses);
  EXPECT_EQ(hash(one.mesh), hash(all.mesh));
  const auto uv_one = one.mesh.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  const auto uv = all.mesh.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  ASSERT_TRUE(uv_one && uv);
  std::size_t differ = 0;
  for (Halfedge h : all.mesh.halfedges())
    if (!all.mesh.is_boundary(h)) differ += uv[h] != uv_one[h];
  EXPECT_EQ(differ, 0u);
  test::expect_same_topology(m, all.mesh);
  EXPECT_EQ(test::orientation_disagreements(m, all.mesh), 0u);
  EXPECT_LE(all.faces_after, m.n_faces() / 10 + 1);
  // No face spans a cut: its corners' chart values stay within half a turn.
  for (Face f : all.mesh.faces())
    for (int x = 0; x < 2; ++x) {
      double lo = 3, hi = -3;
      for (Halfedge h : all.mesh.halfedges(f)) lo = std::min(lo, uv[h][x]), hi = std::max(hi, uv[h][x]);
      EXPECT_LT(hi - lo, 0.5) << "face " << f.idx() << " spans a seam";
    }
}

TEST(SimplifyParallel, CancelStopsBetweenSteps) {
  const SurfaceMesh m = noisy_torus();
  int calls = 0;
  const SimplifyResult r = parallel_simplify(
      m, {.ratio = 0.1, .progress = [&](double) { return ++calls < 2; }});
  EXPECT_EQ(r.stop, SimplifyStop::kCancelled);
  EXPECT_EQ(calls, 2);
  EXPECT_GT(r.faces_after, r.faces_before / 10);
  test::expect_same_topology(m, r.mesh);
}

}  // namespace
}  // namespace geom
