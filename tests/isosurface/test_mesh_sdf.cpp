// Signed distance to a mesh as an implicit input: exact against analytic distances, correct
// sign at vertices/edges/faces, bounded far field, closed iso-surfaces, open meshes rejected,
// the right sign next to slivers and folded hole fills of a real mesh.

#include "support/data.h"
#include "surface_check.h"

#include <geom/core/errors.h>
#include <geom/io/io.h>
#include <geom/isosurface/implicit.h>
#include <geom/isosurface/marching_cubes.h>
#include <geom/isosurface/mesh_sdf.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace geom;
using geom::test::check_surface;

namespace {

/// The cube [-h, h]³ as 12 outward triangles.
SurfaceMesh cube_mesh(double h) {
  SurfaceMesh m;
  Vertex v[8];
  for (int c = 0; c < 8; ++c)
    v[c] = m.add_vertex(Point(c & 1 ? h : -h, c & 2 ? h : -h, c & 4 ? h : -h));
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.add_triangle(v[q[0]], v[q[1]], v[q[2]]);
    m.add_triangle(v[q[0]], v[q[2]], v[q[3]]);
  }
  return m;
}

double box_sdf(const Eigen::Vector3d& p, double h) {
  Eigen::Vector3d q = p.cwiseAbs() - Eigen::Vector3d::Constant(h);
  return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

/// A closed sphere mesh of radius r from our own marching cubes.
SurfaceMesh sphere_mesh(double r, std::size_t n) {
  ScalarGrid g = sample(implicit::Sphere{Eigen::Vector3d::Zero(), r}, cube_box(1.0, n, true));
  return marching_cubes(g.view()).mesh;
}

/// A closed C-shaped prism (the notch opens towards +x) whose top is filled like a hole: a
/// fan from the vertex centroid, which lies in the notch, so the fan's triangles over the
/// notch are inverted and fold back onto their neighbours — the overlapping, non-embedded
/// surface that naive hole filling leaves.
SurfaceMesh folded_fan_prism() {
  const double xy[10][2] = {{0, 0}, {4, 0}, {4, 1}, {1, 1}, {1, 3},
                            {4, 3}, {4, 4}, {0, 4}, {0, 3}, {0, 1}};
  SurfaceMesh m;
  Vertex bottom[10], top[10];
  Point centre = Point::Zero();
  for (int k = 0; k < 10; ++k) {
    bottom[k] = m.add_vertex(Point(xy[k][0], xy[k][1], 0));
    top[k] = m.add_vertex(Point(xy[k][0], xy[k][1], 1));
    centre += Point(xy[k][0], xy[k][1], 1) / 10;
  }
  const Vertex c = m.add_vertex(centre);
  // The bottom, properly triangulated (corners in counter-clockwise order seen from +z).
  const int floor[8][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 9}, {9, 3, 4},
                           {9, 4, 8}, {7, 8, 4}, {7, 4, 5}, {7, 5, 6}};
  for (const auto& t : floor) m.add_triangle(bottom[t[0]], bottom[t[2]], bottom[t[1]]);
  for (int k = 0; k < 10; ++k) {
    const int j = (k + 1) % 10;
    m.add_triangle(bottom[k], bottom[j], top[j]);
    m.add_triangle(bottom[k], top[j], top[k]);
    m.add_triangle(c, top[k], top[j]);
  }
  return m;
}

}  // namespace

TEST(MeshSdf, CubeMatchesAnalyticDistanceEverywhere) {
  MeshSignedDistance sd(cube_mesh(0.5));
  // Points whose closest feature is a face, an edge, a corner, and points inside.
  for (const Eigen::Vector3d& p :
       {Eigen::Vector3d(0.9, 0.1, -0.2), Eigen::Vector3d(0.8, 0.8, 0.0),
        Eigen::Vector3d(0.7, 0.9, 0.6), Eigen::Vector3d(-0.9, -0.9, -0.9),
        Eigen::Vector3d(0.1, 0.2, 0.3), Eigen::Vector3d(0.45, 0.44, -0.43),
        Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(0.5, 0.2, 0.1)})
    EXPECT_NEAR(sd(p), box_sdf(p, 0.5), 1e-12) << p.transpose();

  MeshSdfOptions o;
  o.resolution = 24;
  o.exact_everywhere = true;
  o.use_double = true;
  MeshSdf exact = signed_distance_grid(cube_mesh(0.5), o);
  const GridView v = exact.grid.view();
  double worst = 0;
  for (std::size_t z = 0; z < v.dims.nz; ++z)
    for (std::size_t y = 0; y < v.dims.ny; ++y)
      for (std::size_t x = 0; x < v.dims.nx; ++x)
        worst = std::max(worst, std::abs(v.at(x, y, z) - box_sdf(v.position(x, y, z), 0.5)));
  EXPECT_LT(worst, 1e-12);
  EXPECT_EQ(exact.stats.exact_samples, exact.stats.samples);
}

