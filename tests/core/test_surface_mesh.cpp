// Unit tests of SurfaceMesh: construction, navigation, properties, editing. Every mutation
// is followed by validate(), the habit that catches connectivity bugs where they are made.

#include <geom/core/surface_mesh.h>
#include <geom/core/validate.h>

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <vector>

namespace geom {
namespace {

#define EXPECT_VALID(m)                              \
  do {                                               \
    auto report_ = validate(m);                      \
    EXPECT_TRUE(report_.ok()) << report_.to_string(); \
  } while (0)

SurfaceMesh tetrahedron() {
  SurfaceMesh m;
  Vertex a = m.add_vertex({0, 0, 0}), b = m.add_vertex({1, 0, 0}), c = m.add_vertex({0, 1, 0}),
         d = m.add_vertex({0, 0, 1});
  m.add_triangle(a, c, b);
  m.add_triangle(a, b, d);
  m.add_triangle(b, c, d);
  m.add_triangle(c, a, d);
  return m;
}

// An n×n grid of quads (or triangles) in the plane z = 0.
SurfaceMesh grid(int n, bool triangles) {
  SurfaceMesh m;
  std::vector<Vertex> v;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) v.push_back(m.add_vertex({double(i), double(j), 0}));
  auto at = [&](int i, int j) { return v[j * (n + 1) + i]; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (triangles) {
        m.add_triangle(at(i, j), at(i + 1, j), at(i + 1, j + 1));
        m.add_triangle(at(i, j), at(i + 1, j + 1), at(i, j + 1));
      } else {
        m.add_quad(at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
      }
    }
  return m;
}

std::size_t euler(const SurfaceMesh& m) {
  return m.n_vertices() + m.n_faces() - m.n_edges();
}

TEST(Handles, CompareOnlyWithTheirOwnKind) {
  static_assert(!std::is_convertible_v<Vertex, Face>);
  static_assert(!std::equality_comparable_with<Vertex, Face>);
  static_assert(sizeof(Vertex) == 4 && sizeof(Halfedge) == 4);
  EXPECT_FALSE(Vertex().is_valid());
  EXPECT_EQ(Vertex(3), Vertex(3));
  EXPECT_LT(Face(1), Face(2));
}

TEST(SurfaceMesh, TetrahedronCountsAndNavigation) {
  SurfaceMesh m = tetrahedron();
  EXPECT_VALID(m);
  EXPECT_EQ(m.n_vertices(), 4u);
  EXPECT_EQ(m.n_edges(), 6u);
  EXPECT_EQ(m.n_halfedges(), 12u);
  EXPECT_EQ(m.n_faces(), 4u);
  EXPECT_EQ(euler(m), 2u);
  for (Vertex v : m.vertices()) {
    EXPECT_EQ(m.valence(v), 3u);
    EXPECT_FALSE(m.is_boundary(v));
  }
  for (Halfedge h : m.halfedges()) {
    EXPECT_EQ(SurfaceMesh::opposite(h).idx(), h.idx() ^ 1u);
    EXPECT_EQ(SurfaceMesh::edge(h).idx(), h.idx() / 2);
    EXPECT_EQ(m.next(m.next(m.next(h))), h);
  }
  EXPECT_TRUE(m.is_triangle_mesh());
}

TEST(SurfaceMesh, FaceCornersComeBackInInputOrder) {
  SurfaceMesh m;
  std::vector<Vertex> v;
  for (int i = 0; i < 5; ++i) v.push_back(m.add_vertex({std::cos(i * 1.2566), std::sin(i * 1.2566), 0}));
  Face f = m.add_face({v[0], v[1], v[2], v[3], v[4]});
  std::vector<Vertex> corners(m.vertices(f).begin(), m.vertices(f).end());
  EXPECT_EQ(corners, v);
  EXPECT_EQ(m.valence(f), 5u);
  EXPECT_TRUE(m.is_boundary(f));
}

TEST(SurfaceMesh, WingsAreTheFourNeighbouringEdges) {
  SurfaceMesh m = grid(2, true);
  for (Edge e : m.edges()) {
    EdgeWings w = m.wings(e);
    EXPECT_EQ(m.find_edge(w.v0, w.v1), e);
    if (w.f0.is_valid()) {
      EXPECT_EQ(m.vertex(w.next0, 0) == w.v1 || m.vertex(w.next0, 1) == w.v1, true);
      EXPECT_TRUE(m.vertex(w.prev0, 0) == w.v0 || m.vertex(w.prev0, 1) == w.v0);
    } else {
      EXPECT_FALSE(w.prev0.is_valid());
    }
    EXPECT_EQ(w.f0.is_valid() && w.f1.is_valid(), !m.is_boundary(e));
  }
}

TEST(SurfaceMesh, BoundaryVertexKeepsBoundaryHalfedge) {
  SurfaceMesh m = grid(3, false);
  EXPECT_VALID(m);
  std::size_t boundary = 0;
  for (Vertex v : m.vertices())
    if (m.is_boundary(v)) {
      ++boundary;
      EXPECT_TRUE(m.is_boundary(m.halfedge(v)));
    }
  EXPECT_EQ(boundary, 12u);
  EXPECT_EQ(euler(m), 1u);
}

TEST(SurfaceMesh, FacesAddedInAnyOrderFormOneFan) {
  // A fan around a centre vertex, added out of order so patches must be re-linked.
  SurfaceMesh m;
  Vertex c = m.add_vertex({0, 0, 0});
  std::vector<Vertex> r;
  for (int i = 0; i < 6; ++i) r.push_back(m.add_vertex({std::cos(i), std::sin(i), 0}));
  for (int i : {0, 3, 1, 4, 2, 5}) {
    m.add_triangle(c, r[i], r[(i + 1) % 6]);
    EXPECT_VALID(m);
  }
  EXPECT_FALSE(m.is_boundary(c));
  EXPECT_EQ(m.valence(c), 6u);
}

TEST(SurfaceMesh, AddFaceRejectsComplexEdgeAndLeavesMeshUnchanged) {
  SurfaceMesh m = tetrahedron();
  Vertex e = m.add_vertex({1, 1, 1});
  EXPECT_THROW(m.add_triangle(Vertex(0), Vertex(1), e), TopologyError);  // interior vertex
  SurfaceMesh g = grid(1, true);
  // The diagonal 0 -> 3 already has a face on this side.
  EXPECT_THROW(g.add_triangle(Vertex(0), Vertex(3), g.add_vertex({5, 5, 5})), TopologyError);
  EXPECT_THROW(g.add_triangle(Vertex(0), Vertex(0), Vertex(1)), TopologyError);
  EXPECT_THROW(g.add_face(std::vector<Vertex>{Vertex(0), Vertex(1)}), TopologyError);
  EXPECT_EQ(g.n_faces(), 2u);
  EXPECT_VALID(g);
}

TEST(SurfaceMesh, BowTieVertexIsRepresentableButNotManifold) {
  SurfaceMesh m;
  Vertex c = m.add_vertex({0, 0, 0});
  Vertex a = m.add_vertex({1, 0, 0}), b = m.add_vertex({1, 1, 0});
  Vertex d = m.add_vertex({-1, 0, 0}), e = m.add_vertex({-1, -1, 0});
  m.add_triangle(c, a, b);
  m.add_triangle(c, d, e);
  EXPECT_VALID(m);
  EXPECT_FALSE(m.is_manifold(c));
  EXPECT_TRUE(m.is_manifold(a));
}

// resize() is the bulk path for builders that compute connectivity arrays: the new
// elements start unlinked, and linking them by index reproduces a mesh built face by face.
TEST(SurfaceMesh, ResizeThenLinkByIndexRebuildsTheTetrahedron) {
  const SurfaceMesh ref = tetrahedron();
  SurfaceMesh m;
  auto weight = m.add_property<Vertex, double>("v:weight", 7.0);
  m.resize(ref.vertices_size(), ref.edges_size(), ref.faces_size());
  EXPECT_EQ(m.n_vertices(), 4u);
  EXPECT_EQ(m.n_edges(), 6u);
  EXPECT_EQ(m.n_halfedges(), 12u);
  EXPECT_EQ(m.n_faces(), 4u);
  for (Vertex v : m.vertices()) {
    EXPECT_FALSE(m.halfedge(v).is_valid());
    EXPECT_EQ(weight[v], 7.0);
    EXPECT_EQ(m.position(v), Point::Zero());
  }
  for (Halfedge h : m.halfedges()) {
    EXPECT_FALSE(m.to_vertex(h).is_valid());
    EXPECT_FALSE(m.next(h).is_valid());
    EXPECT_FALSE(m.face(h).is_valid());
  }
  EXPECT_FALSE(validate(m).ok());  // unlinked halfedges are reported, not assumed

  for (Halfedge h : ref.halfedges()) {
    m.set_vertex(h, ref.to_vertex(h));
    m.set_next(h, ref.next(h));
    m.set_face(h, ref.face(h));
  }
  for (Vertex v : ref.vertices()) {
    m.set_halfedge(v, ref.halfedge(v));
    m.position(v) = ref.position(v);
  }
  for (Face f : ref.faces()) m.set_halfedge(f, ref.halfedge(f));
  EXPECT_VALID(m);
  EXPECT_EQ(euler(m), 2u);
  for (Halfedge h : ref.halfedges()) EXPECT_EQ(m.prev(h), ref.prev(h));
}

TEST(SurfaceMesh, ResizeGrowsOnlyAndKeepsExistingElements) {
  SurfaceMesh m = grid(2, false);
  const std::size_t nv = m.n_vertices(), ne = m.n_edges(), nf = m.n_faces();
  auto mark = m.add_property<Face, int>("f:mark", -1);
  mark[Face(0)] = 5;
  m.resize(nv + 1, ne, nf);  // one isolated vertex, linked to nothing: still valid
  EXPECT_EQ(m.n_vertices(), nv + 1);
  EXPECT_TRUE(m.is_isolated(Vertex(static_cast<std::uint32_t>(nv))));
  EXPECT_EQ(mark[Face(0)], 5);
  EXPECT_EQ(m.valence(Face(0)), 4u);
  EXPECT_VALID(m);
  EXPECT_THROW(m.resize(nv, ne, nf), InvalidArgument);
  EXPECT_THROW(m.resize(nv + 1, ne, nf - 1), InvalidArgument);
  EXPECT_EQ(m.n_vertices(), nv + 1);
  EXPECT_EQ(m.n_faces(), nf);
  EXPECT_VALID(m);
}

// Growth by megabytes maps the new pages first (detail::resize_prefaulted); the elements
// must come out exactly as a small resize makes them, and existing ones must survive.
TEST(SurfaceMesh, LargeResizeFillsLikeASmallOne) {
  SurfaceMesh m = tetrahedron();
  auto weight = m.add_property<Vertex, double>("v:weight", 7.0);
  weight[Vertex(2)] = 3.0;
  constexpr std::uint32_t kN = 400000;  // > 4 MiB of halfedges and of positions
  m.resize(kN, 2 * kN, kN);
  EXPECT_EQ(m.n_vertices(), kN);
  EXPECT_EQ(m.n_halfedges(), 4u * kN);
  EXPECT_EQ(weight[Vertex(2)], 3.0);
  EXPECT_EQ(m.to_vertex(Halfedge(0)), tetrahedron().to_vertex(Halfedge(0)));
  for (std::uint32_t i : {4u, 12345u, kN - 1}) {
    EXPECT_FALSE(m.halfedge(Vertex(i)).is_valid());
    EXPECT_EQ(m.position(Vertex(i)), Point::Zero());
    EXPECT_EQ(weight[Vertex(i)], 7.0);
    EXPECT_FALSE(m.is_deleted(Vertex(i)));
    EXPECT_FALSE(m.halfedge(Face(i)).is_valid());
  }
  for (std::uint32_t h : {12u, 777777u, 4 * kN - 1}) {
    EXPECT_FALSE(m.to_vertex(Halfedge(h)).is_valid());
    EXPECT_FALSE(m.next(Halfedge(h)).is_valid());
    EXPECT_FALSE(m.prev(Halfedge(h)).is_valid());
    EXPECT_FALSE(m.face(Halfedge(h)).is_valid());
    EXPECT_FALSE(m.is_deleted(Halfedge(h)));
  }
}

TEST(Properties, TypedNamedAddGetRemove) {
  SurfaceMesh m = tetrahedron();
  auto w = m.add_property<Vertex, double>("v:weight", 1.5);
  EXPECT_EQ(w[Vertex(2)], 1.5);
  w[Vertex(2)] = 3.0;
  EXPECT_THROW((m.add_property<Vertex, double>("v:weight")), InvalidArgument);
  EXPECT_FALSE((m.get_property<Vertex, int>("v:weight")));  // wrong type
  auto same = m.get_property<Vertex, double>("v:weight");
  ASSERT_TRUE(same);
  EXPECT_EQ(same[Vertex(2)], 3.0);
  Vertex v = m.add_vertex({2, 2, 2});
  EXPECT_EQ(w[v], 1.5);  // new elements get the default; the handle survived reallocation
  m.remove_property(w);
  EXPECT_FALSE(w);
  EXPECT_FALSE(m.has_property<Vertex>("v:weight"));
  EXPECT_THROW(m.remove_property<Vertex>(SurfaceMesh::kPositions), InvalidArgument);
  const SurfaceMesh& cm = m;
  Property<Vertex, const Point> pos = cm.positions();
  EXPECT_EQ(pos[Vertex(1)], Point(1, 0, 0));
}

TEST(Properties, CopyIsDeep) {
  SurfaceMesh a = tetrahedron();
  auto pa = a.add_property<Face, int>("f:id", 7);
  SurfaceMesh b = a;
  auto pb = b.get_property<Face, int>("f:id");
  pb[Face(0)] = 9;
  EXPECT_EQ(pa[Face(0)], 7);
  b.position(Vertex(0)) = Point(5, 5, 5);
  EXPECT_EQ(a.position(Vertex(0)), Point(0, 0, 0));
  EXPECT_VALID(b);
}

TEST(Editing, FlipKeepsCountsAndRefusesBoundaryOrDuplicate) {
  SurfaceMesh m = grid(2, true);
  std::size_t flips = 0;
  for (Edge e : m.edges()) {
    if (m.is_boundary(e)) {
      EXPECT_FALSE(m.can_flip(e));
      EXPECT_THROW(m.flip(e), TopologyError);
      continue;
    }
    if (!m.can_flip(e)) continue;
    Vertex a = m.vertex(e, 0), b = m.vertex(e, 1);
    m.flip(e);
    ++flips;
    EXPECT_VALID(m);
    EXPECT_FALSE(m.find_edge(a, b).is_valid());
  }
  EXPECT_GT(flips, 0u);
  EXPECT_EQ(m.n_faces(), 8u);
  EXPECT_EQ(m.n_edges(), 16u);
  SurfaceMesh t = tetrahedron();
  for (Edge e : t.edges()) EXPECT_FALSE(t.can_flip(e));  // would duplicate an edge
}

TEST(Editing, SplitEdgeInteriorAndBoundary) {
  SurfaceMesh m = grid(1, true);
  Edge diag = m.find_edge(Vertex(0), Vertex(3));
  ASSERT_TRUE(diag.is_valid());
  Vertex v = m.split_edge(diag, {0.5, 0.5, 0});
  EXPECT_VALID(m);
  EXPECT_EQ(m.n_faces(), 4u);
  EXPECT_EQ(m.valence(v), 4u);
  Edge side = m.find_edge(Vertex(0), Vertex(1));
  Vertex w = m.split_edge(side, {0.5, 0, 0});
  EXPECT_VALID(m);
  EXPECT_EQ(m.n_faces(), 5u);
  EXPECT_TRUE(m.is_boundary(w));
  EXPECT_EQ(euler(m), 1u);
  SurfaceMesh q = grid(1, false);
  EXPECT_THROW(q.split_edge(Edge(0), {0, 0, 0}), TopologyError);
}

TEST(Editing, InsertVertexOnPolygonEdge) {
  SurfaceMesh m = grid(2, false);
  std::size_t faces = m.n_faces();
  for (Edge e : m.edges()) {
    if (e.idx() >= 6) break;
    m.insert_vertex(e, (m.position(m.vertex(e, 0)) + m.position(m.vertex(e, 1))) / 2);
    EXPECT_VALID(m);
  }
  EXPECT_EQ(m.n_faces(), faces);
  EXPECT_EQ(euler(m), 1u);
}

TEST(Editing, SplitFaceMakesAFan) {
  SurfaceMesh m = grid(1, false);
  Vertex v = m.split_face(Face(0), {0.5, 0.5, 0});
  EXPECT_VALID(m);
  EXPECT_EQ(m.n_faces(), 4u);
  EXPECT_EQ(m.valence(v), 4u);
  EXPECT_TRUE(m.is_triangle_mesh());
}

TEST(Editing, InsertEdgeSplitsAFace) {
  SurfaceMesh m = grid(1, false);
  Halfedge h0 = m.halfedge(Face(0));
  Halfedge h1 = m.next(m.next(h0));
  Halfedge a = m.insert_edge(h0, h1);
  EXPECT_VALID(m);
  EXPECT_EQ(m.n_faces(), 2u);
  EXPECT_EQ(m.from_vertex(a), m.to_vertex(h0));
  EXPECT_THROW(m.insert_edge(h0, m.next(h0)), TopologyError);
}

TEST(Editing, CollapseRespectsLinkCondition) {
  SurfaceMesh t = tetrahedron();
  for (Halfedge h : t.halfedges()) EXPECT_FALSE(t.can_collapse(h));
  SurfaceMesh m = grid(4, true);
  std::size_t collapses = 0;
  std::mt19937 rng(7);
  for (int round = 0; round < 200; ++round) {
    Halfedge h(static_cast<std::uint32_t>(rng() % m.halfedges_size()));
    if (m.is_deleted(h) || !m.can_collapse(h)) continue;
    std::size_t chi = euler(m);
    m.collapse(h);
    ++collapses;
    EXPECT_VALID(m);
    EXPECT_EQ(euler(m), chi);
  }
  EXPECT_GT(collapses, 5u);
  CompactRemap remap = m.compact();
  EXPECT_VALID(m);
  EXPECT_FALSE(m.has_garbage());
  EXPECT_EQ(remap.vertices.size(), 25u);
}

TEST(Editing, DeleteFaceVertexEdgeThenCompact) {
  SurfaceMesh m = grid(3, true);
  auto id = m.add_property<Vertex, int>("v:id");
  for (Vertex v : m.vertices()) id[v] = static_cast<int>(v.idx());
  m.delete_face(Face(0));
  EXPECT_VALID(m);
  m.delete_vertex(Vertex(5));
  EXPECT_VALID(m);
  m.delete_edge(m.find_edge(Vertex(14), Vertex(15)));
  EXPECT_VALID(m);
  EXPECT_TRUE(m.has_garbage());
  std::size_t faces = m.n_faces(), vertices = m.n_vertices();
  CompactRemap remap = m.compact();
  EXPECT_VALID(m);
  EXPECT_EQ(m.n_faces(), faces);
  EXPECT_EQ(m.faces_size(), faces);
  EXPECT_EQ(m.vertices_size(), vertices);
  EXPECT_FALSE(remap.vertices[5].is_valid());
  for (std::uint32_t old = 0; old < remap.vertices.size(); ++old) {
    if (!remap.vertices[old].is_valid()) continue;
    EXPECT_EQ(id[remap.vertices[old]], int(old));
  }
}

TEST(Editing, DeletingEveryFaceEmptiesTheMesh) {
  SurfaceMesh m = tetrahedron();
  for (Face f : m.faces()) m.delete_face(f);
  EXPECT_VALID(m);
  EXPECT_EQ(m.n_faces(), 0u);
  EXPECT_EQ(m.n_edges(), 0u);
  EXPECT_EQ(m.n_vertices(), 0u);
  m.compact();
  EXPECT_TRUE(m.is_empty());
}

TEST(Memory, BytesPerElementDoNotCreep) {
  // The budget documented in surface_mesh.h: 5 B per vertex, 33 B per edge, 5 B per face.
  EXPECT_EQ(SurfaceMesh::kBytesPerVertex, 5u);
  EXPECT_EQ(SurfaceMesh::kBytesPerEdge, 33u);
  EXPECT_EQ(SurfaceMesh::kBytesPerFace, 5u);
  SurfaceMesh m;
  m.reserve(1000, 3000, 2000);
  EXPECT_EQ(m.connectivity_bytes(), 1000 * 5u + 3000 * 33u + 2000 * 5u);
  SurfaceMesh g = grid(10, true);
  EXPECT_EQ(g.property_names<Vertex>().size(), 1u);  // only positions by default
  EXPECT_TRUE(g.property_names<Face>().empty());
}

}  // namespace
}  // namespace geom

