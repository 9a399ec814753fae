// Unit tests, invariants and hard cases of geom/subdivision (no oracle needed).

#include "shapes.h"

#include <geom/core/topology.h>
#include <geom/core/validate.h>
#include <geom/subdivision/creases.h>
#include <geom/subdivision/subdivision.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace geom {
namespace {

SubdivideOptions cc(int levels) {
  SubdivideOptions o;
  o.levels = levels;
  return o;
}
SubdivideOptions loop(int levels) {
  SubdivideOptions o;
  o.levels = levels;
  o.scheme = SubdivisionScheme::kLoop;
  return o;
}

void expect_same_topology(const SurfaceMesh& a, const SurfaceMesh& b) {
  const TopologyReport ta = analyze(a), tb = analyze(b);
  EXPECT_EQ(ta.euler_characteristic, tb.euler_characteristic);
  EXPECT_EQ(ta.genus, tb.genus);
  EXPECT_EQ(ta.boundary_loops, tb.boundary_loops);
  EXPECT_EQ(ta.components, tb.components);
}

TEST(CatmullClark, CountsFollowTheSplitRule) {
  const SurfaceMesh m = test::mixed_polygons();
  const SubdivideResult r = subdivide(m, cc(1));
  // V' = V + E + F, E' = 2E + corners, F' = corners.
  std::size_t corners = 0;
  for (Face f : m.faces()) corners += m.valence(f);
  EXPECT_EQ(r.mesh.n_vertices(), m.n_vertices() + m.n_edges() + m.n_faces());
  EXPECT_EQ(r.mesh.n_edges(), 2 * m.n_edges() + corners);
  EXPECT_EQ(r.mesh.n_faces(), corners);
  EXPECT_TRUE(r.mesh.is_quad_mesh());
  ASSERT_EQ(r.per_level.size(), 2u);
  EXPECT_EQ(r.per_level[1].faces, corners);
}

TEST(Loop, CountsFollowTheSplitRule) {
  const SurfaceMesh m = test::icosahedron();
  const SubdivideResult r = subdivide(m, loop(2));
  EXPECT_EQ(r.mesh.n_faces(), 20u * 16u);
  EXPECT_EQ(r.mesh.n_vertices(), 162u);
  EXPECT_TRUE(r.mesh.is_triangle_mesh());
}

TEST(Subdivision, InvariantsHoldAfterEveryLevel) {
  const SurfaceMesh shapes[] = {test::cube(), test::mixed_polygons(), test::quad_grid(3, 2),
                                test::pyramid(7)};
  for (const SurfaceMesh& m : shapes)
    for (int k = 0; k <= 3; ++k) {
      const SubdivideResult r = subdivide(m, cc(k));
      ASSERT_TRUE(validate(r.mesh).ok()) << validate(r.mesh).to_string();
      expect_same_topology(m, r.mesh);
    }
  const SurfaceMesh tris[] = {test::icosahedron(), test::triangle_strip(4), test::tetrahedron(),
                              test::bipyramid_fan(9)};
  for (const SurfaceMesh& m : tris)
    for (int k = 0; k <= 3; ++k) {
      const SubdivideResult r = subdivide(m, loop(k));
      ASSERT_TRUE(validate(r.mesh).ok()) << validate(r.mesh).to_string();
      expect_same_topology(m, r.mesh);
    }
}

TEST(Subdivision, GenusIsKeptOnATorus) {
  // A 4 × 4 quad torus.
  std::vector<Point> pts;
  std::vector<std::vector<int>> faces;
  const int n = 4;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double u = 2 * M_PI * i / n, v = 2 * M_PI * j / n;
      pts.emplace_back((2 + std::cos(v)) * std::cos(u), (2 + std::cos(v)) * std::sin(u), std::sin(v));
      int a = i * n + j, b = ((i + 1) % n) * n + j, c = ((i + 1) % n) * n + (j + 1) % n,
          d = i * n + (j + 1) % n;
      faces.push_back({a, b, c, d});
    }
  const SurfaceMesh torus = test::mesh_from(pts, faces);
  const SubdivideResult r = subdivide(torus, cc(3));
  EXPECT_EQ(analyze(r.mesh).genus, std::optional<long>(1));
  expect_same_topology(torus, r.mesh);
}

