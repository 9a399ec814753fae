// Attribute-aware simplification (SimplifyOptions::attributes): UVs with a seam, normals,
// colours, and the degenerate inputs that must not produce NaNs.

#include <geom/core/errors.h>
#include <geom/core/geometry.h>
#include <geom/core/soup.h>
#include <geom/lod/lod_chain.h>
#include <geom/lod/simplify.h>
#include <geom/spatial/distance.h>

#include "lod/lod_checks.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <set>

namespace geom {
namespace {

constexpr double kPi = std::numbers::pi;

// The analytic chart of the unit sphere: u = longitude / 2π in [0, 1), v = colatitude / π.
TexCoord sphere_uv(const Point& p) {
  double u = std::atan2(p.y(), p.x()) / (2 * kPi);
  if (u < 0) u += 1;
  return {u, std::acos(std::clamp(p.z() / p.norm(), -1.0, 1.0)) / kPi};
}

// A UV sphere with per-corner texture coordinates ("h:texcoord") cut along longitude 0
// (u = 0 on one side, 1 on the other; each pole corner has its own u) and unit vertex
// normals ("v:normal").
SurfaceMesh uv_sphere(int n_lat, int n_lon) {
  SurfaceMesh m;
  std::vector<Vertex> ring;
  const Vertex north = m.add_vertex(Point(0, 0, 1));
  for (int i = 1; i < n_lat; ++i)
    for (int j = 0; j < n_lon; ++j) {
      const double th = kPi * i / n_lat, ph = 2 * kPi * j / n_lon;
      ring.push_back(m.add_vertex(Point(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th))));
    }
  const Vertex south = m.add_vertex(Point(0, 0, -1));
  auto at = [&](int i, int j) { return ring[(i - 1) * n_lon + j % n_lon]; };
  auto uv = m.add_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  auto face = [&](std::array<Vertex, 3> v, std::array<TexCoord, 3> t) {
    const Face f = m.add_triangle(v[0], v[1], v[2]);
    for (Halfedge h : m.halfedges(f))
      for (int k = 0; k < 3; ++k)
        if (m.to_vertex(h) == v[k]) uv[h] = t[k];
  };
  auto tc = [&](int i, int j) { return TexCoord(double(j) / n_lon, double(i) / n_lat); };
  for (int j = 0; j < n_lon; ++j) {
    const TexCoord pole_n((j + 0.5) / n_lon, 0.0), pole_s((j + 0.5) / n_lon, 1.0);
    face({north, at(1, j), at(1, j + 1)}, {pole_n, tc(1, j), tc(1, j + 1)});
    face({south, at(n_lat - 1, j + 1), at(n_lat - 1, j)}, {pole_s, tc(n_lat - 1, j + 1), tc(n_lat - 1, j)});
    for (int i = 1; i + 1 < n_lat; ++i) {
      face({at(i, j), at(i + 1, j), at(i + 1, j + 1)}, {tc(i, j), tc(i + 1, j), tc(i + 1, j + 1)});
      face({at(i, j), at(i + 1, j + 1), at(i, j + 1)}, {tc(i, j), tc(i + 1, j + 1), tc(i, j + 1)});
    }
  }
  auto normal = m.add_property<Vertex, Normal>(prop::kVertexNormal);
  for (Vertex v : m.vertices()) normal[v] = m.position(v).normalized();
  return m;
}

double periodic(double d) {
  d = std::abs(d);
  return std::min(d, 1.0 - d);
}

// Mean distance between each face's UV centroid and the chart's UV at the face centroid
// (projected to the sphere; the longitude compared periodically so that a correct seam
// costs nothing and a smeared one costs ~0.5).
double mean_uv_error(const SurfaceMesh& m, auto&& corner_uv) {
  double sum = 0;
  for (Face f : m.faces()) {
    Point c = Point::Zero();
    TexCoord t = TexCoord::Zero();
    for (Halfedge h : m.halfedges(f)) c += m.position(m.to_vertex(h)), t += corner_uv(h);
    const TexCoord want = sphere_uv(c / 3), got = t / 3;
    sum += std::hypot(periodic(got.x() - want.x()), got.y() - want.y());
  }
  return sum / m.n_faces();
}

TEST(SimplifyAttributes, UvSeamKeptAndUvErrorSmallerThanGeometryOnly) {
  const SurfaceMesh m = uv_sphere(24, 48);
  const auto in_uv = m.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  const SimplifyResult plain = simplify(m, {.ratio = 0.2, .keep_attributes = false});
  SimplifyOptions o{.ratio = 0.2};
  o.attributes.texcoords.enabled = true;
  o.attributes.normals.enabled = true;
  const SimplifyResult r = simplify(m, o);
  test::expect_same_topology(m, r.mesh);
  EXPECT_EQ(test::orientation_disagreements(m, r.mesh), 0u);
  EXPECT_LE(r.faces_after, plain.faces_after + plain.faces_after / 5);

  // Geometry only: each output vertex takes the UV of its input vertex, on the side of the
  // seam its face lies on (the best a caller can do without attribute quadrics).
  auto naive_uv = [&](Halfedge h) {
    const Vertex in = plain.vertex_origin[plain.mesh.to_vertex(h).idx()];
    Point c = Point::Zero();
    for (Vertex v : plain.mesh.vertices(plain.mesh.face(h))) c += plain.mesh.position(v);
    const double side = sphere_uv(c / 3).x();
    TexCoord best = TexCoord::Zero();
    double best_d = 2;
    for (Halfedge o : m.outgoing(in)) {
      const Halfedge g = SurfaceMesh::opposite(o);  // ends at `in`
      if (!m.is_boundary(g) && periodic(in_uv[g].x() - side) < best_d)
        best_d = periodic(in_uv[g].x() - side), best = in_uv[g];
    }
    return best;
  };
  const auto out_uv = r.mesh.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  ASSERT_TRUE(out_uv);
  const double err_plain = mean_uv_error(plain.mesh, naive_uv);
  const double err_attr = mean_uv_error(r.mesh, [&](Halfedge h) { return out_uv[h]; });
  EXPECT_LT(err_attr, 0.5 * err_plain) << "attributes " << err_attr << ", geometry only " << err_plain;

  // Both sides stay in their chart: no face spans the cut, every UV is inside [0, 1]².
  for (Face f : r.mesh.faces()) {
    double lo = 2, hi = -2;
    for (Halfedge h : r.mesh.halfedges(f)) {
      EXPECT_TRUE(out_uv[h].allFinite());
      EXPECT_GE(out_uv[h].minCoeff(), -1e-9);
      EXPECT_LE(out_uv[h].maxCoeff(), 1 + 1e-9);
      lo = std::min(lo, out_uv[h].x()), hi = std::max(hi, out_uv[h].x());
    }
    EXPECT_LT(hi - lo, 0.5) << "face " << f.idx() << " spans the seam";
  }
  // The seam stays a path of edges from pole to pole on the cut meridian: a seam edge has
  // u differing by more than 0.5 across it at an endpoint.
  std::size_t seam_edges = 0;
  std::vector<int> seam_degree(r.mesh.vertices_size(), 0);
  for (Edge e : r.mesh.edges()) {
    const Halfedge h = r.mesh.halfedge(e, 0), g = r.mesh.halfedge(e, 1);
    if (r.mesh.is_boundary(h) || r.mesh.is_boundary(g)) continue;
    // h ends at v1 and g.prev ends at v1 too (the same corner seen from the other face).
    const bool cut = std::abs(out_uv[h].x() - out_uv[r.mesh.prev(g)].x()) > 0.5 ||
                     std::abs(out_uv[g].x() - out_uv[r.mesh.prev(h)].x()) > 0.5;
    if (!cut) continue;
    ++seam_edges;
    for (Vertex v : {r.mesh.to_vertex(h), r.mesh.to_vertex(g)}) {
      ++seam_degree[v.idx()];
      const Point& p = r.mesh.position(v);
      EXPECT_NEAR(p.y(), 0.0, 1e-12) << "seam vertex left the cut";
      EXPECT_GE(p.x(), -1e-12);
    }
  }
  EXPECT_GE(seam_edges, 2u);
  int ends = 0;
  for (Vertex v : r.mesh.vertices()) {
    const int d = seam_degree[v.idx()];
    EXPECT_TRUE(d == 0 || d == 1 || d == 2);
    if (d == 1) {
      ++ends;
      // At a pole: the refit may lift it along its normal, the axis, not off it.
      const Point& p = r.mesh.position(v);
      EXPECT_NEAR(std::hypot(p.x(), p.y()), 0.0, 1e-12) << "a seam path ends off the poles";
      EXPECT_NEAR(std::abs(p.z()), 1.0, 1e-2);
    }
  }
  EXPECT_EQ(ends, 2);

  // Normals come back unit and close to the sphere's.
  const auto n = r.mesh.get_property<Vertex, Normal>(prop::kVertexNormal);
  ASSERT_TRUE(n);
  for (Vertex v : r.mesh.vertices()) {
    EXPECT_NEAR(n[v].norm(), 1.0, 1e-12);
    EXPECT_GT(n[v].dot(r.mesh.position(v).normalized()), 0.98);
  }
}

// A flat n × n grid on [0, 1]² with colour red = a steep ramp across x = 0.5, green = y².
SurfaceMesh colour_plane(int n) {
  SurfaceMesh m;
  auto colour = m.add_property<Vertex, Color>(prop::kVertexColor);
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const double x = double(j) / n, y = double(i) / n;
      colour[m.add_vertex(Point(x, y, 0))] = Color(0.5 + 0.5 * std::tanh(12 * (x - 0.5)), y * y, 0);
    }
  auto at = [&](int i, int j) { return Vertex(i * (n + 1) + j); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      m.add_triangle(at(i, j), at(i, j + 1), at(i + 1, j + 1));
      m.add_triangle(at(i, j), at(i + 1, j + 1), at(i + 1, j));
    }
  return m;
}

