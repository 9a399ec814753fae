// OFF (variants, binary in both byte orders) and STL (ascii, binary, welding).

#include "io_test_util.h"

#include <geom/io/io.h>

#include <gtest/gtest.h>

#include <cstring>

using namespace geom;
using geom::test::parse;
using geom::test::put;

namespace {

std::string binary_off(bool big, bool colour_counts) {
  std::string s = "OFF BINARY\n";
  put(s, std::int32_t{4}, big);
  put(s, std::int32_t{2}, big);
  put(s, std::int32_t{0}, big);
  const float xyz[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.5f}};
  for (const auto& p : xyz)
    for (float c : p) put(s, c, big);
  for (auto face : {std::array<std::int32_t, 3>{0, 1, 2}, std::array<std::int32_t, 3>{0, 2, 3}}) {
    put(s, std::int32_t{3}, big);
    for (auto i : face) put(s, i, big);
    if (colour_counts) {
      put(s, std::int32_t{3}, big);
      for (int k = 0; k < 3; ++k) put(s, 0.5f, big);
    }
  }
  return s;
}

}  // namespace

TEST(Off, AsciiWithCommentsAndFaceColours) {
  PolygonSoup s = parse("OFF\n# a comment\n4 2 0\n\n0 0 0\n1 0 0\n1 1 0 # trailing\n0 1 0\n"
                        "3 0 1 2 255 0 0\n3 0 2 3\n",
                        FileFormat::kOff);
  ASSERT_EQ(s.positions.size(), 4u);
  ASSERT_EQ(s.n_faces(), 2u);
  EXPECT_EQ(s.face(1)[2], 3u);
}

TEST(Off, CountsOnTheHeaderLine) {
  PolygonSoup s = parse("OFF 3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", FileFormat::kOff);
  EXPECT_EQ(s.n_faces(), 1u);
}

TEST(Off, Variants) {
  PolygonSoup c = parse("COFF\n3 1 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n0 1 0 0 0 255 255\n3 0 1 2\n",
                        FileFormat::kOff);
  ASSERT_EQ(c.vertex_colors.size(), 3u);
  EXPECT_EQ(c.vertex_colors[1], Color(0, 1, 0));
  PolygonSoup cf = parse("COFF\n3 1 0\n0 0 0 1.0 0.5 0\n1 0 0 0 1 0.25\n0 1 0 0 0 1\n3 0 1 2\n", FileFormat::kOff);
  EXPECT_EQ(cf.vertex_colors[0], Color(1, 0.5, 0));
  EXPECT_EQ(cf.vertex_colors[1], Color(0, 1, 0.25));
  PolygonSoup n = parse("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n", FileFormat::kOff);
  ASSERT_EQ(n.vertex_normals.size(), 3u);
  EXPECT_EQ(n.vertex_normals[2], Normal(0, 0, 1));
  PolygonSoup st = parse("STCNOFF\n3 1 0\n0 0 0 0 0 1 1 0 0 0.5 0.5\n1 0 0 0 0 1 1 0 0 1 0\n0 1 0 0 0 1 1 0 0 0 1\n3 0 1 2\n",
                         FileFormat::kOff);
  ASSERT_EQ(st.vertex_texcoords.size(), 3u);
  EXPECT_EQ(st.vertex_texcoords[0], TexCoord(0.5, 0.5));
  EXPECT_EQ(st.vertex_colors[0], Color(1, 0, 0));
}

TEST(Off, BinaryInEveryByteOrderAndFaceLayout) {
  for (bool big : {true, false})
    for (bool counts : {true, false}) {
      PolygonSoup s = parse(binary_off(big, counts), FileFormat::kOff);
      ASSERT_EQ(s.positions.size(), 4u) << big << counts;
      EXPECT_EQ(s.positions[3], Point(0, 1, 0.5));
      ASSERT_EQ(s.n_faces(), 2u);
      EXPECT_EQ(s.face(1)[2], 3u);
    }
}