TEST(Subdivision, PlanarMeshStaysPlanar) {
  const SurfaceMesh flat = test::quad_grid(4, 4, false);
  for (auto b : {BoundaryInterpolation::kNone, BoundaryInterpolation::kEdges,
                 BoundaryInterpolation::kEdgesAndCorners}) {
    SubdivideOptions o = cc(3);
    o.boundary = b;
    o.limit = true;
    const SubdivideResult r = subdivide(flat, o);
    for (Vertex v : r.mesh.vertices()) EXPECT_EQ(r.mesh.position(v).z(), 0.0);
  }
  // A tilted plane: every vertex stays on it up to rounding.
  SurfaceMesh tilted = test::quad_grid(3, 3, false);
  for (Vertex v : tilted.vertices()) {
    Point& p = tilted.position(v);
    p.z() = 0.3 * p.x() - 0.7 * p.y() + 2.0;
  }
  const SubdivideResult r = subdivide(tilted, cc(3));
  for (Vertex v : r.mesh.vertices()) {
    const Point& p = r.mesh.position(v);
    EXPECT_NEAR(p.z(), 0.3 * p.x() - 0.7 * p.y() + 2.0, 1e-13);
  }
}

TEST(Subdivision, AllInfinitelySharpReproducesInputEdges) {
  SurfaceMesh m = test::cube();
  auto sharp = m.add_property<Edge, double>(prop::kEdgeSharpness, 10.0);
  (void)sharp;
  const int levels = 3;
  const SubdivideResult r = subdivide(m, cc(levels));
  // Every point k/2^L along every input edge is a vertex of the result, exactly.
  for (Edge e : m.edges()) {
    const Point a = m.position(m.vertex(e, 0)), b = m.position(m.vertex(e, 1));
    for (int k = 0; k <= (1 << levels); ++k) {
      const double t = static_cast<double>(k) / (1 << levels);
      const Point want = (1 - t) * a + t * b;
      bool found = false;
      for (Vertex v : r.mesh.vertices()) found |= (r.mesh.position(v) - want).norm() == 0.0;
      EXPECT_TRUE(found) << "edge " << e.idx() << " t=" << t;
    }
  }
  // The corners stay put.
  for (Vertex v : m.vertices())
    EXPECT_EQ(r.mesh.position(Vertex(static_cast<std::uint32_t>(r.mesh.n_vertices() - 8 + v.idx()))),
              m.position(v));
}

TEST(Subdivision, CreaseAngleMarksFeatureEdges) {
  SubdivideOptions o = cc(2);
  o.crease_angle = 60.0;
  const SubdivideResult r = subdivide(test::cube(), o);
  EXPECT_EQ(r.angle_creased_edges, 12u);
  // The cube's corners stay put once all its edges are sharp.
  for (Vertex v : r.mesh.vertices()) {
    const Point& p = r.mesh.position(v);
    EXPECT_LE(p.cwiseAbs().maxCoeff(), 1.0 + 1e-15);
  }
  SurfaceMesh m = test::cube();
  EXPECT_EQ(mark_creases_by_angle(m, 100.0), 0u);
  EXPECT_EQ(mark_creases_by_angle(m, 89.0), 12u);
  EXPECT_THROW(mark_creases_by_angle(m, 181.0), InvalidArgument);
  EXPECT_THROW(mark_creases_by_angle(m, std::nan("")), InvalidArgument);
}