Color true_colour(double x, double y) { return {0.5 + 0.5 * std::tanh(12 * (x - 0.5)), y * y, 0}; }

// RMS colour error over a grid of sample points, interpolating the mesh's vertex colours.
double colour_rms(const SurfaceMesh& m, auto&& vertex_colour) {
  double sum = 0;
  int count = 0;
  for (int a = 1; a < 40; ++a)
    for (int b = 1; b < 40; ++b) {
      const Eigen::Vector2d p(a / 40.0, b / 40.0);
      for (Face f : m.faces()) {
        std::array<Vertex, 3> v;
        int k = 0;
        for (Vertex w : m.vertices(f)) v[k++] = w;
        auto xy = [&](int i) { return Eigen::Vector2d(m.position(v[i]).x(), m.position(v[i]).y()); };
        const Eigen::Vector2d e1 = xy(1) - xy(0), e2 = xy(2) - xy(0), d = p - xy(0);
        const double det = e1.x() * e2.y() - e1.y() * e2.x();
        const double s = (d.x() * e2.y() - d.y() * e2.x()) / det, t = (e1.x() * d.y() - e1.y() * d.x()) / det;
        if (s < -1e-12 || t < -1e-12 || s + t > 1 + 1e-12) continue;
        const Color c = (1 - s - t) * vertex_colour(v[0]) + s * vertex_colour(v[1]) + t * vertex_colour(v[2]);
        sum += (c - true_colour(p.x(), p.y())).squaredNorm();
        ++count;
        break;
      }
    }
  EXPECT_EQ(count, 39 * 39);
  return std::sqrt(sum / count);
}

