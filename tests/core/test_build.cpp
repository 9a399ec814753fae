// build(): soup → valid mesh, every repair reported; to_soup() as its inverse.

#include <geom/core/build.h>
#include <geom/core/topology.h>
#include <geom/core/validate.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "soup_shapes.h"

namespace geom {
namespace {

using namespace geom::test;

#define EXPECT_VALID(m)                               \
  do {                                                \
    auto report_ = validate(m);                       \
    EXPECT_TRUE(report_.ok()) << report_.to_string(); \
  } while (0)

std::vector<std::uint32_t> corners(const SurfaceMesh& m, Face f) {
  std::vector<std::uint32_t> out;
  for (Vertex v : m.vertices(f)) out.push_back(v.idx());
  return out;
}

bool mentions(const BuildReport& r, const std::string& text) {
  return std::any_of(r.messages.begin(), r.messages.end(),
                     [&](const std::string& m) { return m.find(text) != std::string::npos; });
}

TEST(Build, CleanInputIsUnchangedAndKeepsCornerOrder) {
  auto s = torus_soup(10, 7);
  auto [m, r] = build(s);
  EXPECT_VALID(m);
  EXPECT_FALSE(r.changed());
  EXPECT_TRUE(r.messages.empty());
  ASSERT_EQ(m.n_faces(), s.n_faces());
  ASSERT_EQ(m.n_vertices(), s.positions.size());
  for (Face f : m.faces()) {
    auto in = s.face(f.idx());
    EXPECT_EQ(corners(m, f), std::vector<std::uint32_t>(in.begin(), in.end()));
  }
  for (Vertex v : m.vertices()) EXPECT_EQ(m.position(v), s.positions[v.idx()]);
  EXPECT_EQ(r.face_origin.size(), s.n_faces());
  EXPECT_EQ(r.vertex_map[5], Vertex(5));
  EXPECT_EQ(r.vertex_origin[5], 5u);
}

TEST(Build, BoundaryVerticesPointAtBoundaryHalfedges) {
  auto [m, r] = build(disk_soup(3));
  EXPECT_VALID(m);
  for (Vertex v : m.vertices()) {
    bool on_boundary = false;
    for (Halfedge h : m.outgoing(v)) on_boundary |= m.is_boundary(h);
    EXPECT_EQ(m.is_boundary(v), on_boundary);
  }
  EXPECT_EQ(analyze(m).boundary_loops, 1u);
}

TEST(Build, EmptySoupGivesEmptyMesh) {
  PolygonSoup s;
  auto [m, r] = build(s);
  EXPECT_TRUE(m.is_empty());
  EXPECT_FALSE(r.changed());
  s.positions = {{0, 0, 0}, {1, 1, 1}};
  auto b = build(s);
  EXPECT_EQ(b.mesh.n_vertices(), 2u);
  EXPECT_EQ(b.report.unreferenced_vertices, 2u);
  auto d = build(s, {.drop_unreferenced = true});
  EXPECT_EQ(d.mesh.n_vertices(), 0u);
  EXPECT_EQ(d.report.dropped_unreferenced, 2u);
  EXPECT_FALSE(d.report.vertex_map[0].is_valid());
}

// A cube whose faces each carry their own four vertices, as STL-like files store it.
PolygonSoup unwelded_cube(double jitter) {
  auto c = cube_soup();
  PolygonSoup s;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> d(-jitter, jitter);
  for (std::size_t f = 0; f < c.n_faces(); ++f) {
    std::vector<std::uint32_t> ids;
    for (std::uint32_t v : c.face(f)) {
      ids.push_back(static_cast<std::uint32_t>(s.positions.size()));
      s.positions.push_back(c.positions[v] + Point(d(rng), d(rng), d(rng)));
    }
    s.add_face(ids);
  }
  return s;
}

TEST(Build, ExactWeldingMergesDuplicates) {
  auto s = unwelded_cube(0);
  auto none = build(s);
  EXPECT_EQ(none.mesh.n_vertices(), 24u);
  EXPECT_EQ(analyze(none.mesh).components, 6u);
  auto [m, r] = build(s, {.weld_tolerance = 0});
  EXPECT_VALID(m);
  EXPECT_EQ(r.welded_vertices, 16u);
  EXPECT_EQ(m.n_vertices(), 8u);
  EXPECT_TRUE(mentions(r, "welded"));
  auto t = analyze(m);
  EXPECT_TRUE(t.closed);
  EXPECT_EQ(t.genus, 0);
  // Welded vertices map to their representative's output vertex.
  for (std::uint32_t v = 0; v < 24; ++v) ASSERT_TRUE(r.vertex_map[v].is_valid());
  EXPECT_EQ(m.position(r.vertex_map[23]), s.positions[23]);
}

// Each face of the unwelded cube is its own UV chart, as PLY and glTF store one: welding
// joins the positions and must keep every corner's texture coordinate (the seams).
TEST(Build, WeldingKeepsTheSeamsOfSplitVertices) {
  auto s = unwelded_cube(0);
  const TexCoord square[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (std::size_t v = 0; v < s.positions.size(); ++v) {
    s.vertex_texcoords.push_back(square[v % 4] * 0.25 + TexCoord(0.25 * (v / 4 % 4), 0.5 * (v / 16)));
    s.vertex_colors.push_back(Color(v % 4 == 0, 0.5, 0));
    s.vertex_normals.push_back(Normal(0, 0, 1));  // all equal: no crease to keep
  }
  auto [m, r] = build(s, {.weld_tolerance = 0});
  EXPECT_EQ(m.n_vertices(), 8u);
  EXPECT_TRUE(mentions(r, "texture coordinates or normals differ (kept per face corner")) << r.messages.back();
  EXPECT_TRUE(mentions(r, "colour differs"));
  EXPECT_FALSE(m.has_property<Vertex>(prop::kVertexTexCoord));
  EXPECT_TRUE(m.has_property<Vertex>(prop::kVertexNormal));
  EXPECT_FALSE(m.has_property<Halfedge>(prop::kCornerNormal));
  const PolygonSoup back = to_soup(m);
  ASSERT_EQ(back.corner_texcoords.size(), s.face_indices.size());
  for (std::size_t c = 0; c < s.face_indices.size(); ++c)
    EXPECT_EQ(back.corner_texcoords[c], s.vertex_texcoords[s.face_indices[c]]) << "corner " << c;
  // Without welding nothing moves to the corners.
  EXPECT_TRUE(build(s).mesh.has_property<Vertex>(prop::kVertexTexCoord));
}

TEST(Build, ToleranceWeldingIsRelativeToTheBoundingBox) {
  auto s = unwelded_cube(1e-9);
  EXPECT_EQ(build(s, {.weld_tolerance = 0}).mesh.n_vertices(), 24u);
  auto [m, r] = build(s, {.weld_tolerance = 1e-6});
  EXPECT_VALID(m);
  EXPECT_EQ(m.n_vertices(), 8u);
  EXPECT_TRUE(analyze(m).closed);
  // The same cube scaled up by 1e6 welds with the same relative tolerance.
  for (auto& p : s.positions) p *= 1e6;
  EXPECT_EQ(build(s, {.weld_tolerance = 1e-6}).mesh.n_vertices(), 8u);
}

TEST(Build, DropsFacesWithOutOfRangeIndices) {
  auto s = tetrahedron_soup();
  s.add_face({0, 1, 99});
  auto [m, r] = build(s);
  EXPECT_VALID(m);
  EXPECT_EQ(r.dropped_out_of_range, 1u);
  EXPECT_EQ(m.n_faces(), 4u);
  EXPECT_TRUE(mentions(r, "face 4 has index 99"));
  EXPECT_TRUE(r.changed());
}

TEST(Build, DropsDegenerateFaces) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {0.5, 0, 0}, {0, 0, 0}};
  s.add_face({0, 1, 2});     // kept
  s.add_face({0, 0, 1});     // two distinct corners
  s.add_face({0, 1, 3});     // collinear
  s.add_face({0, 4, 1, 3});  // collinear quad
  s.add_face({0, 5, 2});     // two corners at the same place: zero area
  s.add_face({1, 2});        // too short
  s.add_face({0, 1, 0, 2});  // visits vertex 0 twice
  auto [m, r] = build(s);
  EXPECT_VALID(m);
  EXPECT_EQ(r.dropped_degenerate, 6u);
  EXPECT_EQ(m.n_faces(), 1u);
  EXPECT_EQ(r.face_origin, std::vector<std::uint32_t>{0});
  EXPECT_TRUE(mentions(r, "zero area"));
}

TEST(Build, ZeroAreaIsDecidedExactlyAtExtremeScales) {
  for (double scale : {1e-300, 1e-150, 1.0, 1e150, 1e300}) {
    PolygonSoup s;
    // (1, 1 + 2^-52) is not on the line through (0, 0) and (2, 2): a tiny but real area.
    s.positions = {{0, 0, 0}, {2 * scale, 2 * scale, 0}, {scale, scale * (1 + 0x1p-52), 0}, {scale, scale, 0}};
    s.add_face({0, 1, 2});
    s.add_face({0, 1, 3});
    auto r = build(s).report;
    EXPECT_EQ(r.dropped_degenerate, 1u) << scale;
    EXPECT_EQ(r.face_origin, std::vector<std::uint32_t>{0}) << scale;
  }
}

TEST(Build, CollapsesRepeatedConsecutiveCorners) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.add_face({0, 1, 1, 2, 0});
  auto [m, r] = build(s);
  EXPECT_VALID(m);
  EXPECT_EQ(r.collapsed_corners, 1u);
  ASSERT_EQ(m.n_faces(), 1u);
  EXPECT_EQ(corners(m, Face(0)), (std::vector<std::uint32_t>{0, 1, 2}));
}

