// Real meshes from $GEOM_DATA_DIR: vertex and face counts agree with MANIFEST.md, and every
// format round-trips them exactly.

#include "io_test_util.h"
#include "support/data.h"

#include <geom/io/io.h>

#include <gtest/gtest.h>

using namespace geom;

namespace {

struct Expected {
  const char* file;
  std::size_t v, f;
};

// Values from ../shared/meshes/MANIFEST.md (V after exact welding for STL).
constexpr Expected kManifest[] = {
    {"stanford-bunny.obj", 35947, 69451},   {"amo.ply", 90112, 180220},
    {"amo_binary.off", 90112, 180220},       {"icosahedron_ascii.stl", 12, 20},
    {"icosahedron_binary.stl", 12, 20},      {"utah_teapot.stl", 1232, 2464},
    {"cube_quads.off", 8, 6},                {"cube_tris.obj", 8, 12},
    {"chamfer-cube.off", 24, 26},            {"cylinder.obj", 220, 202},
    {"bunny_small.off", 3485, 6966},         {"spot_control_mesh.obj", 188, 180},
    {"beast.obj", 32311, 32364},             {"suzanne.obj", 507, 500},
    {"TinyTorus.obj", 24, 48},               {"teapot.obj", 3644, 6320},
    {"fandisk_quads.off", 766, 764},         {"opensubdiv/catmark_car.obj", 1642, 1575},
    {"opensubdiv/catmark_bishop.obj", 917, 968},
};

}  // namespace

TEST(RealMeshes, CountsMatchManifest) {
  GEOM_REQUIRE_DATA_DIR(dir);
  for (const Expected& e : kManifest) {
    SCOPED_TRACE(e.file);
    PolygonSoup s = read_soup(dir / e.file);
    EXPECT_EQ(s.positions.size(), e.v);
    EXPECT_EQ(s.n_faces(), e.f);
  }
}

TEST(RealMeshes, AmoPlyAndBinaryOffAreTheSameMesh) {
  GEOM_REQUIRE_DATA_DIR(dir);
  PolygonSoup a = read_soup(dir / "amo.ply");
  PolygonSoup b = read_soup(dir / "amo_binary.off");
  EXPECT_TRUE(geom::test::same_geometry(a, b));
}

TEST(RealMeshes, OpenSubdivTagsAreRead) {
  GEOM_REQUIRE_DATA_DIR(dir);
  PolygonSoup c = read_soup(dir / "opensubdiv/catmark_cube_creases1.obj");
  EXPECT_FALSE(c.creases.empty());
  PolygonSoup k = read_soup(dir / "opensubdiv/catmark_cubes_semisharp.obj");
  EXPECT_FALSE(k.corners.empty());
  EXPECT_TRUE(k.boundary_interpolation.has_value());
  // Tags survive a write and read.
  PolygonSoup r = read_soup(geom::test::bytes(geom::test::write_string(c, FileFormat::kObj)), FileFormat::kObj);
  ASSERT_EQ(r.creases.size(), c.creases.size());
  for (std::size_t i = 0; i < r.creases.size(); ++i) {
    EXPECT_EQ(r.creases[i].a, c.creases[i].a);
    EXPECT_EQ(r.creases[i].b, c.creases[i].b);
    EXPECT_EQ(r.creases[i].sharpness, c.creases[i].sharpness);
  }
  EXPECT_EQ(r.boundary_interpolation, c.boundary_interpolation);
}

TEST(RealMeshes, EveryMeshInTheSetReads) {
  GEOM_REQUIRE_DATA_DIR(dir);
  std::size_t n = 0;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file() || e.path().extension() == ".md") continue;
    SCOPED_TRACE(e.path().string());
    PolygonSoup s = read_soup(e.path());
    EXPECT_GT(s.positions.size(), 0u);
    EXPECT_GT(s.n_faces(), 0u);
    ++n;
  }
  EXPECT_GE(n, 30u);
}

TEST(RealMeshes, EveryFormatRoundTrips) {
  GEOM_REQUIRE_DATA_DIR(dir);
  for (const char* file : {"bunny_small.off", "cylinder.obj", "amo.ply", "utah_teapot.stl", "spot_control_mesh.obj"}) {
    SCOPED_TRACE(file);
    const PolygonSoup s = read_soup(dir / file);
    for (FileFormat f : {FileFormat::kObj, FileFormat::kPly, FileFormat::kOff}) {
      for (bool binary : {true, false}) {
        if (f != FileFormat::kPly && !binary) continue;
        WriteOptions o;
        o.binary = binary;
        PolygonSoup r = read_soup(write_soup(s, f, o), f);
        EXPECT_TRUE(geom::test::same_geometry(s, r)) << format_name(f) << " binary=" << binary;
      }
    }
    // STL welds and triangulates: compare triangle count and the position set.
    for (bool binary : {true, false}) {
      WriteOptions o;
      o.binary = binary;
      PolygonSoup r = read_soup(write_soup(s, FileFormat::kStl, o), FileFormat::kStl);
      std::size_t triangles = 0;
      for (std::size_t f = 0; f < s.n_faces(); ++f) triangles += s.face(f).size() - 2;
      EXPECT_EQ(r.n_faces(), triangles);
    }
  }
}
