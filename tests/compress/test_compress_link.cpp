// The decoder links triangle meshes in one pass (link_triangles) instead of add_face per
// face: the same mesh as add_face on manifold input, fans at non-manifold vertices linked so
// rotation meets them all, and what add_face refuses refused, also from corrupt streams.

#include "compress/meshes.h"

#include <geom/compress/container/codec.h>
#include <geom/compress/container/mesh_tables.h>
#include <geom/core/validate.h>

#include <gtest/gtest.h>

#include <map>
#include <random>
#include <set>

namespace geom {
namespace {

using codec::detail::kNone;
using codec::detail::link_triangles;

struct Linked {
  std::vector<std::uint32_t> vertex, twin;
};

/// Corners and twins of a triangle list (corner i: vertex[i] → vertex of the next corner).
Linked corners_of(const std::vector<std::vector<std::uint32_t>>& faces) {
  Linked l;
  for (const auto& f : faces) l.vertex.insert(l.vertex.end(), f.begin(), f.end());
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> corner;
  auto to = [&](std::uint32_t i) { return l.vertex[i % 3 == 2 ? i - 2 : i + 1]; };
  for (std::uint32_t i = 0; i < l.vertex.size(); ++i) corner[{l.vertex[i], to(i)}] = i;
  l.twin.assign(l.vertex.size(), kNone);
  for (std::uint32_t i = 0; i < l.vertex.size(); ++i)
    if (auto it = corner.find({to(i), l.vertex[i]}); it != corner.end()) l.twin[i] = it->second;
  return l;
}

SurfaceMesh link(const test::Arrays& a, const Linked& l) {
  SurfaceMesh m;
  for (const Point& p : a.points) m.add_vertex(p);
  link_triangles(m, l.vertex, l.twin, 77);
  return m;
}

SurfaceMesh link(const test::Arrays& a) { return link(a, corners_of(a.faces)); }

/// Every halfedge's vertex and next, every face's halfedge, and boundary vertices' outgoing
/// halfedge agree with add_face's mesh.
void expect_same_as_add_face(const test::Arrays& a) {
  const SurfaceMesh ref = a.build();
  const SurfaceMesh m = link(a);
  ASSERT_TRUE(validate(m).ok());
  ASSERT_EQ(m.n_edges(), ref.n_edges());
  ASSERT_EQ(m.n_faces(), ref.n_faces());
  for (Halfedge h : ref.halfedges()) {
    EXPECT_EQ(m.to_vertex(h), ref.to_vertex(h)) << h.idx();
    EXPECT_EQ(m.next(h), ref.next(h)) << h.idx();
    EXPECT_EQ(m.face(h), ref.face(h)) << h.idx();
  }
  for (Face f : ref.faces()) EXPECT_EQ(m.halfedge(f), ref.halfedge(f));
  // An interior vertex may start its rotation anywhere; a boundary one at its gap.
  for (Vertex v : ref.vertices()) {
    if (ref.is_boundary(v)) {
      EXPECT_EQ(m.halfedge(v), ref.halfedge(v)) << v.idx();
    }
    if (m.halfedge(v).is_valid()) {
      EXPECT_EQ(m.from_vertex(m.halfedge(v)), v);
    }
  }
}

test::Arrays triangulated(const test::Arrays& a) {
  test::Arrays t{a.points, {}};
  for (const auto& f : a.faces)
    for (std::size_t i = 1; i + 1 < f.size(); ++i) t.faces.push_back({f[0], f[i], f[i + 1]});
  return t;
}

/// Three triangles meeting only at vertex 0 (three fans, three boundary gaps).
test::Arrays three_fans() {
  test::Arrays a;
  a.points.push_back({0, 0, 0});
  for (int k = 0; k < 6; ++k) a.points.push_back({std::cos(k * 1.0), std::sin(k * 1.0), 0.1 * k});
  a.faces = {{0, 1, 2}, {0, 3, 4}, {0, 5, 6}};
  return a;
}

TEST(LinkTriangles, SameMeshAsAddFace) {
  expect_same_as_add_face(test::grid(6, 4));
  expect_same_as_add_face(test::torus(9, 7));
  expect_same_as_add_face(triangulated(test::holey_slab(2, false)));
  expect_same_as_add_face(test::torus(6, 5).shuffled(3));
  test::Arrays several = test::grid(3, 3);
  several.append(test::torus(5, 4), {10, 0, 0});
  several.points.push_back({0, 0, 9});  // isolated
  expect_same_as_add_face(several);
}

TEST(LinkTriangles, FansAtANonManifoldVertexAreAllReached) {
  const SurfaceMesh m = link(three_fans());
  ASSERT_TRUE(validate(m).ok());
  std::set<std::uint32_t> around;
  for (Halfedge h : m.outgoing(Vertex(0))) around.insert(m.to_vertex(h).idx());
  EXPECT_EQ(around, (std::set<std::uint32_t>{1, 2, 3, 4, 5, 6}));
  EXPECT_TRUE(m.is_boundary(m.halfedge(Vertex(0))));
}

TEST(LinkTriangles, RefusesWhatAddFaceRefuses) {
  // A closed fan at vertex 0 (a tetrahedron) touched by another triangle.
  test::Arrays a;
  for (int k = 0; k < 6; ++k) a.points.push_back({k * 1.0, k * k * 1.0, k * k * k * 1.0});
  a.faces = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}, {0, 4, 5}};
  EXPECT_THROW(link(a), DecodeError);
  // Two edges 0 → 1.
  a.faces = {{0, 1, 2}, {0, 1, 3}};
  EXPECT_THROW(link(a), DecodeError);
  // A repeated vertex.
  a.faces = {{0, 0, 1}};
  EXPECT_THROW(link(a), DecodeError);
  // Twins that do not reverse their edges.
  a.faces = {{0, 1, 2}, {1, 0, 3}};
  Linked l = corners_of(a.faces);
  std::swap(l.twin[0], l.twin[1]);
  try {
    link(a, l);
    FAIL();
  } catch (const DecodeError& e) {
    EXPECT_EQ(e.offset(), 77u);
  }
}

