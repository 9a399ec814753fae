// read_points: numeric text in 2D and 3D, mesh files, and its errors.

#include "io_test_util.h"

#include <geom/io/points.h>

#include <gtest/gtest.h>

using namespace geom;
using geom::test::bytes;

TEST(Points, Text2DWithCommasTabsAndComments) {
  PointSet p = read_points(bytes("# header\n1 2\n3,4\n\n5\t6 # trailing\n  -7.5e1 , 8\r\n"), "p.txt");
  EXPECT_EQ(p.dimension, 2);
  ASSERT_EQ(p.points.size(), 4u);
  EXPECT_EQ(p.points[1], Eigen::Vector3d(3, 4, 0));
  EXPECT_EQ(p.points[3], Eigen::Vector3d(-75, 8, 0));
}

TEST(Points, Text3D) {
  PointSet p = read_points(bytes("0 0 0\n1 2 3\n"), "p.xyz");
  EXPECT_EQ(p.dimension, 3);
  EXPECT_EQ(p.points[1], Eigen::Vector3d(1, 2, 3));
}

TEST(Points, EmptyTextIsEmpty) {
  PointSet p = read_points(bytes("# nothing\n"), "e.txt");
  EXPECT_TRUE(p.points.empty());
}

TEST(Points, MeshFilesGiveTheirVertices) {
  PointSet p = read_points(bytes("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                                 "property float z\nend_header\n1 2 3\n4 5 6\n"),
                           "v.ply");
  EXPECT_EQ(p.dimension, 3);
  ASSERT_EQ(p.points.size(), 2u);
  EXPECT_EQ(p.points[1], Eigen::Vector3d(4, 5, 6));
  PointSet o = read_points(bytes("OFF\n1 0 0\n1 1 1\n"), "v.off");
  EXPECT_EQ(o.points.size(), 1u);
  PointSet j = read_points(bytes("v 1 2 3\nv 4 5 6\n"), "v.obj", FileFormat::kObj);
  EXPECT_EQ(j.points.size(), 2u);
}

TEST(Points, FromFilesOfAnyExtension) {
  const auto dir = std::filesystem::temp_directory_path() / "geom_points_test";
  std::filesystem::create_directories(dir);
  {
    std::FILE* f = std::fopen((dir / "pts.dat").c_str(), "w");
    std::fputs("0 0\n1 0\n0 1\n", f);
    std::fclose(f);
  }
  PointSet p = read_points(dir / "pts.dat");
  EXPECT_EQ(p.dimension, 2);
  EXPECT_EQ(p.points.size(), 3u);
  write_soup(geom::test::tetra(), dir / "t.off");
  EXPECT_EQ(read_points(dir / "t.off").points.size(), 4u);
  EXPECT_THROW(read_points(dir / "missing.txt"), Error);
  std::filesystem::remove_all(dir);
}

TEST(Points, ErrorsNameTheLine) {
  struct Case {
    const char* text;
    std::uint64_t line;
  };
  for (const Case& c : {Case{"1 2\n3 x\n", 2}, Case{"1 2\n3 4 5\n", 2}, Case{"1 2 3\n4 5\n", 2}, Case{"1\n", 1},
                        Case{"1 2\n\n3 nan\n", 3}, Case{"1 2 3 4\n", 1}, Case{"1 2\n3 inf\n", 2}}) {
    try {
      read_points(bytes(c.text), "bad.txt");
      ADD_FAILURE() << c.text;
    } catch (const ParseError& e) {
      EXPECT_EQ(e.where(), c.line) << e.what();
      EXPECT_NE(std::string(e.what()).find("bad.txt:"), std::string::npos) << e.what();
    }
  }
}