TEST(Build, DropsDuplicateFaces) {
  auto s = tetrahedron_soup();
  s.add_face({2, 1, 0});  // same corners as face 0 (rotated)
  s.add_face({3, 0, 1});  // same corners as face 1, reversed
  auto [m, r] = build(s);
  EXPECT_VALID(m);
  EXPECT_EQ(r.dropped_duplicate, 2u);
  EXPECT_EQ(m.n_faces(), 4u);
  EXPECT_TRUE(mentions(r, "face 4 repeats face 0"));
  EXPECT_EQ(analyze(m).genus, 0);
  // Two copies of one triangle facing each other: still a duplicate.
  PolygonSoup p;
  p.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  p.add_face({0, 1, 2});
  p.add_face({0, 2, 1});
  auto b = build(p);
  EXPECT_EQ(b.report.dropped_duplicate, 1u);
  EXPECT_EQ(b.mesh.n_faces(), 1u);
}

TEST(Build, SplitsAnEdgeWithThreeFaces) {
  auto s = three_fin_soup();
  auto [m, r] = build(s);
  EXPECT_VALID(m);
  EXPECT_EQ(r.split_nonmanifold_edges, 1u);
  EXPECT_EQ(m.n_faces(), 3u);
  EXPECT_EQ(m.n_vertices(), 7u);  // the extra face gets its own copies of 0 and 1
  EXPECT_EQ(r.vertex_origin[5], 0u);
  EXPECT_EQ(r.vertex_origin[6], 1u);
  EXPECT_TRUE(mentions(r, "edge (0, 1)"));
  EXPECT_TRUE(analyze(m).manifold);
}