TEST(Subdivision, RefinesEveryFloatingVertexProperty) {
  SurfaceMesh m = test::mixed_polygons();
  auto color = m.add_property<Vertex, Color>(prop::kVertexColor, Color::Zero());
  auto weight = m.add_property<Vertex, float>("v:weight", 0.0f);
  auto tag = m.add_property<Vertex, int>("v:tag", 7);
  auto fid = m.add_property<Face, int>("f:id", -1);
  for (Vertex v : m.vertices()) {
    color[v] = m.position(v);
    weight[v] = 2.0f;
  }
  for (Face f : m.faces()) fid[f] = static_cast<int>(f.idx());
  (void)tag;
  const SubdivideResult r = subdivide(m, cc(2));
  auto rc = r.mesh.get_property<Vertex, Color>(prop::kVertexColor);
  auto rw = r.mesh.get_property<Vertex, float>("v:weight");
  ASSERT_TRUE(rc);
  ASSERT_TRUE(rw);
  for (Vertex v : r.mesh.vertices()) {
    EXPECT_LE((rc[v] - r.mesh.position(v)).norm(), 1e-15);
    EXPECT_NEAR(rw[v], 2.0f, 1e-6f);
  }
  EXPECT_FALSE(r.mesh.has_property<Vertex>("v:tag"));
  auto rf = r.mesh.get_property<Face, int>("f:id");
  ASSERT_TRUE(rf);
  // Level 2: 4 × corners(level 1) faces; each level-1 face has the id of its parent.
  const SubdivideResult r1 = subdivide(m, cc(1));
  auto rf1 = r1.mesh.get_property<Face, int>("f:id");
  std::size_t child = 0;
  for (Face f : m.faces())
    for (std::size_t j = 0; j < m.valence(f); ++j) EXPECT_EQ(rf1[Face(child++)], fid[f]);
  for (Face f : r.mesh.faces()) EXPECT_EQ(rf[f], rf1[Face(f.idx() / 4)]);
}

TEST(Subdivision, SmoothFaceVaryingIsAffineInsideIslandsAndKeepsSeamValues) {
  // Seamless UVs that are an affine function of position stay that function of the refined
  // positions (subdivision is affine-invariant); a seam's vertices keep their values.
  auto affine = [](const Point& p) { return TexCoord(0.5 * p.x() + 0.25 * p.y(), p.z() - 0.3 * p.x()); };
  for (bool seam : {false, true}) {
    SurfaceMesh m = test::cube();
    auto uv = m.add_property<Halfedge, TexCoord>(prop::kCornerTexCoord, TexCoord::Zero());
    for (Face f : m.faces())
      for (Halfedge h : m.halfedges(f))
        uv[h] = affine(m.position(m.to_vertex(h))) + (seam && f.idx() == 0 ? TexCoord(2, 0) : TexCoord(0, 0));
    SubdivideOptions o;
    o.levels = 3;
    o.face_varying = FaceVaryingInterpolation::kLinearBoundaries;
    const SurfaceMesh r = subdivide(m, o).mesh;
    auto ruv = r.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
    ASSERT_TRUE(ruv);
    const std::uint32_t first_vertex_point = static_cast<std::uint32_t>(r.n_vertices() - m.n_vertices());
    for (Halfedge h : r.halfedges()) {
      if (r.is_boundary(h)) continue;
      const Vertex v = r.to_vertex(h);
      if (!seam) {
        EXPECT_LT((ruv[h] - affine(r.position(v))).norm(), 1e-12);
      } else if (v.idx() >= first_vertex_point) {
        // Every cube vertex lies on the seam around face 0 or away from it; the four on it
        // (vertices 0-3) keep the value of the face the corner belongs to.
        const Vertex parent(v.idx() - first_vertex_point);
        if (parent.idx() < 4) {
          const Point p = m.position(parent);
          const bool island = (ruv[h] - affine(p)).norm() > 1.0;
          EXPECT_LT((ruv[h] - affine(p) - (island ? TexCoord(2, 0) : TexCoord(0, 0))).norm(), 1e-15);
        }
      }
    }
  }
}