TEST(Off, RoundTripBitExact) {
  PolygonSoup s = geom::test::house();
  s.vertex_colors.assign(5, Color(1, 0, 1));  // integral floats must not read back as 0-255
  s.vertex_normals.assign(5, Normal(0.1, 0.2, 0.3));
  s.vertex_texcoords.assign(5, TexCoord(0.1, 1e-5));
  PolygonSoup r = parse(geom::test::write_string(s, FileFormat::kOff), FileFormat::kOff);
  EXPECT_TRUE(geom::test::same_geometry(s, r));
  EXPECT_TRUE(geom::test::same_vectors(s.vertex_colors, r.vertex_colors, "colors"));
  EXPECT_TRUE(geom::test::same_vectors(s.vertex_normals, r.vertex_normals, "normals"));
  EXPECT_TRUE(geom::test::same_vectors(s.vertex_texcoords, r.vertex_texcoords, "texcoords"));
}

TEST(Off, Errors) {
  for (const char* text : {"OFF\n3 1 0\n0 0 0\n1 0 0\n", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
                           "OFF\n1000000000000 1 0\n0 0 0\n", "OFF\nx 1 0\n", "4OFF\n1 0 0\n0 0 0 0\n",
                           "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 nan\n3 0 1 2\n", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n0\n"}) {
    try {
      parse(text, FileFormat::kOff, "m.off");
      ADD_FAILURE() << text;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find("m.off:"), std::string::npos) << e.what();
    }
  }
  std::string bin = binary_off(false, false);
  EXPECT_THROW(parse(bin.substr(0, bin.size() - 2), FileFormat::kOff), ParseError);
}

TEST(Stl, AsciiWeldsCorners) {
  const char* text =
      "solid two\n"
      " facet normal 0 0 1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n   vertex 0 1 0\n  endloop\n endfacet\n"
      " facet normal 0 0 1\n  outer loop\n   vertex 1 0 0\n   vertex 1 1 0\n   vertex 0 1 -0\n  endloop\n endfacet\n"
      "endsolid two\n";
  PolygonSoup s = parse(text, FileFormat::kStl);
  EXPECT_EQ(s.positions.size(), 4u);
  ASSERT_EQ(s.n_faces(), 2u);
  EXPECT_EQ(s.face(1)[0], 1u);
  EXPECT_EQ(s.face(1)[2], 2u);
}

TEST(Stl, BinaryDetectedBySizeEvenWithSolidHeader) {
  // Faces list the vertices in index order first, so welding numbers them the same way.
  PolygonSoup t;
  t.positions = geom::test::tetra().positions;
  t.add_face({0, 1, 2});
  t.add_face({0, 3, 1});
  t.add_face({1, 3, 2});
  t.add_face({2, 3, 0});
  std::string bin = geom::test::write_string(t, FileFormat::kStl);
  ASSERT_EQ(bin.size(), 84u + 50u * 4u);
  std::memcpy(bin.data(), "solid trick", 11);
  PolygonSoup r = parse(bin, FileFormat::kStl);
  EXPECT_TRUE(geom::test::same_geometry(t, r));
}

TEST(Stl, RoundTripAsciiAndBinaryWithFanTriangulation) {
  PolygonSoup quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5f, 1.5f, 0}};
  quad.add_face({0, 1, 2, 3});
  quad.add_face({3, 2, 4});
  for (bool binary : {true, false}) {
    WriteOptions o;
    o.binary = binary;
    PolygonSoup r = parse(geom::test::write_string(quad, FileFormat::kStl, o), FileFormat::kStl);
    EXPECT_TRUE(geom::test::same_vectors(quad.positions, r.positions, "positions"));
    ASSERT_EQ(r.n_faces(), 3u);
    EXPECT_EQ(std::vector<std::uint32_t>(r.face(1).begin(), r.face(1).end()), (std::vector<std::uint32_t>{0, 2, 3}));
  }
  // ascii keeps doubles exactly (welding by value turns -0 into +0)
  WriteOptions ascii;
  ascii.binary = false;
  PolygonSoup h = geom::test::house();
  h.positions[1].y() = 0.0;
  PolygonSoup r = parse(geom::test::write_string(h, FileFormat::kStl, ascii), FileFormat::kStl);
  EXPECT_TRUE(geom::test::same_vectors(h.positions, r.positions, "positions"));
}