TEST(Build, TwoCubesSharingAnEdgeStayClosed) {
  auto s = voxel_surface(2, 2, 1, [](int x, int y, int) { return x == y; });
  auto t = analyze(s);
  EXPECT_EQ(t.nonmanifold_edges, 1u);
  auto [m, r] = build(s);
  EXPECT_VALID(m);
  EXPECT_EQ(r.split_nonmanifold_edges, 1u);
  EXPECT_EQ(m.n_faces(), 12u);
  auto tm = analyze(m);
  EXPECT_TRUE(tm.closed);
  EXPECT_TRUE(tm.manifold);
  EXPECT_EQ(tm.components, 2u);
  EXPECT_EQ(tm.genus, 0);
}

TEST(Build, ManyFacesOnOneEdgeAllKept) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {0, 0, 1}};
  const int k = 7;
  for (int i = 0; i < k; ++i) {
    double a = 2 * std::numbers::pi * i / k;
    s.positions.push_back({std::cos(a), std::sin(a), 0.5});
    s.add_face({0, 1, static_cast<std::uint32_t>(2 + i)});
  }
  auto [m, r] = build(s);
  EXPECT_VALID(m);
  EXPECT_EQ(m.n_faces(), static_cast<std::size_t>(k));
  EXPECT_TRUE(analyze(m).manifold);
}