namespace geom {
namespace {

TEST(Editing, CollapseRefusesToLeaveADanglingApexNextToAPolygon) {
  // A triangle (a, b, c) whose apex c has valence 2, glued to a quad (b, a, c... ) along
  // both of c's edges: collapsing a into b would leave c hanging inside the quad.
  SurfaceMesh m;
  Vertex a = m.add_vertex({0, 0, 0}), b = m.add_vertex({1, 0, 0}), c = m.add_vertex({0.5, 1, 0});
  Vertex d = m.add_vertex({0.5, -1, 0});
  m.add_triangle(a, b, c);
  m.add_quad(b, d, a, c);
  EXPECT_VALID(m);
  EXPECT_EQ(m.valence(c), 2u);
  Halfedge h = m.find_halfedge(a, b);
  EXPECT_FALSE(m.can_collapse(h));
  EXPECT_THROW(m.collapse(h), TopologyError);
  EXPECT_VALID(m);
}

TEST(Validate, FlagsAFaceThatVisitsAVertexTwice) {
  SurfaceMesh m;
  Vertex a = m.add_vertex({0, 0, 0}), b = m.add_vertex({1, 0, 0}), c = m.add_vertex({0, 1, 0});
  m.add_triangle(a, b, c);
  // Re-point one halfedge so the loop passes through a twice: a broken invariant by hand.
  Halfedge h = m.find_halfedge(b, c);
  m.set_vertex(h, a);
  auto report = validate(m);
  EXPECT_FALSE(report.ok());
  bool named = false;
  for (const auto& p : report.problems) named |= p.find("visits a vertex twice") != std::string::npos;
  EXPECT_TRUE(named) << report.to_string();
}

}  // namespace
}  // namespace geom
