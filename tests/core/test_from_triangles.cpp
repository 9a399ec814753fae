// mesh_from_triangles(): the bulk build gives the mesh add_triangle gives, element for element,
// and takes the add_triangle path (same mesh, same error) on input that is not a clean manifold.

#include <geom/core/from_triangles.h>
#include <geom/core/validate.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <random>
#include <string>

#include "soup_shapes.h"

namespace geom {
namespace {

using namespace geom::test;
using Tri = std::array<std::uint32_t, 3>;

struct Input {
  std::vector<Point> positions;
  std::vector<Tri> triangles;
};

// Polygons split into fans from their first corner.
Input triangulated(const PolygonSoup& s) {
  Input in{s.positions, {}};
  for (std::size_t f = 0; f < s.n_faces(); ++f) {
    auto c = s.face(f);
    for (std::size_t i = 1; i + 1 < c.size(); ++i) in.triangles.push_back({c[0], c[i], c[i + 1]});
  }
  return in;
}

// The reference: add_triangle in input order, or the message it throws.
struct Reference {
  std::optional<SurfaceMesh> mesh;
  std::string error;
};
Reference one_by_one(const Input& in) {
  Reference r;
  try {
    SurfaceMesh m;
    for (const Point& p : in.positions) m.add_vertex(p);
    for (const Tri& t : in.triangles) m.add_triangle(Vertex(t[0]), Vertex(t[1]), Vertex(t[2]));
    r.mesh = std::move(m);
  } catch (const TopologyError& e) {
    r.error = e.what();
  }
  return r;
}

// Same elements and links; an interior vertex may pick another outgoing halfedge.
void expect_same(const SurfaceMesh& got, const SurfaceMesh& want) {
  auto report = validate(got);
  ASSERT_TRUE(report.ok()) << report.to_string();
  ASSERT_EQ(got.vertices_size(), want.vertices_size());
  ASSERT_EQ(got.edges_size(), want.edges_size());
  ASSERT_EQ(got.faces_size(), want.faces_size());
  for (Vertex v : want.vertices()) {
    EXPECT_EQ(got.position(v), want.position(v));
    EXPECT_EQ(got.is_boundary(v), want.is_boundary(v)) << v;
    EXPECT_EQ(got.valence(v), want.valence(v)) << v;
    if (want.is_boundary(v)) {
      EXPECT_EQ(got.halfedge(v), want.halfedge(v)) << v;
    }
  }
  for (Face f : want.faces()) EXPECT_EQ(got.halfedge(f), want.halfedge(f)) << f;
  for (Halfedge h : want.halfedges()) {
    EXPECT_EQ(got.to_vertex(h), want.to_vertex(h)) << h;
    EXPECT_EQ(got.next(h), want.next(h)) << h;
    EXPECT_EQ(got.face(h), want.face(h)) << h;
  }
}

void expect_like_add_triangle(const Input& in) {
  Reference want = one_by_one(in);
  std::string error;
  std::optional<SurfaceMesh> got;
  try {
    got = mesh_from_triangles(in.positions, in.triangles);
  } catch (const TopologyError& e) {
    error = e.what();
  }
  ASSERT_EQ(error, want.error);
  ASSERT_EQ(got.has_value(), want.mesh.has_value());
  if (got) expect_same(*got, *want.mesh);
}

Input shuffled(Input in, unsigned seed) {
  std::mt19937 rng(seed);
  std::shuffle(in.triangles.begin(), in.triangles.end(), rng);
  return in;
}

TEST(FromTriangles, ClosedSurfaces) {
  expect_like_add_triangle(triangulated(tetrahedron_soup()));
  expect_like_add_triangle(triangulated(cube_soup()));
  expect_like_add_triangle(triangulated(holed_plate(3)));
  expect_like_add_triangle(triangulated(torus_soup(12, 9)));
  const std::vector<Point> three{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  expect_like_add_triangle(Input{three, {{0, 1, 2}, {0, 2, 1}}});  // two faces, one closed surface
}

TEST(FromTriangles, OpenSurfacesWithHoles) {
  expect_like_add_triangle(Input{{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}});
  expect_like_add_triangle(triangulated(disk_soup(6)));
  expect_like_add_triangle(triangulated(annulus_soup(10, 3)));
  expect_like_add_triangle(triangulated(torus_soup(8, 6, true)));
  Input holes = triangulated(disk_soup(8));
  // Three squares apart from each other and from the rim, so every vertex keeps one fan.
  for (std::size_t t : {87u, 86u, 27u, 26u, 19u, 18u}) holes.triangles.erase(holes.triangles.begin() + t);
  expect_like_add_triangle(holes);
}

TEST(FromTriangles, AnyFaceOrder) {
  for (unsigned seed = 1; seed <= 5; ++seed) {
    expect_like_add_triangle(shuffled(triangulated(torus_soup(9, 7)), seed));
    expect_like_add_triangle(shuffled(triangulated(annulus_soup(8, 3)), seed));
  }
}

TEST(FromTriangles, ComponentsAndIsolatedVertices) {
  expect_like_add_triangle(triangulated(merged(torus_soup(6, 5), translated(disk_soup(3), {9, 0, 0}))));
  Input lonely = triangulated(tetrahedron_soup());
  lonely.positions.insert(lonely.positions.begin() + 2, Point(5, 5, 5));
  for (Tri& t : lonely.triangles)
    for (auto& c : t) c += c >= 2;
  lonely.positions.push_back(Point(7, 7, 7));
  expect_like_add_triangle(lonely);
  expect_like_add_triangle(Input{{Point(0, 0, 0), Point(1, 0, 0)}, {}});
  expect_like_add_triangle(Input{});
}

TEST(FromTriangles, NonManifoldInputTakesTheFaceByFacePath) {
  expect_like_add_triangle(triangulated(bowtie_soup()));  // two boundary fans at one vertex: kept
  Input two_cones = triangulated(merged(tetrahedron_soup(), tetrahedron_soup()));
  for (Tri& t : two_cones.triangles)
    for (auto& c : t) c = c == 4 ? 0 : c;  // two closed fans at vertex 0: add_face refuses
  expect_like_add_triangle(two_cones);
  expect_like_add_triangle(triangulated(three_fin_soup()));
  expect_like_add_triangle(triangulated(moebius_soup(7)));
}

TEST(FromTriangles, BadInputThrowsWhatAddTriangleThrows) {
  Input flipped = triangulated(disk_soup(3));
  std::swap(flipped.triangles[4][1], flipped.triangles[4][2]);
  expect_like_add_triangle(flipped);
  Input out_of_range = triangulated(tetrahedron_soup());
  out_of_range.triangles[2][1] = 4;
  expect_like_add_triangle(out_of_range);
  Input repeated = triangulated(tetrahedron_soup());
  repeated.triangles[1][2] = repeated.triangles[1][0];
  expect_like_add_triangle(repeated);
  // The errors must actually have been raised, not both paths quietly succeeding.
  EXPECT_FALSE(one_by_one(flipped).error.empty());
  EXPECT_FALSE(one_by_one(out_of_range).error.empty());
  EXPECT_FALSE(one_by_one(repeated).error.empty());
}

}  // namespace
}  // namespace geom