TEST(Build, SplitsBowTieVertexCopyingAttributes) {
  auto s = bowtie_soup();
  s.vertex_colors.assign(5, Color(0.1, 0.2, 0.3));
  s.vertex_colors[0] = Color(1, 0, 0);
  auto [m, r] = build(s);
  EXPECT_VALID(m);
  EXPECT_EQ(r.split_nonmanifold_vertices, 1u);
  EXPECT_EQ(m.n_vertices(), 6u);
  EXPECT_EQ(r.vertex_origin[5], 0u);
  auto color = m.get_property<Vertex, Color>(prop::kVertexColor);
  ASSERT_TRUE(color);
  EXPECT_EQ(color[Vertex(5)], Color(1, 0, 0));
  EXPECT_EQ(m.position(Vertex(5)), s.positions[0]);
  EXPECT_TRUE(mentions(r, "vertex 0 into 2"));
  for (Vertex v : m.vertices()) EXPECT_TRUE(m.is_manifold(v));
}

TEST(Build, FlipsFacesToAgreeWithTheirNeighbours) {
  auto s = cube_soup();
  for (std::size_t f : {1u, 4u}) {
    auto b = s.face_indices.begin() + s.face_offsets[f];
    std::reverse(b + 1, s.face_indices.begin() + s.face_offsets[f + 1]);
  }
  auto [m, r] = build(s);
  EXPECT_VALID(m);
  EXPECT_EQ(r.flipped_faces, 2u);
  EXPECT_TRUE(r.orientable);
  EXPECT_TRUE(analyze(m).closed);
  EXPECT_EQ(analyze(m).genus, 0);
  // The first corner stays first.
  EXPECT_EQ(corners(m, Face(1))[0], s.face(1)[0]);
  // Majority wins: with most faces reversed, the reversed ones are kept.
  auto t = tetrahedron_soup();
  for (std::size_t f = 0; f < 3; ++f)
    std::reverse(t.face_indices.begin() + t.face_offsets[f] + 1, t.face_indices.begin() + t.face_offsets[f + 1]);
  EXPECT_EQ(build(t).report.flipped_faces, 1u);
}

TEST(Build, OrientOffLeavesDisagreeingEdgesAsBoundary) {
  auto s = cube_soup();
  std::reverse(s.face_indices.begin() + 1, s.face_indices.begin() + 4);
  auto [m, r] = build(s, {.orient = false});
  EXPECT_VALID(m);
  EXPECT_EQ(r.flipped_faces, 0u);
  EXPECT_EQ(r.cut_edges, 4u);
  EXPECT_EQ(m.n_faces(), 6u);
}

TEST(Build, MoebiusStripIsCutAndReportedNonOrientable) {
  auto s = moebius_soup(9);
  auto [m, r] = build(s);
  EXPECT_VALID(m);
  EXPECT_FALSE(r.orientable);
  EXPECT_GE(r.cut_edges, 1u);
  EXPECT_EQ(m.n_faces(), 9u);
  EXPECT_TRUE(mentions(r, "not orientable"));
  auto t = analyze(m);
  EXPECT_TRUE(t.manifold);
  EXPECT_EQ(t.genus, 0);  // cut open: a strip
}