TEST(MeshSdf, FarBlocksAreBoundedWithTheRightSign) {
  MeshSdfOptions o;
  o.resolution = 96;
  o.use_double = true;
  MeshSdf s = signed_distance_grid(cube_mesh(0.5), o);
  const GridView v = s.grid.view();
  const double h = v.geometry.spacing.x();
  const double band = o.band_cells * h;
  std::size_t wrong_sign = 0, inexact_in_band = 0, over = 0;
  for (std::size_t z = 0; z < v.dims.nz; ++z)
    for (std::size_t y = 0; y < v.dims.ny; ++y)
      for (std::size_t x = 0; x < v.dims.nx; ++x) {
        const double got = v.at(x, y, z), want = box_sdf(v.position(x, y, z), 0.5);
        if (std::abs(want) > 1e-12) wrong_sign += (got < 0) != (want < 0);
        if (std::abs(want) <= band) inexact_in_band += std::abs(got - want) > 1e-12;
        over += std::abs(got) > std::abs(want) + 1e-12;  // far values are lower bounds
      }
  EXPECT_EQ(wrong_sign, 0u);
  EXPECT_EQ(inexact_in_band, 0u);
  EXPECT_EQ(over, 0u);
  // Only the work the surface needs: most samples come from one query per block.
  EXPECT_LT(s.stats.exact_samples, s.stats.samples / 2) << s.stats.exact_samples;
  EXPECT_LT(s.stats.near_blocks, s.stats.blocks);
}

TEST(MeshSdf, SphereMeshGivesClosedSurfaceNearTheSphere) {
  const double r = 0.7;
  SurfaceMesh sphere = sphere_mesh(r, 32);
  for (double level : {0.0, 0.15, -0.2}) {
    MeshSdfOptions o;
    o.resolution = 40;
    o.level = level;
    MeshSdf s = signed_distance_grid(sphere, o);
    MarchingCubesOptions mo;
    mo.level = level;
    IsoSurface iso = marching_cubes_arrays(s.grid.view(), mo);
    auto c = check_surface(iso.positions, iso.triangles);
    EXPECT_TRUE(c.closed_manifold()) << "level " << level << ": " << c.summary();
    EXPECT_EQ(c.euler(), 2) << level;
    EXPECT_GT(c.signed_volume, 0) << "outward orientation";
    double worst = 0;
    for (const Point& p : iso.positions) worst = std::max(worst, std::abs(p.norm() - (r + level)));
    // The input mesh is within about 2e-3 of the sphere; the resampling adds O(h²).
    EXPECT_LT(worst, 0.01) << "level " << level;
  }
}

TEST(MeshSdf, CubeOffsetSurfaceIsAtTheOffsetDistance) {
  MeshSdfOptions o;
  o.resolution = 40;
  o.level = 0.2;
  MeshSdf s = signed_distance_grid(cube_mesh(0.5), o);
  MarchingCubesOptions mo;
  mo.level = o.level;
  IsoSurface iso = marching_cubes_arrays(s.grid.view(), mo);
  auto c = check_surface(iso.positions, iso.triangles);
  EXPECT_TRUE(c.closed_manifold()) << c.summary();
  EXPECT_EQ(c.euler(), 2);
  EXPECT_TRUE(iso.stats.closed);
  double worst = 0;
  for (const Point& p : iso.positions) worst = std::max(worst, std::abs(box_sdf(p, 0.5) - 0.2));
  EXPECT_LT(worst, 0.01);
}

