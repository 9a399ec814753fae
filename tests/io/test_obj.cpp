// OBJ reader and writer: record forms, relative indices, tags, attributes, round trips.

#include "io_test_util.h"

#include <geom/io/io.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace geom;
using geom::test::parse;

TEST(Obj, ReadsAllCornerFormsAndPolygons) {
  const char* text =
      "# comment\n"
      "mtllib x.mtl\n"
      "o thing\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
      "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
      "vn 0 0 1\n"
      "g group1\nusemtl red\ns 1\n"
      "f 1 2 3 4\n"
      "f 1/1 2/2 3/3\n"
      "f 1//1 3//1 4//1\n"
      "f 1/1/1 3/3/1 4/4/1   # trailing comment\n"
      "s off\n"
      "l 1 2\n";
  PolygonSoup s = parse(text, FileFormat::kObj);
  ASSERT_EQ(s.positions.size(), 4u);
  ASSERT_EQ(s.n_faces(), 4u);
  EXPECT_EQ(s.face(0).size(), 4u);
  EXPECT_EQ(s.face(3)[2], 3u);
  ASSERT_EQ(s.corner_texcoords.size(), 13u);
  ASSERT_EQ(s.corner_normals.size(), 13u);
  // Corners without a vt get (0, 0); the second face's third corner has vt 3 = (1, 1).
  EXPECT_EQ(s.corner_texcoords[6], TexCoord(1, 1));
  EXPECT_EQ(s.corner_texcoords[0], TexCoord(0, 0));
  // Not every corner has a vt, so no per-vertex texcoords are derived.
  EXPECT_TRUE(s.vertex_texcoords.empty());
}

TEST(Obj, RelativeIndicesResolveAgainstRecordsSoFar) {
  PolygonSoup s = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf -4 -3 -1\n", FileFormat::kObj);
  ASSERT_EQ(s.n_faces(), 2u);
  EXPECT_EQ(std::vector<std::uint32_t>(s.face(0).begin(), s.face(0).end()), (std::vector<std::uint32_t>{0, 1, 2}));
  EXPECT_EQ(std::vector<std::uint32_t>(s.face(1).begin(), s.face(1).end()), (std::vector<std::uint32_t>{0, 1, 3}));
}

TEST(Obj, LineContinuationJoinsLines) {
  PolygonSoup s = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\nf 1 2 \\\n 3 \\\r\n 4\nv 2 2 2\n", FileFormat::kObj);
  ASSERT_EQ(s.n_faces(), 1u);
  EXPECT_EQ(s.face(0).size(), 4u);
  EXPECT_EQ(s.positions.size(), 5u);
}

TEST(Obj, ConsistentCornerAttributesAlsoGivePerVertexValues) {
  PolygonSoup s = parse(
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.25\nvt 1 0\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\n", FileFormat::kObj);
  ASSERT_EQ(s.vertex_texcoords.size(), 3u);
  EXPECT_EQ(s.vertex_texcoords[0], TexCoord(0.5, 0.25));
  ASSERT_EQ(s.vertex_normals.size(), 3u);
  EXPECT_EQ(s.vertex_normals[2], Normal(0, 0, 1));
}

TEST(Obj, SeamCornersKeepPerCornerValuesOnly) {
  PolygonSoup s = parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 9 9\n"
                        "f 1/1 2/2 3/3\nf 2/4 4/2 3/3\n",
                        FileFormat::kObj);
  EXPECT_EQ(s.corner_texcoords.size(), 6u);
  EXPECT_TRUE(s.vertex_texcoords.empty());
}

TEST(Obj, VertexColoursExtension) {
  PolygonSoup s = parse("v 0 0 0 1 0 0\nv 1 0 0\nv 0 1 0 0 0.5 1\nf 1 2 3\n", FileFormat::kObj);
  ASSERT_EQ(s.vertex_colors.size(), 3u);
  EXPECT_EQ(s.vertex_colors[0], Color(1, 0, 0));
  EXPECT_EQ(s.vertex_colors[1], Color(0, 0, 0));
  EXPECT_EQ(s.vertex_colors[2], Color(0, 0.5, 1));
}

TEST(Obj, OpenSubdivTags) {
  PolygonSoup s = parse("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"
                        "t crease 2/1/0 0 1 6.5\n"
                        "t crease 3/1/0 1 2 3 2.0\n"
                        "t corner 1/1/0  2  10.0\n"
                        "t interpolateboundary 1/0/0 2\n"
                        "t hole 1/0/0 0\n"
                        "t smoothtriangles 0/0/1 catmark\n",
                        FileFormat::kObj);
  ASSERT_EQ(s.creases.size(), 3u);
  EXPECT_EQ(s.creases[0].a, 0u);
  EXPECT_EQ(s.creases[0].b, 1u);
  EXPECT_EQ(s.creases[0].sharpness, 6.5);
  EXPECT_EQ(s.creases[2].a, 2u);
  EXPECT_EQ(s.creases[2].b, 3u);
  ASSERT_EQ(s.corners.size(), 1u);
  EXPECT_EQ(s.corners[0].v, 2u);
  EXPECT_EQ(s.corners[0].sharpness, 10.0);
  EXPECT_EQ(s.boundary_interpolation, 2);
}