TEST(Build, ReportsFaceOriginWhenFacesAreDropped) {
  auto s = tetrahedron_soup();
  PolygonSoup t;
  t.positions = s.positions;
  t.add_face({0, 0, 1});
  for (std::size_t f = 0; f < 4; ++f) t.add_face(s.face(f));
  auto [m, r] = build(t);
  EXPECT_EQ(r.face_origin, (std::vector<std::uint32_t>{1, 2, 3, 4}));
}

// ---- strict policy and argument errors -------------------------------------------------

void expect_strict_throw(const PolygonSoup& s, const std::string& needle) {
  try {
    build(s, {.policy = RepairPolicy::kStrict});
    ADD_FAILURE() << "no TopologyError; expected one mentioning " << needle;
  } catch (const TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
  }
}

TEST(Build, StrictPolicyThrowsNamingTheFace) {
  auto bad = tetrahedron_soup();
  bad.add_face({0, 1, 9});
  expect_strict_throw(bad, "face 4");
  auto degenerate = tetrahedron_soup();
  degenerate.add_face({0, 0, 1});
  expect_strict_throw(degenerate, "face 4");
  auto dup = tetrahedron_soup();
  dup.add_face({0, 2, 1});
  expect_strict_throw(dup, "face 4 repeats face 0");
  expect_strict_throw(three_fin_soup(), "edge (0, 1)");
  expect_strict_throw(bowtie_soup(), "face 1 meets the other faces at vertex 0");
  auto flipped = cube_soup();
  std::reverse(flipped.face_indices.begin() + 1, flipped.face_indices.begin() + 4);
  expect_strict_throw(flipped, "oriented against");
  expect_strict_throw(moebius_soup(6), "oriented against");
  PolygonSoup collapsed;
  collapsed.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  collapsed.add_face({0, 1, 1, 2});
  expect_strict_throw(collapsed, "face 0");
  // Clean input passes.
  EXPECT_NO_THROW(build(torus_soup(6, 5), {.policy = RepairPolicy::kStrict}));
}

TEST(Build, ThrowsInvalidArgumentOnInconsistentArrays) {
  auto s = tetrahedron_soup();
  auto t = s;
  t.face_offsets.back() = 99;
  EXPECT_THROW(build(t), InvalidArgument);
  t = s;
  t.face_offsets[0] = 1;
  EXPECT_THROW(build(t), InvalidArgument);
  t = s;
  std::swap(t.face_offsets[1], t.face_offsets[2]);
  EXPECT_THROW(build(t), InvalidArgument);
  t = s;
  t.vertex_normals.resize(3);
  EXPECT_THROW(build(t), InvalidArgument);
  t = s;
  t.corner_texcoords.resize(5);
  EXPECT_THROW(build(t), InvalidArgument);
  t = s;
  t.face_scalars.push_back({"quality", {1.0}});
  EXPECT_THROW(build(t), InvalidArgument);
  t = s;
  t.vertex_scalars.push_back({"q", {1.0, 2.0}});
  EXPECT_THROW(build(t), InvalidArgument);
  t = s;
  t.face_offsets.clear();
  EXPECT_THROW(build(t), InvalidArgument);
  EXPECT_THROW(check_soup(t), InvalidArgument);
  EXPECT_NO_THROW(check_soup(s));
}

TEST(Build, NonFinitePositionsDoNotCrash) {
  auto s = tetrahedron_soup();
  s.positions[3] = Point(std::numeric_limits<double>::quiet_NaN(), 0, std::numeric_limits<double>::infinity());
  auto [m, r] = build(s, {.weld_tolerance = 1e-3});
  EXPECT_VALID(m);
  EXPECT_EQ(m.n_faces(), 4u);
}