TEST(Subdivision, SharpnessPropertiesDecayInTheResult) {
  SurfaceMesh m = test::creased_cube();
  const SubdivideResult r = subdivide(m, cc(1));
  auto es = r.mesh.get_property<Edge, double>(prop::kEdgeSharpness);
  auto vs = r.mesh.get_property<Vertex, double>(prop::kVertexSharpness);
  ASSERT_TRUE(es);
  ASSERT_TRUE(vs);
  double max_semi = 0.0;
  int infinite = 0;
  for (Edge e : r.mesh.edges()) {
    if (es[e] >= 10.0) ++infinite;
    else max_semi = std::max(max_semi, es[e]);
  }
  EXPECT_EQ(infinite, 4);  // two infinite input edges, two halves each
  EXPECT_NEAR(max_semi, 1.7, 1e-6);
  EXPECT_NEAR(vs[Vertex(static_cast<std::uint32_t>(6 + 12 + 3))], 1.0, 0.0);
}

TEST(Subdivision, LimitPositionsAgreeWithSubdivideLimit) {
  const SubdivideResult two = subdivide(test::cube(), cc(2));
  SubdivideOptions o = cc(2);
  o.limit = true;
  const SubdivideResult lim = subdivide(test::cube(), o);
  LimitOptions lo;
  lo.normals = true;
  const LimitResult l = limit_positions(two.mesh, lo);
  ASSERT_EQ(l.positions.size(), two.mesh.n_vertices());
  for (Vertex v : two.mesh.vertices()) {
    EXPECT_LE((l.positions[v.idx()] - lim.mesh.position(v)).norm(), 1e-15);
    // The cube's limit surface is round and centred: normals point outwards.
    EXPECT_GT(l.normals[v.idx()].dot(l.positions[v.idx()].normalized()), 0.7);
    EXPECT_NEAR(l.normals[v.idx()].norm(), 1.0, 1e-12);
  }
  EXPECT_NEAR(l.max_distance, lim.limit_max_distance, 1e-15);
  EXPECT_GT(l.max_distance, 0.0);
  // Loop, with a boundary.
  const SubdivideResult strip = subdivide(test::triangle_strip(4), loop(1));
  LimitOptions ll;
  ll.scheme = SubdivisionScheme::kLoop;
  ll.normals = true;
  const LimitResult ls = limit_positions(strip.mesh, ll);
  for (const Normal& n : ls.normals) EXPECT_NEAR(n.norm(), 1.0, 1e-12);
}

TEST(Subdivision, LimitErrorShrinksWithLevels) {
  double previous = std::numeric_limits<double>::infinity();
  for (int k = 1; k <= 4; ++k) {
    SubdivideOptions o = cc(k);
    o.limit = true;
    const SubdivideResult r = subdivide(test::cube(), o);
    EXPECT_LT(r.limit_max_distance, previous);
    previous = r.limit_max_distance;
  }
}

TEST(Subdivision, HugeAndTinyCoordinatesScale) {
  for (double scale : {1e150, 1e-150}) {
    SurfaceMesh m = test::creased_cube();
    for (Vertex v : m.vertices()) m.position(v) *= scale;
    const SubdivideResult big = subdivide(m, cc(3));
    const SubdivideResult unit = subdivide(test::creased_cube(), cc(3));
    for (Vertex v : unit.mesh.vertices()) {
      const Point p = big.mesh.position(v) / scale;
      EXPECT_TRUE(p.allFinite());
      EXPECT_LE((p - unit.mesh.position(v)).norm(), 1e-14);
    }
  }
}