TEST(Obj, EmptySlotsInCornersAreNoReference) {
  // Exporters write "1//" and "1/" for a corner with neither vt nor vn.
  for (const char* face : {"f 1// 2// 3//\n", "f 1/ 2/ 3/\n", "f 1//\t2/ 3 # mixed\n"}) {
    PolygonSoup s = parse(std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\n") + face, FileFormat::kObj);
    ASSERT_EQ(s.n_faces(), 1u) << face;
    EXPECT_EQ(s.face(0)[2], 2u) << face;
    EXPECT_TRUE(s.corner_texcoords.empty()) << face;
    EXPECT_TRUE(s.corner_normals.empty()) << face;
  }
  // "v/vt/" keeps its vt.
  PolygonSoup s =
      parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.25\nf 1/1/ 2/1/ 3/1/\n", FileFormat::kObj);
  ASSERT_EQ(s.corner_texcoords.size(), 3u);
  EXPECT_EQ(s.corner_texcoords[1], TexCoord(0.5, 0.25));
  EXPECT_TRUE(s.corner_normals.empty());
}

TEST(Obj, FileWithoutGeometryIsAnErrorNamingIt) {
  for (const char* text :
       {"", "# nothing\n\n   \n", "mtllib scene.mtl\no empty\ng group\nusemtl red\n"}) {
    try {
      parse(text, FileFormat::kObj, "notes.obj");
      ADD_FAILURE() << "no error for: " << text;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find("notes.obj: no geometry"), std::string::npos)
          << e.what();
    }
  }
  // Read by path, as geom info, convert and batch read it.
  const auto dir = std::filesystem::temp_directory_path() / "geom_obj_no_geometry";
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "notes.obj") << "# only a comment\n";
  EXPECT_THROW(read_soup(dir / "notes.obj"), ParseError);
  std::filesystem::remove_all(dir);
}

TEST(Obj, CrlfAndTabs) {
  PolygonSoup s = parse("v\t0\t0\t0\r\nv 1 0 0\r\nv 0 1 0\r\nf\t1 2\t3\r\n", FileFormat::kObj);
  EXPECT_EQ(s.positions.size(), 3u);
  EXPECT_EQ(s.n_faces(), 1u);
}