// ---- attributes and to_soup ----------------------------------------------------------

PolygonSoup decorated_cube() {
  auto s = cube_soup();
  const std::size_t n = s.positions.size();
  for (std::size_t v = 0; v < n; ++v) {
    s.vertex_normals.push_back(s.positions[v].normalized());
    s.vertex_colors.push_back(Color(v / 8.0, 0.5, 1.0));
    s.vertex_texcoords.push_back(TexCoord(v, -double(v)));
  }
  s.vertex_scalars.push_back({"quality", std::vector<double>(n, 0.0)});
  for (std::size_t v = 0; v < n; ++v) s.vertex_scalars[0].values[v] = 10.0 + v;
  for (std::size_t c = 0; c < s.face_indices.size(); ++c) {
    s.corner_texcoords.push_back(TexCoord(c, 0.25));
    s.corner_normals.push_back(Normal(0, 0, c));
  }
  s.face_scalars.push_back({"label", {1, 2, 3, 4, 5, 6}});
  s.creases.push_back({s.face(0)[0], s.face(0)[1], 2.5});
  s.corners.push_back({3, 4.0});
  return s;
}

TEST(Build, CarriesEveryAttributeOntoProperties) {
  auto s = decorated_cube();
  auto [m, r] = build(s);
  EXPECT_VALID(m);
  auto vn = m.get_property<Vertex, Normal>(prop::kVertexNormal);
  auto vq = m.get_property<Vertex, double>("v:quality");
  auto ct = m.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  auto cn = m.get_property<Halfedge, Normal>(prop::kCornerNormal);
  auto fl = m.get_property<Face, double>("f:label");
  auto es = m.get_property<Edge, double>(prop::kEdgeSharpness);
  auto vs = m.get_property<Vertex, double>(prop::kVertexSharpness);
  ASSERT_TRUE(vn && vq && ct && cn && fl && es && vs);
  EXPECT_EQ(vq[Vertex(2)], 12.0);
  EXPECT_EQ(fl[Face(4)], 5.0);
  EXPECT_EQ(vs[Vertex(3)], 4.0);
  // Corner attributes sit on the halfedge ending at the corner.
  for (Face f : m.faces()) {
    std::uint32_t c = s.face_offsets[f.idx()];
    for (Halfedge h : m.halfedges(f)) EXPECT_EQ(ct[h], TexCoord(c++, 0.25));
  }
  Edge e = m.find_edge(Vertex(s.face(0)[0]), Vertex(s.face(0)[1]));
  ASSERT_TRUE(e.is_valid());
  EXPECT_EQ(es[e], 2.5);
  std::size_t sharp = 0;
  for (Edge x : m.edges()) sharp += es[x] != 0;
  EXPECT_EQ(sharp, 1u);
}

TEST(Build, ToSoupRoundTripsEverything) {
  auto s = decorated_cube();
  auto m = build(s).mesh;
  auto t = to_soup(m);
  EXPECT_EQ(t.positions, s.positions);
  EXPECT_EQ(t.face_offsets, s.face_offsets);
  EXPECT_EQ(t.face_indices, s.face_indices);
  EXPECT_EQ(t.vertex_normals, s.vertex_normals);
  EXPECT_EQ(t.vertex_colors, s.vertex_colors);
  EXPECT_EQ(t.vertex_texcoords, s.vertex_texcoords);
  EXPECT_EQ(t.corner_texcoords, s.corner_texcoords);
  EXPECT_EQ(t.corner_normals, s.corner_normals);
  ASSERT_EQ(t.vertex_scalars.size(), 1u);
  EXPECT_EQ(t.vertex_scalars[0].name, "quality");
  EXPECT_EQ(t.vertex_scalars[0].values, s.vertex_scalars[0].values);
  ASSERT_EQ(t.face_scalars.size(), 1u);
  EXPECT_EQ(t.face_scalars[0].values, s.face_scalars[0].values);
  ASSERT_EQ(t.creases.size(), 1u);
  EXPECT_EQ(std::minmax(t.creases[0].a, t.creases[0].b), std::minmax(s.creases[0].a, s.creases[0].b));
  EXPECT_EQ(t.creases[0].sharpness, 2.5);
  ASSERT_EQ(t.corners.size(), 1u);
  EXPECT_EQ(t.corners[0].v, 3u);
  // And again through build: a fixed point.
  auto u = to_soup(build(t).mesh);
  EXPECT_EQ(u.face_indices, t.face_indices);
}