// The default refit runs with attributes too: the same connectivity and attribute values as
// without it, the seam vertices moved only along their normals (so on their seam line), the
// rest freely, closer to the input.
TEST(SimplifyAttributes, DefaultRefitMovesSeamVerticesAlongTheirNormalsAndLowersTheError) {
  const SurfaceMesh m = uv_sphere(24, 48);
  SimplifyOptions o{.ratio = 0.2};
  o.attributes.texcoords.enabled = true;
  const SimplifyResult fitted = simplify(m, o);
  o.refit_iterations = 0;
  const SimplifyResult plain = simplify(m, o);
  ASSERT_EQ(fitted.refit_rounds, 1);
  ASSERT_EQ(plain.refit_rounds, 0);
  ASSERT_EQ(fitted.mesh.n_vertices(), plain.mesh.n_vertices());
  const auto uv_f = fitted.mesh.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  const auto uv_p = plain.mesh.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  ASSERT_TRUE(uv_f && uv_p);
  for (Halfedge h : fitted.mesh.halfedges()) {
    ASSERT_EQ(fitted.mesh.to_vertex(h), plain.mesh.to_vertex(h));
    if (!fitted.mesh.is_boundary(h)) {
      EXPECT_EQ(uv_f[h], uv_p[h]);
    }
  }
  std::size_t seam = 0, seam_moved = 0, moved = 0;
  for (Vertex v : fitted.mesh.vertices()) {
    std::set<std::pair<double, double>> wedges;
    for (Halfedge o2 : fitted.mesh.outgoing(v)) {
      const Halfedge h = SurfaceMesh::opposite(o2);
      if (!fitted.mesh.is_boundary(h)) wedges.insert({uv_f[h].x(), uv_f[h].y()});
    }
    const Eigen::Vector3d d = fitted.mesh.position(v) - plain.mesh.position(v);
    if (wedges.size() > 1) {
      ++seam;
      seam_moved += d.norm() > 1e-9;
      // Along the input's normal at the vertex it was: radial on the sphere, so within the
      // plane of the cut meridian. Off that line is across (or along) the seam.
      const Normal n = vertex_normal(m, fitted.vertex_origin[v.idx()]);
      EXPECT_LT((d - d.dot(n) * n).norm(), 1e-12) << "seam vertex " << v.idx() << " left its line";
      EXPECT_NEAR(fitted.mesh.position(v).y(), 0.0, 1e-12) << "seam vertex left the cut";
    } else {
      moved += d != Eigen::Vector3d::Zero();
    }
  }
  EXPECT_GE(seam, 10u);
  EXPECT_GE(seam_moved, seam / 2) << "the seam vertices stayed where the collapses left them";
  EXPECT_GT(moved, fitted.mesh.n_vertices() / 2);
  const double rms_fitted = mesh_distance(fitted.mesh, m).rms;
  const double rms_plain = mesh_distance(plain.mesh, m).rms;
  EXPECT_LT(rms_fitted, 0.9 * rms_plain) << rms_fitted << " against " << rms_plain;
}