TEST(MeshSdf, OpenMeshIsRejectedNamingAnEdge) {
  SurfaceMesh open = cube_mesh(0.5);
  open.delete_face(Face(0));
  open.compact();
  try {
    MeshSignedDistance sd(open);
    FAIL() << "expected InvalidArgument";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("closed mesh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("3 boundary edges"), std::string::npos) << e.what();
  }
  EXPECT_THROW(MeshSignedDistance{SurfaceMesh()}, InvalidArgument);
  MeshSdfOptions o;
  o.resolution = 4;
  EXPECT_THROW(signed_distance_grid(cube_mesh(0.5), o), InvalidArgument);
}

TEST(MeshSdf, WindingNumberIsOneInsideAndZeroOutside) {
  MeshSignedDistance sd(cube_mesh(0.5));
  EXPECT_NEAR(sd.winding_number(Eigen::Vector3d(0.1, -0.2, 0.3)), 1.0, 1e-12);
  EXPECT_NEAR(sd.winding_number(Eigen::Vector3d(0.49, 0.49, -0.49)), 1.0, 1e-12);
  EXPECT_NEAR(sd.winding_number(Eigen::Vector3d(0.51, 0.0, 0.0)), 0.0, 1e-12);
  EXPECT_NEAR(sd.winding_number(Eigen::Vector3d(3.0, -2.0, 1.0)), 0.0, 1e-12);
}

// Before: the pseudo-normal of the inverted fan triangles (and of the edges where they fold)
// gave whole regions the wrong sign; χ = −23 at resolution 24. The winding number counts the
// overlapping layers with their orientation, so it sees the C-shaped solid.
TEST(MeshSdf, FoldedHoleFillFanGetsTheWindingNumberSign) {
  const MeshSignedDistance sd(folded_fan_prism());
  MeshSdfOptions o;
  o.resolution = 32;
  o.exact_everywhere = true;
  o.use_double = true;
  MeshSdf s = signed_distance_grid(sd, o);
  const GridView v = s.grid.view();
  std::size_t wrong = 0;
  for (std::size_t z = 0; z < v.dims.nz; ++z)
    for (std::size_t y = 0; y < v.dims.ny; ++y)
      for (std::size_t x = 0; x < v.dims.nx; ++x) {
        const double w = sd.winding_number(v.position(x, y, z));
        if (std::abs(v.at(x, y, z)) > 1e-9) wrong += (v.at(x, y, z) < 0) != (w > 0.5);
      }
  EXPECT_EQ(wrong, 0u);
  for (std::size_t resolution : {24, 40}) {
    o.resolution = resolution;
    o.exact_everywhere = false;
    IsoSurface iso = marching_cubes_arrays(signed_distance_grid(sd, o).grid.view());
    auto c = check_surface(iso.positions, iso.triangles);
    EXPECT_TRUE(c.closed_manifold()) << resolution << ": " << c.summary();
    EXPECT_EQ(c.euler(), 2) << resolution;
  }
}

// bunny_closed.off fills its holes with fans that fold back over themselves (two triangles
// of one fan with nearly opposite normals) and contains needle slivers. Before: samples 0.01
// away from a fold, and samples whose closest point is on a sliver's edge (its barycentric
// coordinates rounded to "interior"), got the wrong sign, adding tiny components (χ = 6 at
// resolution 96 and 128, 4 at 256). The points below are such samples; the winding number is
// the oracle.
TEST(MeshSdf, RealMeshSignIsRightAtFoldsAndSlivers) {
  GEOM_REQUIRE_DATA_DIR(dir);
  const MeshSignedDistance sd(load_mesh(dir / "bunny_closed.off").mesh);
  for (const Eigen::Vector3d& p : {
           Eigen::Vector3d(-0.050954327359550557, 0.065543614306741577, 0.016831984658988747),
           Eigen::Vector3d(-0.054453181370786509, 0.058545906284269665, 0.018581411664606737),
           Eigen::Vector3d(-0.019654338162650609, 0.041683959242168681, 0.040670562289759044)}) {
    EXPECT_NEAR(sd.winding_number(p), 1.0, 1e-9) << p.transpose();
    EXPECT_LT(sd(p), 0) << p.transpose();
  }
  MeshSdfOptions o;
  o.resolution = 96;
  IsoSurface iso = marching_cubes_arrays(signed_distance_grid(sd, o).grid.view());
  auto c = check_surface(iso.positions, iso.triangles);
  EXPECT_TRUE(c.closed_manifold()) << c.summary();
  EXPECT_EQ(c.euler(), 2) << "one sphere-like component, no specks";
}