TEST(Subdivision, DegenerateAndDuplicateGeometryStaysFinite) {
  // All corners at one point, and a collinear quad.
  SurfaceMesh m = test::mesh_from({{1, 1, 1}, {1, 1, 1}, {1, 1, 1}, {1, 1, 1}}, {{0, 1, 2, 3}});
  const SubdivideResult r = subdivide(m, cc(3));
  for (Vertex v : r.mesh.vertices()) EXPECT_EQ(r.mesh.position(v), Point(1, 1, 1));
  SurfaceMesh line = test::mesh_from({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}}, {{0, 1, 2, 3}});
  SubdivideOptions o = cc(2);
  o.limit = true;
  o.crease_angle = 30.0;
  const SubdivideResult rl = subdivide(line, o);
  for (Vertex v : rl.mesh.vertices()) {
    EXPECT_TRUE(rl.mesh.position(v).allFinite());
    EXPECT_EQ(rl.mesh.position(v).y(), 0.0);
  }
}

TEST(Subdivision, EmptyMeshAndIsolatedVertices) {
  const SubdivideResult empty = subdivide(SurfaceMesh(), cc(2));
  EXPECT_EQ(empty.mesh.n_vertices(), 0u);
  EXPECT_EQ(empty.mesh.n_faces(), 0u);
  SurfaceMesh m = test::cube();
  m.add_vertex(Point(5, 5, 5));
  const SubdivideResult r = subdivide(m, cc(1));
  EXPECT_TRUE(validate(r.mesh).ok());
  EXPECT_EQ(r.mesh.position(Vertex(static_cast<std::uint32_t>(r.mesh.n_vertices() - 1))), Point(5, 5, 5));
}

TEST(Subdivision, ZeroLevelsCopiesTheMesh) {
  const SurfaceMesh m = test::mixed_polygons();
  const SubdivideResult r = subdivide(m, cc(0));
  EXPECT_EQ(r.mesh.n_faces(), m.n_faces());
  for (Vertex v : m.vertices()) EXPECT_EQ(r.mesh.position(v), m.position(v));
}

TEST(Subdivision, DeletedElementsAreIgnored) {
  SurfaceMesh m = test::quad_grid(3, 3);
  m.delete_face(Face(4));
  const SubdivideResult r = subdivide(m, cc(2));
  EXPECT_TRUE(validate(r.mesh).ok());
  EXPECT_EQ(r.mesh.n_faces(), 8u * 16u);
}

// ---- every documented Throws: ----------------------------------------------------------

TEST(Subdivision, RefusesANonManifoldVertexNamingIt) {
  // Two triangles sharing only vertex 0: a bow-tie.
  SurfaceMesh m = test::mesh_from({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {-1, 0, 0}, {-1, -1, 0}},
                                  {{0, 1, 2}, {0, 3, 4}});
  try {
    subdivide(m, cc(1));
    FAIL() << "expected TopologyError";
  } catch (const TopologyError& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 0"), std::string::npos) << e.what();
  }
  LimitOptions lo;
  lo.scheme = SubdivisionScheme::kLoop;
  EXPECT_THROW(limit_positions(m, lo), TopologyError);
}

TEST(Loop, RefusesNonTrianglesNamingTheFace) {
  try {
    subdivide(test::mixed_polygons(), loop(1));
    FAIL() << "expected InvalidArgument";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("face 0"), std::string::npos) << e.what();
  }
  LimitOptions lo;
  lo.scheme = SubdivisionScheme::kLoop;
  EXPECT_THROW(limit_positions(test::cube(), lo), InvalidArgument);
  EXPECT_THROW(limit_positions(test::tetrahedron(), LimitOptions{}), InvalidArgument);
}