/// The fan check runs on all cores; its error must still name the lowest bad vertex, as a
/// serial check would, however the vertices are scheduled.
TEST(LinkTriangles, ErrorNamesTheLowestBadVertexOnAnyCore) {
  // A closed fan (a tetrahedron) at its first vertex, touched there by another triangle.
  test::Arrays defect;
  for (int k = 0; k < 6; ++k) defect.points.push_back({k * 1.0, k * k * 1.0, k * k * k * 1.0});
  defect.faces = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}, {0, 4, 5}};
  test::Arrays a = test::grid(90, 90);  // 8281 vertices: several blocks of the parallel check
  const auto first = static_cast<std::uint32_t>(a.points.size());
  a.append(defect, {0, 0, 5});
  a.append(test::grid(90, 90), {0, 0, 10});
  a.append(defect, {0, 0, 15});
  const std::string want = "vertex " + std::to_string(first) + " is shared by faces";
  for (int run = 0; run < 20; ++run) {
    try {
      link(a);
      FAIL();
    } catch (const DecodeError& e) {
      EXPECT_NE(std::string(e.what()).find(want), std::string::npos) << e.what();
    }
  }
}

TEST(LinkTriangles, ThreeFansRoundTrip) {
  const SurfaceMesh in = three_fans().build();
  for (bool preserve : {false, true}) {
    const auto d = decompress(compress(in, {.preserve_order = preserve}).bytes);
    ASSERT_TRUE(validate(d.mesh).ok());
    EXPECT_EQ(d.mesh.n_faces(), 3u);
    EXPECT_EQ(d.mesh.n_edges(), 9u);
  }
}

/// Corrupt triangle streams take link_triangles: an error or a valid mesh, never a crash.
TEST(LinkTriangles, BitFlippedTriangleStreamsNeverCrash) {
  std::mt19937 rng(4321);
  test::Arrays a = test::torus(8, 6);
  a.append(triangulated(test::holey_slab(1, false)), {10, 0, 0});
  a.append(three_fans(), {0, 10, 0});
  for (bool preserve : {false, true}) {
    const auto bytes = compress(a.build(), {.preserve_order = preserve}).bytes;
    for (int trial = 0; trial < 2500; ++trial) {
      auto bad = bytes;
      const int flips = 1 + static_cast<int>(rng() % 3);
      for (int i = 0; i < flips; ++i)
        bad[rng() % bad.size()] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
      try {
        const auto d = decompress(bad);
        EXPECT_TRUE(validate(d.mesh).ok());
      } catch (const DecodeError&) {
      }
    }
  }
}

}  // namespace
}  // namespace geom