TEST(SimplifyAttributes, FlatPlaneKeepsItsColourGradient) {
  const SurfaceMesh m = colour_plane(40);
  const auto in_colour = m.get_property<Vertex, Color>(prop::kVertexColor);
  const SimplifyResult plain = simplify(m, {.target_faces = 200});
  SimplifyOptions o{.target_faces = 200};
  o.attributes.colors = {.enabled = true, .weight = 1.0};
  const SimplifyResult r = simplify(m, o);
  EXPECT_EQ(r.stop, SimplifyStop::kTargetReached);
  test::expect_same_topology(m, r.mesh);
  const auto colour = r.mesh.get_property<Vertex, Color>(prop::kVertexColor);
  ASSERT_TRUE(colour);
  for (Vertex v : r.mesh.vertices()) {
    EXPECT_TRUE(r.mesh.position(v).allFinite());
    EXPECT_TRUE(colour[v].allFinite());
    EXPECT_GE(colour[v].minCoeff(), 0.0);
    EXPECT_LE(colour[v].maxCoeff(), 1.0);
  }
  const double err_plain =
      colour_rms(plain.mesh, [&](Vertex v) { return in_colour[plain.vertex_origin[v.idx()]]; });
  const double err_attr = colour_rms(r.mesh, [&](Vertex v) { return colour[v]; });
  EXPECT_LT(err_attr, 0.5 * err_plain) << "attributes " << err_attr << ", geometry only " << err_plain;
}