TEST(Stl, Errors) {
  std::string bin = geom::test::write_string(geom::test::tetra(), FileFormat::kStl);
  for (const std::string& bad :
       {bin.substr(0, bin.size() - 1), std::string("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"),
        std::string("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zz\n"), std::string("abc"),
        std::string("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n")}) {
    try {
      parse(bad, FileFormat::kStl, "s.stl");
      ADD_FAILURE() << bad.size();
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find("s.stl"), std::string::npos) << e.what();
    }
  }
  // NaN in binary names the byte offset of the coordinate.
  std::string nan = bin;
  const float q = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(nan.data() + 84 + 12 + 4, &q, 4);
  try {
    parse(nan, FileFormat::kStl, "n.stl");
    ADD_FAILURE();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.unit(), ParseError::Unit::kByte);
    EXPECT_EQ(e.where(), 96u);
  }
}

TEST(Formats, NamesExtensionsAndSniffing) {
  EXPECT_EQ(format_from_path("a/b.OBJ"), FileFormat::kObj);
  EXPECT_EQ(format_from_path("x.ply"), FileFormat::kPly);
  EXPECT_EQ(format_from_path("x.Off"), FileFormat::kOff);
  EXPECT_EQ(format_from_path("x.stl"), FileFormat::kStl);
  EXPECT_EQ(format_from_path("x.drc"), FileFormat::kDrc);
  EXPECT_THROW(format_from_path("x.xyz"), InvalidArgument);
  EXPECT_THROW(format_from_path("noext"), InvalidArgument);
  EXPECT_STREQ(format_name(FileFormat::kStl), "stl");
  using geom::test::bytes;
  EXPECT_EQ(sniff_format(bytes("ply\nformat ascii 1.0\n")), FileFormat::kPly);
  EXPECT_EQ(sniff_format(bytes("# hi\nv 1 2 3\n")), FileFormat::kObj);
  EXPECT_EQ(sniff_format(bytes("COFF\n")), FileFormat::kOff);
  EXPECT_EQ(sniff_format(bytes("OFF BINARY\n")), FileFormat::kOff);
  EXPECT_EQ(sniff_format(bytes("solid x\n")), FileFormat::kStl);
  EXPECT_EQ(sniff_format(bytes("DRACO\x02\x02")), FileFormat::kDrc);
  EXPECT_EQ(sniff_format(bytes("1 2 3\n")), std::nullopt);
  EXPECT_EQ(sniff_format(bytes("")), std::nullopt);
  const std::string bin = geom::test::write_string(geom::test::tetra(), FileFormat::kStl);
  EXPECT_EQ(sniff_format(bytes(bin)), FileFormat::kStl);
}

TEST(Formats, FilesAndStdinStdoutNeedFormats) {
  const auto dir = std::filesystem::temp_directory_path() / "geom_io_test_files";
  std::filesystem::create_directories(dir);
  const auto path = dir / "t.obj";
  write_soup(geom::test::tetra(), path);
  EXPECT_TRUE(geom::test::same_geometry(read_soup(path), geom::test::tetra()));
  // Unknown extension: sniffed.
  const auto odd = dir / "t.mesh";
  std::filesystem::copy_file(path, odd, std::filesystem::copy_options::overwrite_existing);
  EXPECT_EQ(read_soup(odd).n_faces(), 4u);
  EXPECT_THROW(read_soup("-"), InvalidArgument);
  EXPECT_THROW(write_soup(geom::test::tetra(), "-"), InvalidArgument);
  EXPECT_THROW(read_soup(dir / "missing.obj"), Error);
  EXPECT_THROW(write_soup(geom::test::tetra(), dir / "t.xyz"), InvalidArgument);
  std::filesystem::remove_all(dir);
}

TEST(Formats, LoadAndSaveMesh) {
  const auto dir = std::filesystem::temp_directory_path() / "geom_io_load_save";
  std::filesystem::create_directories(dir);
  write_soup(geom::test::tetra(), dir / "t.ply");
  LoadResult r = load_mesh(dir / "t.ply");
  EXPECT_EQ(r.mesh.n_vertices(), 4u);
  EXPECT_EQ(r.mesh.n_faces(), 4u);
  save_mesh(r.mesh, dir / "u.off");
  PolygonSoup back = read_soup(dir / "u.off");
  EXPECT_EQ(back.positions.size(), 4u);
  EXPECT_EQ(back.n_faces(), 4u);
  EXPECT_THROW(load_mesh(dir / "missing.ply"), Error);
  std::filesystem::remove_all(dir);
}
