// Every mesh of the shared corpus: analyze(soup) agrees with the independent count written
// down in ../shared/meshes/MANIFEST.md ($GEOM_DATA_DIR) (copied into the table below by hand from that
// file, never computed with geom), and build() turns each one into a valid mesh whose own
// analysis agrees again.

#include <geom/core/build.h>
#include <geom/core/topology.h>
#include <geom/core/validate.h>
#include <geom/io/io.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "support/data.h"

namespace geom {
namespace {

struct Expected {
  const char* file;
  std::size_t vertices;      ///< vertex records (STL: after exact welding)
  std::size_t unreferenced;  ///< vertices no face uses
  std::size_t faces;
  std::size_t boundary_loops;
  std::size_t components;
  bool closed, manifold, oriented;
  bool has_genus;            ///< MANIFEST gives a genus (manifold and consistently oriented)
  std::vector<long> genera;  ///< per component, ascending
};

// MANIFEST.md columns: V, F, Closed, Manifold, Oriented consistently, Components, Boundary
// loops, Genus; "unreferenced vertices" from the notes column.
const std::vector<Expected> kCorpus = {
    {"stanford-bunny.obj", 35947, 1113, 69451, 5, 1, false, true, true, true, {0}},
    {"bunny_closed.off", 34835, 0, 69666, 0, 1, true, true, true, true, {0}},
    {"bunny_small.off", 3485, 0, 6966, 0, 1, true, true, true, true, {0}},
    {"spot_quadrangulated.obj", 2930, 0, 2928, 0, 1, true, true, true, true, {0}},
    {"spot_triangulated.obj", 2930, 0, 5856, 0, 1, true, true, true, true, {0}},
    {"spot_control_mesh.obj", 188, 0, 180, 0, 1, true, true, true, true, {0}},
    {"beast.obj", 32311, 0, 32364, 0, 1, true, true, true, true, {0}},
    {"fandisk_quads.off", 766, 0, 764, 0, 1, true, true, true, true, {0}},
    {"fandisk.off", 6475, 0, 12946, 0, 1, true, true, true, true, {0}},
    {"horse_quad.obj", 2400, 0, 2398, 0, 1, true, true, true, true, {0}},
    {"suzanne.obj", 507, 0, 500, 4, 3, false, true, true, true, {0, 0, 0}},
    {"camelhead.off", 11381, 0, 22704, 1, 1, false, true, true, true, {0}},
    {"halftunnel.off", 831, 0, 784, 3, 1, false, true, true, true, {0}},
    {"annulus.obj", 4985, 0, 9724, 2, 1, false, true, true, true, {0}},
    {"hemisphere.off", 1861, 0, 3600, 1, 1, false, true, true, true, {0}},
    {"fertility.off", 4494, 0, 9000, 0, 1, true, true, true, true, {4}},
    {"3holes.off", 3596, 0, 7200, 0, 1, true, true, true, true, {3}},
    {"rocker-arm.obj", 10044, 0, 20088, 0, 1, true, true, true, true, {1}},
    {"TinyTorus.obj", 24, 0, 48, 0, 1, true, true, true, true, {1}},
    {"nefertiti.obj", 49971, 0, 99938, 0, 1, true, true, true, true, {0}},
    {"armadillo.obj", 43243, 0, 86482, 0, 1, true, true, true, true, {0}},
    {"amo_binary.off", 90112, 0, 180220, 0, 1, true, true, true, true, {0}},
    {"amo.ply", 90112, 0, 180220, 0, 1, true, true, true, true, {0}},
    {"teapot.obj", 3644, 0, 6320, 10, 4, false, false, true, false, {}},
    {"utah_teapot.stl", 1232, 0, 2464, 0, 1, true, true, true, true, {1}},
    {"icosahedron_ascii.stl", 12, 0, 20, 0, 1, true, true, true, true, {0}},
    {"icosahedron_binary.stl", 12, 0, 20, 0, 1, true, true, true, true, {0}},
    {"cube_quads.off", 8, 0, 6, 0, 1, true, true, true, true, {0}},
    {"cube_tris.obj", 8, 0, 12, 0, 1, true, true, true, true, {0}},
    {"chamfer-cube.off", 24, 0, 26, 0, 1, true, true, true, true, {0}},
    {"cylinder.obj", 220, 0, 202, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/bilinear_cube.obj", 8, 0, 6, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/bilinear_nonquads1.obj", 20, 0, 11, 1, 1, false, true, true, true, {0}},
    {"opensubdiv/catmark_cube.obj", 8, 0, 6, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/catmark_cube_creases1.obj", 8, 0, 6, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/catmark_cube_corner4.obj", 8, 0, 6, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/catmark_cubes_semisharp.obj", 32, 0, 24, 0, 4, true, true, true, true, {0, 0, 0, 0}},
    {"opensubdiv/catmark_torus.obj", 32, 0, 32, 0, 1, true, true, true, true, {1}},
    {"opensubdiv/catmark_torus_creases0.obj", 32, 0, 32, 0, 1, true, true, true, true, {1}},
    {"opensubdiv/catmark_toroidal_tet.obj", 20, 0, 24, 0, 1, true, true, true, true, {3}},
    {"opensubdiv/catmark_pyramid.obj", 5, 0, 5, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/catmark_pyramid_creases0.obj", 5, 0, 5, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/catmark_nonquads.obj", 33, 0, 17, 4, 4, false, true, true, true, {0, 0, 0, 0}},
    {"opensubdiv/catmark_flap.obj", 8, 0, 3, 1, 1, false, true, true, true, {0}},
    {"opensubdiv/catmark_tent_creases0.obj", 16, 0, 9, 1, 1, false, true, true, true, {0}},
    {"opensubdiv/catmark_dart_edgecorner.obj", 25, 0, 16, 1, 1, false, true, true, true, {0}},
    {"opensubdiv/catmark_edgecorner.obj", 52, 0, 28, 4, 4, false, true, true, true, {0, 0, 0, 0}},
    {"opensubdiv/catmark_hole_test2.obj", 25, 0, 16, 1, 1, false, true, true, true, {0}},
    {"opensubdiv/catmark_helmet.obj", 72, 0, 58, 1, 1, false, true, true, true, {0}},
    {"opensubdiv/catmark_pawn.obj", 601, 0, 588, 1, 1, false, true, true, true, {0}},
    {"opensubdiv/catmark_rook.obj", 768, 0, 777, 1, 1, false, true, true, true, {0}},
    {"opensubdiv/catmark_bishop.obj", 917, 0, 968, 1, 2, false, true, true, true, {0, 0}},
    {"opensubdiv/catmark_car.obj", 1642, 0, 1575, 11, 31, false, true, true, true, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 6}},
    {"opensubdiv/catmark_pole64.obj", 129, 0, 128, 1, 1, false, true, true, true, {0}},
    {"opensubdiv/catmark_single_crease.obj", 105, 0, 80, 1, 1, false, true, true, true, {0}},
    {"opensubdiv/catmark_smoothtris0.obj", 42, 0, 80, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/catmark_xord_interior.obj", 151, 0, 71, 9, 9, false, true, true, true, {0, 0, 0, 0, 0, 0, 0, 0, 0}},
    {"opensubdiv/catmark_gregory_test8.obj", 9, 0, 6, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/catmark_chaikin0.obj", 24, 0, 22, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/catmark_val2_interior.obj", 103, 0, 56, 8, 9, false, true, true, true, {0, 0, 0, 0, 0, 0, 0, 0, 0}},
    {"opensubdiv/loop_cube.obj", 14, 0, 24, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/loop_cube_creases1.obj", 8, 0, 12, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/loop_icosahedron.obj", 12, 0, 20, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/loop_icos_semisharp.obj", 48, 0, 80, 0, 4, true, true, true, true, {0, 0, 0, 0}},
    {"opensubdiv/loop_tetrahedron.obj", 4, 0, 4, 0, 1, true, true, true, true, {0}},
    {"opensubdiv/loop_toroidal_tet.obj", 32, 0, 72, 0, 1, true, true, true, true, {3}},
    {"opensubdiv/loop_saddle_edgecorner.obj", 6, 0, 4, 1, 1, false, true, true, true, {0}},
    {"opensubdiv/loop_triangle_edgecorner.obj", 48, 0, 49, 4, 4, false, true, true, true, {0, 0, 0, 0}},
    {"opensubdiv/loop_pole64.obj", 129, 0, 192, 1, 1, false, true, true, true, {0}},
    {"opensubdiv/loop_xord_interior.obj", 78, 0, 69, 9, 9, false, true, true, true, {0, 0, 0, 0, 0, 0, 0, 0, 0}},
    {"opensubdiv/loop_chaikin0.obj", 24, 0, 44, 0, 1, true, true, true, true, {0}},
};

long expected_chi(const Expected& x) {
  long chi = -static_cast<long>(x.boundary_loops);
  for (long g : x.genera) chi += 2 - 2 * g;
  return chi;
}

class Corpus : public ::testing::TestWithParam<Expected> {};

TEST_P(Corpus, SoupTopologyMatchesManifest) {
  GEOM_REQUIRE_DATA_DIR(dir);
  const Expected& x = GetParam();
  const PolygonSoup soup = read_soup(dir / x.file);
  const TopologyReport r = analyze(soup);
  EXPECT_EQ(r.vertices, x.vertices);
  EXPECT_EQ(r.isolated_vertices, x.unreferenced);
  EXPECT_EQ(r.faces, x.faces);
  EXPECT_EQ(r.boundary_loops, x.boundary_loops);
  EXPECT_EQ(r.components, x.components);
  EXPECT_EQ(r.closed, x.closed);
  EXPECT_EQ(r.manifold, x.manifold);
  EXPECT_EQ(r.consistently_oriented, x.oriented);
  EXPECT_EQ(r.out_of_range_faces, 0u);
  // χ = V_ref − E + F, always.
  const long v_ref = static_cast<long>(r.vertices - r.isolated_vertices);
  EXPECT_EQ(r.euler_characteristic, v_ref - static_cast<long>(r.edges) + static_cast<long>(r.faces));
  if (x.has_genus) {
    long total = 0;
    for (long g : x.genera) total += g;
    EXPECT_EQ(r.genus, total);
    std::vector<long> genera;
    for (const auto& c : r.per_component) genera.push_back(c.genus.value_or(-1));
    std::sort(genera.begin(), genera.end());
    EXPECT_EQ(genera, x.genera);
    // The surface form of Euler's formula fixes E from the manifest's own columns.
    EXPECT_EQ(r.euler_characteristic, expected_chi(x));
    const long e = static_cast<long>(x.vertices - x.unreferenced) + static_cast<long>(x.faces) - expected_chi(x);
    EXPECT_EQ(static_cast<long>(r.edges), e);
  } else {
    EXPECT_FALSE(r.genus.has_value());
  }
}

TEST_P(Corpus, BuildGivesValidMeshWithTheSameTopology) {
  GEOM_REQUIRE_DATA_DIR(dir);
  const Expected& x = GetParam();
  const PolygonSoup soup = read_soup(dir / x.file);
  const BuildResult b = build(soup);
  const auto v = validate(b.mesh);
  ASSERT_TRUE(v.ok()) << v.to_string();
  const TopologyReport t = analyze(b.mesh);
  EXPECT_TRUE(t.manifold);
  EXPECT_TRUE(t.genus.has_value());
  if (!x.manifold || !x.oriented) {
    EXPECT_TRUE(b.report.changed());
    EXPECT_FALSE(b.report.messages.empty());
    return;
  }
  // Clean input: nothing to repair, and the mesh has exactly the manifest's topology.
  EXPECT_FALSE(b.report.changed()) << ::testing::PrintToString(b.report.messages);
  EXPECT_EQ(b.mesh.n_faces(), x.faces);
  EXPECT_EQ(t.vertices, x.vertices);
  EXPECT_EQ(t.isolated_vertices, x.unreferenced);
  EXPECT_EQ(t.boundary_loops, x.boundary_loops);
  EXPECT_EQ(t.components, x.components);
  EXPECT_EQ(t.closed, x.closed);
  EXPECT_EQ(t.euler_characteristic, expected_chi(x));
  std::vector<long> genera;
  for (const auto& c : t.per_component) genera.push_back(c.genus.value_or(-1));
  std::sort(genera.begin(), genera.end());
  EXPECT_EQ(genera, x.genera);
  // Faces keep their input corner order.
  for (Face f : b.mesh.faces()) {
    auto in = soup.face(b.report.face_origin[f.idx()]);
    std::size_t i = 0;
    for (Vertex w : b.mesh.vertices(f)) {
      ASSERT_LT(i, in.size());
      EXPECT_EQ(w, b.report.vertex_map[in[i++]]);
    }
  }
}

std::string test_name(const ::testing::TestParamInfo<Expected>& info) {
  std::string s = info.param.file;
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(Manifest, Corpus, ::testing::ValuesIn(kCorpus), test_name);

// MANIFEST notes: "non-manifold vertices:38; duplicate-coordinate vertices:403".
TEST(CorpusTeapot, NonManifoldVerticesMatchManifestAndWeldingIsReported) {
  GEOM_REQUIRE_DATA_DIR(dir);
  const PolygonSoup soup = read_soup(dir / "teapot.obj");
  EXPECT_EQ(analyze(soup).nonmanifold_vertices, 38u);
  EXPECT_EQ(analyze(soup).nonmanifold_edges, 0u);
  const BuildResult b = build(soup);
  EXPECT_EQ(b.report.split_nonmanifold_vertices, 38u);
  EXPECT_EQ(b.mesh.n_faces(), 6320u);
  const BuildResult w = build(soup, {.weld_tolerance = 0});
  EXPECT_EQ(w.report.welded_vertices, 403u);
  EXPECT_TRUE(validate(w.mesh).ok());
}

TEST(CorpusTable, CoversEveryFileInTheDirectory) {
  GEOM_REQUIRE_DATA_DIR(dir);
  std::vector<std::string> listed, found;
  for (const auto& x : kCorpus) listed.push_back(x.file);
  for (const auto& sub : {std::filesystem::path(), std::filesystem::path("opensubdiv")})
    for (const auto& entry : std::filesystem::directory_iterator(dir / sub))
      if (entry.is_regular_file() && entry.path().extension() != ".md")
        found.push_back((sub / entry.path().filename()).generic_string());
  std::sort(listed.begin(), listed.end());
  std::sort(found.begin(), found.end());
  EXPECT_EQ(listed, found);
}

}  // namespace
}  // namespace geom