TEST(SimplifyAttributes, DegenerateUvsAndConstantNormalsStayFinite) {
  // All UVs zero (one wedge per vertex, zero gradients) and every normal (0, 0, 1) on a flat
  // plane: every quadric is singular, nothing may become NaN.
  SurfaceMesh m = colour_plane(20);
  auto uv = m.add_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  (void)uv;
  auto n = m.add_property<Vertex, Normal>(prop::kVertexNormal);
  for (Vertex v : m.vertices()) n[v] = Normal(0, 0, 1);
  SimplifyOptions o{.ratio = 0.1};
  o.attributes.texcoords.enabled = o.attributes.normals.enabled = o.attributes.colors.enabled = true;
  const SimplifyResult r = simplify(m, o);
  EXPECT_EQ(r.stop, SimplifyStop::kTargetReached);
  EXPECT_TRUE(std::isfinite(r.max_quadric_error));
  test::expect_same_topology(m, r.mesh);
  const auto out_uv = r.mesh.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  const auto out_n = r.mesh.get_property<Vertex, Normal>(prop::kVertexNormal);
  ASSERT_TRUE(out_uv && out_n);
  for (Face f : r.mesh.faces())
    for (Halfedge h : r.mesh.halfedges(f)) EXPECT_EQ(out_uv[h], TexCoord::Zero());
  for (Vertex v : r.mesh.vertices()) {
    EXPECT_TRUE(r.mesh.position(v).allFinite());
    EXPECT_NEAR((out_n[v] - Normal(0, 0, 1)).norm(), 0.0, 1e-12);
  }
}

TEST(SimplifyAttributes, HardNormalEdgesActAsSeams) {
  // Per-corner face normals on a subdivided cube: each cube edge is a normal seam and each
  // cube corner has three wedges. No output face may cut across an edge, and every corner
  // keeps its face's exact normal.
  SurfaceMesh m = test::subdivided_cube(8);
  auto hn = m.add_property<Halfedge, Normal>(prop::kCornerNormal);
  for (Face f : m.faces()) {
    std::vector<Point> c;
    for (Vertex v : m.vertices(f)) c.push_back(m.position(v));
    const Normal n = (c[1] - c[0]).cross(c[2] - c[0]).normalized();
    for (Halfedge h : m.halfedges(f)) hn[h] = n;
  }
  SimplifyOptions o{.ratio = 0.05};
  o.attributes.normals.enabled = true;
  const SimplifyResult r = simplify(m, o);
  test::expect_same_topology(m, r.mesh);
  EXPECT_LT(r.faces_after, m.n_faces() / 4);
  const auto out = r.mesh.get_property<Halfedge, Normal>(prop::kCornerNormal);
  ASSERT_TRUE(out);
  for (Face f : r.mesh.faces()) {
    std::vector<Point> c;
    for (Vertex v : r.mesh.vertices(f)) c.push_back(r.mesh.position(v));
    const Normal n = (c[1] - c[0]).cross(c[2] - c[0]).normalized();
    EXPECT_NEAR(n.cwiseAbs().maxCoeff(), 1.0, 1e-12) << "face " << f.idx() << " cuts a cube edge";
    for (Halfedge h : r.mesh.halfedges(f)) EXPECT_NEAR((out[h] - n).norm(), 0.0, 1e-12);
  }
}

TEST(SimplifyAttributes, WeightZeroCarriesValuesWithoutSteering) {
  // Weight 0: the collapse order is the geometric one, but the output still has UVs.
  const SurfaceMesh m = uv_sphere(12, 24);
  SimplifyOptions o{.ratio = 0.3};
  o.attributes.texcoords = {.enabled = true, .weight = 0.0};
  const SimplifyResult r = simplify(m, o);
  test::expect_same_topology(m, r.mesh);
  const auto out_uv = r.mesh.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  ASSERT_TRUE(out_uv);
  for (Face f : r.mesh.faces())
    for (Halfedge h : r.mesh.halfedges(f)) EXPECT_TRUE(out_uv[h].allFinite());
}

TEST(SimplifyAttributes, RejectsMissingAttributesBadWeightsAndNaNs) {
  SurfaceMesh m = colour_plane(4);
  SimplifyOptions o;
  o.attributes.texcoords.enabled = true;
  EXPECT_THROW(simplify(m, o), InvalidArgument);  // no texcoords on the mesh
  o.attributes = {};
  o.attributes.colors = {.enabled = true, .weight = -1.0};
  EXPECT_THROW(simplify(m, o), InvalidArgument);
  o.attributes.colors.weight = std::numeric_limits<double>::infinity();
  EXPECT_THROW(simplify(m, o), InvalidArgument);
  o.attributes.colors.weight = 1.0;
  m.get_property<Vertex, Color>(prop::kVertexColor)[Vertex(3)] = Color(std::nan(""), 0, 0);
  try {
    simplify(m, o);
    ADD_FAILURE() << "NaN colour accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("vertex 3"), std::string::npos) << e.what();
  }
}

