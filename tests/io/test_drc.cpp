// Draco: round trips through our writer and reader, and agreement with Debian's
// draco_encoder / draco_decoder tools.

#include "io_test_util.h"
#include "support/data.h"

#include <geom/io/io.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <set>

using namespace geom;

namespace {

bool on_path(const char* tool) {
  const std::string cmd = std::string("command -v ") + tool + " >/dev/null 2>&1";
  return std::system(cmd.c_str()) == 0;
}

std::set<std::array<double, 3>> position_set(const PolygonSoup& s) {
  std::set<std::array<double, 3>> out;
  for (const auto& p : s.positions) out.insert({p.x(), p.y(), p.z()});
  return out;
}

}  // namespace

TEST(Drc, LosslessRoundTripKeepsOrderAndBits) {
  PolygonSoup t = geom::test::tetra();
  const auto bytes = write_soup(t, FileFormat::kDrc);
  PolygonSoup r = read_soup(bytes, FileFormat::kDrc, "t.drc");
  EXPECT_EQ(position_set(t), position_set(r));
  EXPECT_EQ(r.n_faces(), 4u);
}

// Draco's sequential decoder refuses more points than three per triangle, so a lossless file
// of one triangle beside an isolated vertex was written but never read back. The writer
// keeps the vertices of faces, in order; a point cloud keeps all of its points.
TEST(Drc, VerticesNoFaceUsesAreLeftOutSoThatTheFileDecodes) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {5, 5, 5}, {1, 0, 0}, {0, 1, 0}};
  s.add_face({0, 2, 3});
  for (int bits : {0, 11}) {
    WriteOptions o;
    o.drc_position_bits = bits;
    const PolygonSoup r = read_soup(write_soup(s, FileFormat::kDrc, o), FileFormat::kDrc, "t.drc");
    ASSERT_EQ(r.positions.size(), 3u) << bits;
    ASSERT_EQ(r.n_faces(), 1u);
    if (bits == 0) {
      EXPECT_EQ(r.positions, (std::vector<Point>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}));
      EXPECT_EQ(r.face_indices, (std::vector<std::uint32_t>{0, 1, 2}));
    }
  }
  PolygonSoup cloud;
  cloud.positions = s.positions;
  EXPECT_EQ(read_soup(write_soup(cloud, FileFormat::kDrc), FileFormat::kDrc, "c.drc").positions,
            cloud.positions);
}

TEST(Drc, PolygonsAreFannedAndAttributesCarried) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  s.add_face({0, 1, 2, 3});
  s.vertex_normals.assign(4, Normal(0, 0, 1));
  s.vertex_texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  PolygonSoup r = read_soup(write_soup(s, FileFormat::kDrc), FileFormat::kDrc);
  EXPECT_EQ(r.n_faces(), 2u);
  ASSERT_EQ(r.vertex_normals.size(), r.positions.size());
  for (const auto& n : r.vertex_normals) EXPECT_EQ(n, Normal(0, 0, 1));
  ASSERT_EQ(r.vertex_texcoords.size(), r.positions.size());
}

TEST(Drc, QuantisedWithinBound) {
  PolygonSoup t = geom::test::tetra();
  WriteOptions o;
  o.drc_position_bits = 11;
  o.drc_level = 10;
  PolygonSoup r = read_soup(write_soup(t, FileFormat::kDrc, o), FileFormat::kDrc);
  ASSERT_EQ(r.positions.size(), 4u);
  for (const auto& p : r.positions) {
    double best = 1e9;
    for (const auto& q : t.positions) best = std::min(best, (p - q).norm());
    EXPECT_LT(best, 1.5 * std::sqrt(3.0) / 2047.0);
  }
}

TEST(Drc, BadOptionsAndBadBytes) {
  WriteOptions o;
  o.drc_position_bits = 31;
  EXPECT_THROW(write_soup(geom::test::tetra(), FileFormat::kDrc, o), InvalidArgument);
  o.drc_position_bits = 0;
  o.drc_level = 11;
  EXPECT_THROW(write_soup(geom::test::tetra(), FileFormat::kDrc, o), InvalidArgument);
  EXPECT_THROW(read_soup(geom::test::bytes("DRACO garbage"), FileFormat::kDrc, "g.drc"), ParseError);
  auto good = write_soup(geom::test::tetra(), FileFormat::kDrc);
  good.resize(good.size() / 2);
  EXPECT_THROW(read_soup(good, FileFormat::kDrc, "h.drc"), ParseError);
}

TEST(Drc, AgreesWithDracoTools) {
  if (!on_path("draco_encoder") || !on_path("draco_decoder"))
    GTEST_SKIP() << "draco_encoder/draco_decoder not on PATH (Debian package 'draco')";
  GEOM_REQUIRE_DATA_DIR(dir);
  const auto tmp = std::filesystem::temp_directory_path() / "geom_drc_tools";
  std::filesystem::create_directories(tmp);
  // Their encoder → our reader.
  const auto src = dir / "bunny_small.off";
  PolygonSoup original = read_soup(src);
  // Draco keeps float32 positions; compare against the float-rounded input.
  for (auto& p : original.positions)
    for (int k = 0; k < 3; ++k) {
      // volatile: GCC 12's SLP vectoriser folds the double→float→double round trip away.
      volatile float f = static_cast<float>(p[k]);
      p[k] = f;
    }
  // draco_encoder reads OBJ/PLY; give it our PLY.
  write_soup(original, tmp / "in.ply");
  const std::string enc = "draco_encoder -i " + (tmp / "in.ply").string() + " -o " + (tmp / "theirs.drc").string() +
                          " -qp 0 >/dev/null 2>&1";
  ASSERT_EQ(std::system(enc.c_str()), 0) << enc;
  PolygonSoup theirs = read_soup(tmp / "theirs.drc");
  EXPECT_EQ(theirs.n_faces(), original.n_faces());
  EXPECT_EQ(position_set(theirs), position_set(original));
  // Our writer → their decoder → our PLY reader.
  write_soup(original, tmp / "ours.drc");
  const std::string dec = "draco_decoder -i " + (tmp / "ours.drc").string() + " -o " + (tmp / "out.ply").string() +
                          " >/dev/null 2>&1";
  ASSERT_EQ(std::system(dec.c_str()), 0) << dec;
  PolygonSoup back = read_soup(tmp / "out.ply");
  EXPECT_EQ(back.n_faces(), original.n_faces());
  EXPECT_EQ(position_set(back), position_set(original));
  std::filesystem::remove_all(tmp);
}
