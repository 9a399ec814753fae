// analyze() on procedural meshes with known topology, both on the soup as given and on the
// mesh build() makes of it.

#include <geom/core/build.h>
#include <geom/core/topology.h>
#include <geom/core/validate.h>

#include <gtest/gtest.h>

#include "soup_shapes.h"

namespace geom {
namespace {

using namespace geom::test;

struct Expect {
  std::size_t v, e, f, h, c;
  long chi;
  std::optional<long> genus;
  bool closed, manifold, orientable;
};

void check(const TopologyReport& r, const Expect& x, const char* what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(r.vertices - r.isolated_vertices, x.v);
  EXPECT_EQ(r.edges, x.e);
  EXPECT_EQ(r.faces, x.f);
  EXPECT_EQ(r.boundary_loops, x.h);
  EXPECT_EQ(r.components, x.c);
  EXPECT_EQ(r.euler_characteristic, x.chi);
  EXPECT_EQ(r.genus, x.genus);
  EXPECT_EQ(r.closed, x.closed);
  EXPECT_EQ(r.manifold, x.manifold);
  EXPECT_EQ(r.orientable, x.orientable);
  // The surface form of Euler's formula, wherever a genus is claimed.
  if (r.genus) {
    EXPECT_EQ(r.euler_characteristic,
              2 * (static_cast<long>(r.components) - *r.genus) - static_cast<long>(r.boundary_loops));
  }
}

void check_both(const PolygonSoup& soup, const Expect& x) {
  check(analyze(soup), x, "soup");
  auto built = build(soup);
  EXPECT_TRUE(validate(built.mesh).ok()) << validate(built.mesh).to_string();
  check(analyze(built.mesh), x, "mesh");
}

// Found by fuzz_algorithms: with no edge at all, the edge grouping offset a null pointer
// (UB, which the sanitizer build aborts on). A point cloud, and a soup whose only faces
// have collapsed to a point, have vertices and nothing else.
TEST(Topology, PointsWithoutEdgesHaveOnlyIsolatedVertices) {
  PolygonSoup points;
  points.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  PolygonSoup collapsed = points;
  collapsed.add_face({1, 1, 1});
  for (const PolygonSoup* s : {&points, &collapsed}) {
    const TopologyReport r = analyze(*s);
    EXPECT_EQ(r.vertices, 3u);
    EXPECT_EQ(r.edges, 0u);
    EXPECT_EQ(r.boundary_loops, 0u);
    const BuildResult b = build(*s);
    EXPECT_TRUE(validate(b.mesh).ok());
    EXPECT_EQ(b.mesh.n_faces(), 0u);
    EXPECT_EQ(analyze(b.mesh).edges, 0u);
  }
}

TEST(Topology, SingleTriangleHasChiOneAndGenusZero) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.add_face({0, 1, 2});
  check_both(s, {3, 3, 1, 1, 1, 1, 0, false, true, true});
}

TEST(Topology, TetrahedronHasChiTwo) { check_both(tetrahedron_soup(), {4, 6, 4, 0, 1, 2, 0, true, true, true}); }

TEST(Topology, CubeHasChiTwo) { check_both(cube_soup(), {8, 12, 6, 0, 1, 2, 0, true, true, true}); }

TEST(Topology, TorusHasGenusOne) {
  check_both(torus_soup(12, 8), {96, 288, 192, 0, 1, 0, 1, true, true, true});
  auto plate = holed_plate(1);
  auto r = analyze(plate);
  EXPECT_EQ(r.genus, 1);
  EXPECT_TRUE(r.closed);
}

TEST(Topology, DoubleTorusHasGenusTwo) {
  auto s = holed_plate(2);
  auto r = analyze(s);
  EXPECT_EQ(r.genus, 2);
  EXPECT_EQ(r.euler_characteristic, -2);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.manifold);
  auto m = build(s).mesh;
  auto rm = analyze(m);
  EXPECT_EQ(rm.genus, 2);
  EXPECT_EQ(rm.euler_characteristic, -2);
  ASSERT_EQ(rm.per_component.size(), 1u);
  EXPECT_EQ(rm.per_component[0].genus, 2);
  EXPECT_EQ(analyze(holed_plate(3)).genus, 3);
}

TEST(Topology, DiskHasOneBoundaryLoop) {
  // 4×4 grid: V = 25, E = 2·4·5 + 16 = 56, F = 32.
  check_both(disk_soup(4), {25, 56, 32, 1, 1, 1, 0, false, true, true});
}

TEST(Topology, AnnulusHasTwoBoundaryLoops) {
  // 10 × 2 quads: V = 30, E = 10·3 + 10·2 = 50, F = 20.
  check_both(annulus_soup(10, 2), {30, 50, 20, 2, 1, 0, 0, false, true, true});
}

TEST(Topology, TorusWithOneHoleCut) {
  check_both(torus_soup(12, 8, true), {96, 287, 190, 1, 1, -1, 1, false, true, true});
}

TEST(Topology, MoebiusStripIsNonOrientableWithoutGenus) {
  auto s = moebius_soup(8);
  auto r = analyze(s);
  EXPECT_FALSE(r.orientable);
  EXPECT_FALSE(r.consistently_oriented);
  EXPECT_FALSE(r.genus.has_value());
  EXPECT_EQ(r.vertices, 16u);
  EXPECT_EQ(r.edges, 24u);
  EXPECT_EQ(r.faces, 8u);
  EXPECT_EQ(r.euler_characteristic, 0);
  EXPECT_EQ(r.boundary_loops, 1u);
  EXPECT_TRUE(r.manifold);
  ASSERT_EQ(r.per_component.size(), 1u);
  EXPECT_FALSE(r.per_component[0].orientable);
  EXPECT_FALSE(r.per_component[0].genus.has_value());
}