TEST(Obj, ErrorsNameTheLine) {
  struct Case {
    const char* text;
    const char* needle;
  };
  for (const Case& c : {Case{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", "test:4"},
                        Case{"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n", "test:4"},
                        Case{"v 0 0 0\nv 1 x 0\n", "test:2"},
                        Case{"v 0 0 nan\n", "test:1"},
                        Case{"v 0 0 inf\n", "test:1"},
                        Case{"v 0 0 0\nf -2 1 1\n", "test:2"},
                        Case{"v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1/5 2 3\n", "test:4"},
                        Case{"v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3x\n", "test:4"},
                        Case{"v 0 0\n", "test:1"},
                        Case{"v 0 0 0\nt crease 2/1/0 0 7 1.0\n", "test:2"},
                        Case{"v 0 0 0\nt crease x/y/z\n", "test:2"},
                        Case{"f\n", "test:1"}}) {
    try {
      parse(c.text, FileFormat::kObj);
      ADD_FAILURE() << "no error for: " << c.text;
    } catch (const ParseError& e) {
      EXPECT_NE(std::string(e.what()).find(c.needle), std::string::npos) << e.what();
      EXPECT_EQ(e.unit(), ParseError::Unit::kLine);
    }
  }
}

TEST(Obj, RoundTripIsBitExact) {
  PolygonSoup s = geom::test::house();
  s.creases = {{0, 1, 2.5}, {1, 2, 10}};
  s.corners = {{4, 3.25}};
  s.boundary_interpolation = 1;
  const std::string text = geom::test::write_string(s, FileFormat::kObj);
  PolygonSoup r = parse(text, FileFormat::kObj);
  EXPECT_TRUE(geom::test::same_geometry(s, r));
  ASSERT_EQ(r.creases.size(), 2u);
  EXPECT_EQ(r.creases[1].sharpness, 10);
  ASSERT_EQ(r.corners.size(), 1u);
  EXPECT_EQ(r.corners[0].sharpness, 3.25);
  EXPECT_EQ(r.boundary_interpolation, 1);
}

TEST(Obj, RoundTripKeepsCornerAndVertexAttributes) {
  PolygonSoup s = geom::test::house();
  s.vertex_colors.assign(5, Color(0.25, 0.5, 1.0 / 3.0));
  for (std::size_t c = 0; c < s.face_indices.size(); ++c) {
    s.corner_texcoords.emplace_back(0.1 * static_cast<double>(c), 0.5);
    s.corner_normals.emplace_back(0, 0, c % 2 ? 1.0 : -1.0);
  }
  PolygonSoup r = parse(geom::test::write_string(s, FileFormat::kObj), FileFormat::kObj);
  EXPECT_TRUE(geom::test::same_geometry(s, r));
  EXPECT_TRUE(geom::test::same_vectors(s.corner_texcoords, r.corner_texcoords, "corner_texcoords"));
  EXPECT_TRUE(geom::test::same_vectors(s.corner_normals, r.corner_normals, "corner_normals"));
  EXPECT_TRUE(geom::test::same_vectors(s.vertex_colors, r.vertex_colors, "vertex_colors"));

  PolygonSoup v = geom::test::tetra();
  v.vertex_texcoords = {{0, 0}, {1, 0}, {0, 1}, {0.5, 0.5}};
  v.vertex_normals = {{0, 0, -1}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  PolygonSoup w = parse(geom::test::write_string(v, FileFormat::kObj), FileFormat::kObj);
  EXPECT_TRUE(geom::test::same_vectors(v.vertex_texcoords, w.vertex_texcoords, "vertex_texcoords"));
  EXPECT_TRUE(geom::test::same_vectors(v.vertex_normals, w.vertex_normals, "vertex_normals"));
}

TEST(Obj, WriterRejectsInconsistentSoup) {
  PolygonSoup s = geom::test::tetra();
  s.face_indices[0] = 99;
  EXPECT_THROW(geom::test::write_string(s, FileFormat::kObj), InvalidArgument);
  PolygonSoup t = geom::test::tetra();
  t.vertex_normals.resize(2);
  EXPECT_THROW(geom::test::write_string(t, FileFormat::kObj), InvalidArgument);
}

namespace {

/// A large OBJ (over 8 MB, so the reader splits it into pieces parsed in parallel) whose
/// faces use relative indices, plus its expected soup.
std::string big_relative_obj(PolygonSoup& expected, std::size_t& bad_line) {
  std::string text;
  std::size_t line = 0;
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const Point p(i * 0.5, -i * 0.25, (i % 7) * 0.125);
    expected.positions.push_back(p);
    text += "v " + std::to_string(p.x()) + " " + std::to_string(p.y()) + " " + std::to_string(p.z()) + "\n";
    ++line;
    text += "vt 0.5 0.25\n";
    ++line;
    if (i >= 2) {
      // relative: the previous three vertices; every 1000th face continued over two lines
      if (i % 1000 == 0) {
        text += "f -3/-1 -2/-1 \\\n -1/-1\n";
        line += 2;
      } else {
        text += "f -3/-1 -2/-1 -1/-1\n";
        ++line;
      }
      expected.add_face({static_cast<std::uint32_t>(i - 2), static_cast<std::uint32_t>(i - 1),
                         static_cast<std::uint32_t>(i)});
    }
    text += "# padding comment to make the file large enough for several pieces\n";
    ++line;
  }
  bad_line = line + 2;
  return text;
}

}  // namespace

TEST(Obj, LargeFilesParsedInPiecesMatchTheSequentialMeaning) {
  PolygonSoup expected;
  std::size_t bad_line = 0;
  std::string text = big_relative_obj(expected, bad_line);
  ASSERT_GT(text.size(), 9u << 20);
  PolygonSoup s = parse(text, FileFormat::kObj);
  ASSERT_EQ(s.positions.size(), expected.positions.size());
  EXPECT_EQ(s.face_offsets, expected.face_offsets);
  ASSERT_EQ(s.face_indices.size(), expected.face_indices.size());
  for (std::size_t c = 0; c < s.face_indices.size(); ++c)
    ASSERT_EQ(s.face_indices[c], expected.face_indices[c]) << "corner " << c;
  ASSERT_EQ(s.corner_texcoords.size(), s.face_indices.size());
  EXPECT_EQ(s.corner_texcoords.back(), TexCoord(0.5, 0.25));
  // An error at the very end names its line in the whole file.
  text += "v 1 2 3\nv 1 oops 3\n";
  try {
    parse(text, FileFormat::kObj);
    ADD_FAILURE();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.where(), bad_line) << e.what();
  }
  // A relative index reaching before the file start, far into the file.
  std::string before = "v 0 0 0\n" + std::string(9u << 20, '#') + "\nf -1 -2 -3\n";
  try {
    parse(before, FileFormat::kObj);
    ADD_FAILURE();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.where(), 3u) << e.what();
  }
}