TEST(Subdivision, RefusesBadOptions) {
  EXPECT_THROW(subdivide(test::cube(), cc(-1)), InvalidArgument);
  EXPECT_THROW(subdivide(test::cube(), cc(11)), InvalidArgument);
  SubdivideOptions o = cc(1);
  o.crease_angle = -5.0;
  EXPECT_THROW(subdivide(test::cube(), o), InvalidArgument);
  // Too many elements for 32-bit handles.
  EXPECT_THROW(subdivide(test::quad_grid(40, 40), cc(10)), InvalidArgument);
  // Limit at level 0 needs quads for Catmull-Clark.
  SubdivideOptions l0 = cc(0);
  l0.limit = true;
  EXPECT_THROW(subdivide(test::tetrahedron(), l0), InvalidArgument);
  EXPECT_NO_THROW(subdivide(test::cube(), l0));
  // Smooth UVs reach the limit only from refined levels (OpenSubdiv's base-level rule
  // differs); linear UVs stay where they are at any level.
  SurfaceMesh uv_cube = test::cube();
  uv_cube.add_property<Halfedge, TexCoord>(prop::kCornerTexCoord, TexCoord(0.5, 0.5));
  l0.face_varying = FaceVaryingInterpolation::kLinearBoundaries;
  EXPECT_THROW(subdivide(uv_cube, l0), InvalidArgument);
  l0.levels = 1;
  EXPECT_NO_THROW(subdivide(uv_cube, l0));
  l0.levels = 0;
  l0.face_varying = FaceVaryingInterpolation::kLinearAll;
  EXPECT_NO_THROW(subdivide(uv_cube, l0));
}

TEST(Subdivision, RefusesNaNSharpness) {
  SurfaceMesh m = test::cube();
  test::set_crease(m, 0, 1, std::nan(""));
  EXPECT_THROW(subdivide(m, cc(1)), InvalidArgument);
}

TEST(Subdivision, ProgressCanCancel) {
  SubdivideOptions o = cc(3);
  int calls = 0;
  o.progress = [&](double fraction) {
    ++calls;
    EXPECT_GT(fraction, 0.0);
    return calls < 2;
  };
  EXPECT_THROW(subdivide(test::cube(), o), Error);
  EXPECT_EQ(calls, 2);
}

TEST(Subdivision, SerialAndParallelAgreeExactly) {
  // Big enough (3.7M halfedges at level 4) for the huge-page allocation path.
  SurfaceMesh m = test::quad_grid(60, 60);
  test::set_crease(m, 100, 101, 2.5);
  SubdivideOptions a = cc(4), b = cc(4);
  b.parallel = false;
  const SubdivideResult ra = subdivide(m, a), rb = subdivide(m, b);
  ASSERT_EQ(ra.mesh.n_vertices(), rb.mesh.n_vertices());
  for (Vertex v : ra.mesh.vertices()) ASSERT_EQ(ra.mesh.position(v), rb.mesh.position(v));
  EXPECT_TRUE(validate(ra.mesh).ok());
  // Level 4 of a grid: interior vertices of the planar-in-xy parametrisation stay finite.
  EXPECT_EQ(ra.mesh.n_faces(), 3600u * 256u);
  // The limit pass splits across workers too.
  a.levels = b.levels = 3;
  a.limit = b.limit = true;
  const SubdivideResult la = subdivide(m, a), lb = subdivide(m, b);
  for (Vertex v : la.mesh.vertices()) ASSERT_EQ(la.mesh.position(v), lb.mesh.position(v));
}

TEST(Subdivision, LoopSerialAndParallelAgreeExactly) {
  // A long strip: every triangle touches the boundary, and levels 2 and 3 have enough
  // faces to split across workers.
  SurfaceMesh m = test::triangle_strip(4000);
  SubdivideOptions a = loop(3), b = loop(3);
  b.parallel = false;
  const SubdivideResult ra = subdivide(m, a), rb = subdivide(m, b);
  ASSERT_EQ(ra.mesh.n_halfedges(), rb.mesh.n_halfedges());
  for (Halfedge h : ra.mesh.halfedges()) {
    ASSERT_EQ(ra.mesh.next(h), rb.mesh.next(h));
    ASSERT_EQ(ra.mesh.face(h), rb.mesh.face(h));
  }
  for (Vertex v : ra.mesh.vertices()) ASSERT_EQ(ra.mesh.position(v), rb.mesh.position(v));
  EXPECT_TRUE(validate(ra.mesh).ok());
  EXPECT_EQ(ra.mesh.n_faces(), 8000u * 64u);
}

}  // namespace
}  // namespace geom