TEST(Topology, InconsistentlyOrientedButOrientableSoupHasNoGenus) {
  auto s = cube_soup();
  std::reverse(s.face_indices.begin(), s.face_indices.begin() + 4);  // flip face 0
  auto r = analyze(s);
  EXPECT_TRUE(r.orientable);
  EXPECT_FALSE(r.consistently_oriented);
  EXPECT_FALSE(r.genus.has_value());
  // build() reorients it; then the genus is there.
  auto m = build(s);
  EXPECT_EQ(m.report.flipped_faces, 1u);
  EXPECT_EQ(analyze(m.mesh).genus, 0);
}

TEST(Topology, TwoComponents) {
  auto s = merged(tetrahedron_soup(), translated(cube_soup(), {5, 0, 0}));
  check_both(s, {12, 18, 10, 0, 2, 4, 0, true, true, true});
  auto r = analyze(s);
  ASSERT_EQ(r.per_component.size(), 2u);
  EXPECT_EQ(r.per_component[0].faces, 4u);
  EXPECT_EQ(r.per_component[1].faces, 6u);
  EXPECT_EQ(r.per_component[1].euler_characteristic, 2);
}

TEST(Topology, BowTieVertexIsNonManifold) {
  auto s = bowtie_soup();
  auto r = analyze(s);
  EXPECT_FALSE(r.manifold);
  EXPECT_EQ(r.nonmanifold_vertices, 1u);
  EXPECT_EQ(r.nonmanifold_edges, 0u);
  EXPECT_EQ(r.components, 1u);      // joined through the shared vertex
  EXPECT_EQ(r.boundary_loops, 1u);  // the two loops touch: one piece of boundary
  EXPECT_EQ(analyze(build(s).mesh).boundary_loops, 2u);
  EXPECT_FALSE(r.genus.has_value());
  // Built, the vertex is split: two disks.
  auto b = build(s);
  auto rm = analyze(b.mesh);
  EXPECT_TRUE(rm.manifold);
  EXPECT_EQ(rm.components, 2u);
  EXPECT_EQ(rm.vertices, 6u);
  EXPECT_EQ(rm.genus, 0);
}

TEST(Topology, EdgeWithThreeFacesIsNonManifold) {
  auto s = three_fin_soup();
  auto r = analyze(s);
  EXPECT_FALSE(r.manifold);
  EXPECT_EQ(r.nonmanifold_edges, 1u);
  EXPECT_EQ(r.edges, 7u);
  EXPECT_EQ(r.boundary_edges, 6u);
  EXPECT_FALSE(r.genus.has_value());
  auto b = build(s);
  auto rm = analyze(b.mesh);
  EXPECT_TRUE(rm.manifold);
  EXPECT_EQ(rm.faces, 3u);
  EXPECT_EQ(rm.nonmanifold_edges, 0u);
  EXPECT_TRUE(rm.genus.has_value());
}

TEST(Topology, IsolatedVerticesAreNotComponents) {
  auto s = tetrahedron_soup();
  s.positions.push_back({9, 9, 9});
  auto r = analyze(s);
  EXPECT_EQ(r.vertices, 5u);
  EXPECT_EQ(r.isolated_vertices, 1u);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.euler_characteristic, 2);
  EXPECT_EQ(r.genus, 0);
  auto rm = analyze(build(s).mesh);
  EXPECT_EQ(rm.isolated_vertices, 1u);
  EXPECT_EQ(rm.components, 1u);
  EXPECT_EQ(rm.genus, 0);
}

TEST(Topology, DegenerateFacesAndHistogramAndBounds) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  s.add_face({0, 1, 2});     // collinear: zero area
  s.add_face({0, 1, 4, 3});  // a quad
  s.add_face({0, 0, 3});     // repeated index
  s.add_face({0, 1, 7});     // out of range
  auto r = analyze(s);
  EXPECT_EQ(r.degenerate_faces, 2u);
  EXPECT_EQ(r.out_of_range_faces, 1u);
  EXPECT_EQ(r.faces, 3u);
  EXPECT_EQ(r.face_sizes.at(3), 2u);
  EXPECT_EQ(r.face_sizes.at(4), 1u);
  EXPECT_EQ(r.bounds.min(), Point(0, 0, 0));
  EXPECT_EQ(r.bounds.max(), Point(2, 1, 0));
}

TEST(Topology, EmptyInput) {
  PolygonSoup s;
  auto r = analyze(s);
  EXPECT_EQ(r.vertices, 0u);
  EXPECT_EQ(r.components, 0u);
  EXPECT_FALSE(r.closed);
  // No face: an empty surface, manifold and orientable, of genus 0 (the same for points).
  EXPECT_EQ(r.genus, std::optional<long>(0));
  s.positions = {{0, 0, 0}, {1, 0, 0}};
  r = analyze(s);
  EXPECT_TRUE(r.manifold && r.orientable);
  EXPECT_EQ(r.genus, std::optional<long>(0));
  auto rm = analyze(SurfaceMesh());
  EXPECT_EQ(rm.vertices, 0u);
  EXPECT_EQ(rm.components, 0u);
  EXPECT_EQ(rm.genus, std::optional<long>(0));
}

}  // namespace
}  // namespace geom