TEST(Build, ToSoupRenumbersDenselyAfterDeletion) {
  auto m = build(torus_soup(6, 5)).mesh;
  m.delete_face(Face(0));
  m.delete_vertex(Vertex(17));
  auto t = to_soup(m);
  EXPECT_EQ(t.n_faces(), m.n_faces());
  EXPECT_EQ(t.positions.size(), m.n_vertices());
  for (std::uint32_t i : t.face_indices) EXPECT_LT(i, t.positions.size());
  auto back = build(t);
  EXPECT_FALSE(back.report.changed());
  EXPECT_VALID(back.mesh);
}

TEST(Build, RandomSoupsAlwaysGiveValidMeshes) {
  std::mt19937 rng(1234);
  // Every repair path must actually run in this battery.
  std::size_t detached = 0, cut = 0, split_vertices = 0, split_edges = 0, flipped = 0, duplicates = 0;
  for (int trial = 0; trial < 300; ++trial) {
    PolygonSoup s;
    const int nv = 4 + static_cast<int>(rng() % 12);
    for (int v = 0; v < nv; ++v)
      s.positions.push_back(Point(rng() % 4, rng() % 4, rng() % 3));
    const int nf = 1 + static_cast<int>(rng() % 25);
    for (int f = 0; f < nf; ++f) {
      std::vector<std::uint32_t> c;
      const int k = 3 + static_cast<int>(rng() % 3);
      for (int i = 0; i < k; ++i) c.push_back(static_cast<std::uint32_t>(rng() % (nv + 1)));
      s.add_face(c);
    }
    for (double weld : {-1.0, 0.0, 0.3}) {
      BuildResult b;
      ASSERT_NO_THROW(b = build(s, {.weld_tolerance = weld})) << "trial " << trial;
      auto v = validate(b.mesh);
      ASSERT_TRUE(v.ok()) << "trial " << trial << " weld " << weld << "\n" << v.to_string();
      const auto& r = b.report;
      detached += r.detached_faces;
      cut += r.cut_edges;
      split_vertices += r.split_nonmanifold_vertices;
      split_edges += r.split_nonmanifold_edges;
      flipped += r.flipped_faces;
      duplicates += r.dropped_duplicate;
      EXPECT_EQ(b.mesh.n_faces() + r.dropped_out_of_range + r.dropped_degenerate + r.dropped_duplicate,
                s.n_faces());
      auto t = analyze(b.mesh);
      EXPECT_TRUE(t.manifold) << "trial " << trial;
      for (Vertex x : b.mesh.vertices()) ASSERT_TRUE(b.mesh.is_manifold(x)) << "trial " << trial;
      // No two edges join the same two vertices.
      for (Vertex x : b.mesh.vertices()) {
        std::vector<std::uint32_t> nb;
        for (Vertex y : b.mesh.vertices(x)) nb.push_back(y.idx());
        std::sort(nb.begin(), nb.end());
        ASSERT_TRUE(std::adjacent_find(nb.begin(), nb.end()) == nb.end()) << "trial " << trial;
      }
    }
  }
  EXPECT_GT(detached, 0u);
  EXPECT_GT(cut, 0u);
  EXPECT_GT(split_vertices, 0u);
  EXPECT_GT(split_edges, 0u);
  EXPECT_GT(flipped, 0u);
  EXPECT_GT(duplicates, 0u);
}

}  // namespace
}  // namespace geom