// As given unless asked: the attributes a mesh holds are carried without being named, and
// what the output lacks is named.
TEST(SimplifyAttributes, KeptByDefaultAndWhatIsDroppedIsNamed) {
  SurfaceMesh m = uv_sphere(12, 24);
  m.add_property<Edge, double>(prop::kEdgeSharpness);
  // Face properties go with the faces: each output face has its input face's value.
  auto group = m.add_property<Face, std::string>(prop::kFaceGroup);
  for (Face f : m.faces()) group[f] = m.position(m.to_vertex(m.halfedge(f))).z() > 0 ? "north" : "south";
  EXPECT_EQ(present_attributes(m).names(), (std::vector<std::string>{"normals", "uv"}));
  const SimplifyResult kept = simplify(m, {.ratio = 0.3});
  const auto out_group = kept.mesh.get_property<Face, std::string>(prop::kFaceGroup);
  ASSERT_TRUE(out_group);
  std::size_t north = 0, south = 0;
  for (Face f : kept.mesh.faces()) north += out_group[f] == "north", south += out_group[f] == "south";
  EXPECT_EQ(north + south, kept.mesh.n_faces());
  EXPECT_GT(north, kept.mesh.n_faces() / 4);
  EXPECT_GT(south, kept.mesh.n_faces() / 4);
  EXPECT_TRUE(kept.mesh.has_property<Halfedge>(prop::kCornerTexCoord));
  EXPECT_TRUE(kept.mesh.has_property<Vertex>(prop::kVertexNormal));
  EXPECT_EQ(kept.dropped_properties, std::vector<std::string>{"e:sharpness"});
  const SimplifyResult bare = simplify(m, {.ratio = 0.3, .keep_attributes = false});
  EXPECT_EQ(bare.dropped_properties, (std::vector<std::string>{"v:normal", "h:texcoord", "e:sharpness"}));
  SimplifyOptions uv_only{.ratio = 0.3, .keep_attributes = false};
  uv_only.attributes.texcoords.enabled = true;
  EXPECT_EQ(simplify(m, uv_only).dropped_properties, (std::vector<std::string>{"v:normal", "e:sharpness"}));
  uv_only.keep_attributes = true;  // the named one, and the others the mesh holds
  EXPECT_EQ(simplify(m, uv_only).dropped_properties, std::vector<std::string>{"e:sharpness"});
}

TEST(LodChain, EveryLevelCarriesTheAttributesWithTheirSeam) {
  const SurfaceMesh m = uv_sphere(24, 48);
  const double f0 = static_cast<double>(m.n_faces());
  const auto levels = lod_chain(m, {.ratios = {0.25, 0.5, 0.1}, .measure = false});
  ASSERT_EQ(levels.size(), 3u);
  for (const LodLevel& l : levels) {
    const auto target = static_cast<double>(std::llround(l.ratio * f0));
    EXPECT_LE(static_cast<double>(l.faces), 1.25 * target);
    EXPECT_GE(static_cast<double>(l.faces), target - 2);
    test::expect_same_topology(m, l.mesh);
    const auto uv = l.mesh.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
    ASSERT_TRUE(uv) << "level " << l.ratio;
    EXPECT_TRUE(l.mesh.has_property<Vertex>(prop::kVertexNormal));
    const double err = mean_uv_error(l.mesh, [&](Halfedge h) { return uv[h]; });
    EXPECT_LT(err, 0.02) << "level " << l.ratio;
  }
  EXPECT_LT(levels[2].faces, levels[0].faces);
  EXPECT_LT(levels[0].faces, levels[1].faces);
  const auto bare = lod_chain(m, {.ratios = {0.25}, .simplify = {.keep_attributes = false}, .measure = false});
  EXPECT_FALSE(bare[0].mesh.has_property<Halfedge>(prop::kCornerTexCoord));
  EXPECT_FALSE(bare[0].mesh.has_property<Vertex>(prop::kVertexNormal));
}

}  // namespace
}  // namespace geom
