// PLY reader and writer: the three encodings, every scalar type, attributes, skipped
// elements, float/double selection on writing.

#include "io_test_util.h"

#include <geom/io/io.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <cstring>

using namespace geom;
using geom::test::parse;
using geom::test::put;

namespace {

/// One triangle with every scalar type used somewhere, plus an edge element and a face
/// list property that must both be skipped.
std::string typed_ply(bool big) {
  std::string s = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\ncomment all the types\n"
                  "element vertex 3\n"
                  "property double x\nproperty float y\nproperty int16 z\n"
                  "property float32 nx\nproperty float ny\nproperty float nz\n"
                  "property uchar red\nproperty uint8 green\nproperty uchar blue\n"
                  "property float s\nproperty float t\n"
                  "property ushort quality\nproperty char flag\nproperty uint big\n"
                  "element face 1\n"
                  "property list uchar uint vertex_indices\n"
                  "property list int float texcoord\n"
                  "property int material\n"
                  "element edge 2\n"
                  "property list ushort int vertex_pair\n"
                  "property float64 w\n"
                  "end_header\n";
  for (int v = 0; v < 3; ++v) {
    put(s, 0.1 * v, big);
    put(s, static_cast<float>(v) + 0.5f, big);
    put(s, static_cast<std::int16_t>(-v), big);
    put(s, 0.0f, big);
    put(s, 0.0f, big);
    put(s, 1.0f, big);
    put(s, static_cast<std::uint8_t>(255), big);
    put(s, static_cast<std::uint8_t>(51 * v), big);
    put(s, static_cast<std::uint8_t>(0), big);
    put(s, 0.25f * v, big);
    put(s, 1.0f, big);
    put(s, static_cast<std::uint16_t>(1000 + v), big);
    put(s, static_cast<std::int8_t>(-1), big);
    put(s, static_cast<std::uint32_t>(4000000000u), big);
  }
  put(s, static_cast<std::uint8_t>(3), big);
  for (std::uint32_t i : {0u, 1u, 2u}) put(s, i, big);
  put(s, static_cast<std::int32_t>(6), big);
  for (int i = 0; i < 6; ++i) put(s, 0.5f, big);
  put(s, static_cast<std::int32_t>(7), big);
  for (int e = 0; e < 2; ++e) {
    put(s, static_cast<std::uint16_t>(2), big);
    put(s, static_cast<std::int32_t>(e), big);
    put(s, static_cast<std::int32_t>(e + 1), big);
    put(s, 3.0, big);
  }
  return s;
}

void check_typed(const PolygonSoup& s) {
  ASSERT_EQ(s.positions.size(), 3u);
  EXPECT_EQ(s.positions[1], Point(0.1, 1.5, -1));
  ASSERT_EQ(s.n_faces(), 1u);
  EXPECT_EQ(s.face(0)[2], 2u);
  ASSERT_EQ(s.vertex_normals.size(), 3u);
  EXPECT_EQ(s.vertex_normals[0], Normal(0, 0, 1));
  ASSERT_EQ(s.vertex_colors.size(), 3u);
  EXPECT_EQ(s.vertex_colors[1], Color(1, 51.0 / 255.0, 0));
  ASSERT_EQ(s.vertex_texcoords.size(), 3u);
  EXPECT_EQ(s.vertex_texcoords[2], TexCoord(0.5, 1));
  ASSERT_EQ(s.vertex_scalars.size(), 3u);
  EXPECT_EQ(s.vertex_scalars[0].name, "quality");
  EXPECT_EQ(s.vertex_scalars[0].values, (std::vector<double>{1000, 1001, 1002}));
  EXPECT_EQ(s.vertex_scalars[1].values[0], -1);
  EXPECT_EQ(s.vertex_scalars[2].values[0], 4000000000.0);
  ASSERT_EQ(s.face_scalars.size(), 1u);
  EXPECT_EQ(s.face_scalars[0].name, "material");
  EXPECT_EQ(s.face_scalars[0].values, std::vector<double>{7});
}

}  // namespace

TEST(Ply, BinaryLittleEndianAllTypes) { check_typed(parse(typed_ply(false), FileFormat::kPly)); }
TEST(Ply, BinaryBigEndianAllTypes) { check_typed(parse(typed_ply(true), FileFormat::kPly)); }

TEST(Ply, AsciiWithSkippedElementsAndVertexIndexName) {
  const char* text =
      "ply\r\nformat ascii 1.0\r\n"
      "element vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float confidence\n"
      "element material 1\nproperty list uchar float rgba\n"
      "element face 2\nproperty list uchar int vertex_index\n"
      "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
      "end_header\n"
      "0 0 0 0.5\n1 0 0 1\n1 1 0 1\n0 1 0.1 1\n"
      "4 0.1 0.2 0.3 1\n"
      "3 0 1 2\n3 0 2 3\n"
      "0 1\n";
  PolygonSoup s = parse(text, FileFormat::kPly);
  ASSERT_EQ(s.positions.size(), 4u);
  // Declared float: the value is the float nearest 0.1, not the double.
  EXPECT_EQ(s.positions[3].z(), static_cast<double>(0.1f));
  ASSERT_EQ(s.n_faces(), 2u);
  EXPECT_EQ(s.face(1)[2], 3u);
  ASSERT_EQ(s.vertex_scalars.size(), 1u);
  EXPECT_EQ(s.vertex_scalars[0].values[0], 0.5);
}

TEST(Ply, RoundTripBinaryAndAsciiBitExact) {
  for (bool binary : {true, false}) {
    for (const PolygonSoup& s0 : {geom::test::house(), geom::test::tetra()}) {
      PolygonSoup s = s0;
      const std::size_t nv = s.positions.size();
      s.vertex_normals.assign(nv, Normal(0.1, 0.2, 0.3));
      s.vertex_colors.assign(nv, Color(1, 0.2, 0));  // 0.2 = 51/255 exactly? not: float path
      s.vertex_texcoords.assign(nv, TexCoord(0.75, 1.0 / 3.0));
      s.vertex_scalars.push_back({"quality", std::vector<double>(nv, 0.125)});
      s.face_scalars.push_back({"label", std::vector<double>(s.n_faces(), 3)});
      WriteOptions o;
      o.binary = binary;
      const std::string bytes = geom::test::write_string(s, FileFormat::kPly, o);
      PolygonSoup r = parse(bytes, FileFormat::kPly);
      EXPECT_TRUE(geom::test::same_geometry(s, r)) << "binary=" << binary;
      EXPECT_TRUE(geom::test::same_vectors(s.vertex_normals, r.vertex_normals, "normals"));
      EXPECT_TRUE(geom::test::same_vectors(s.vertex_colors, r.vertex_colors, "colors"));
      EXPECT_TRUE(geom::test::same_vectors(s.vertex_texcoords, r.vertex_texcoords, "texcoords"));
      ASSERT_EQ(r.vertex_scalars.size(), 1u);
      EXPECT_EQ(r.vertex_scalars[0].values, s.vertex_scalars[0].values);
      ASSERT_EQ(r.face_scalars.size(), 1u);
      EXPECT_EQ(r.face_scalars[0].values, s.face_scalars[0].values);
    }
  }
}

TEST(Ply, WriterPicksFloatOnlyWhenExact) {
  const std::string f = geom::test::write_string(geom::test::tetra(), FileFormat::kPly);
  EXPECT_NE(f.find("property float x"), std::string::npos);
  const std::string d = geom::test::write_string(geom::test::house(), FileFormat::kPly);
  EXPECT_NE(d.find("property double x"), std::string::npos);
  PolygonSoup c = geom::test::tetra();
  c.vertex_colors.assign(4, Color(1, 51.0 / 255.0, 0));
  EXPECT_NE(geom::test::write_string(c, FileFormat::kPly).find("property uchar red"), std::string::npos);
}

TEST(Ply, LargeFacesUseAnIntCount) {
  PolygonSoup s;
  std::vector<std::uint32_t> ring;
  for (std::uint32_t i = 0; i < 300; ++i) {
    s.positions.emplace_back(std::cos(i * 0.02), std::sin(i * 0.02), 0);
    ring.push_back(i);
  }
  s.add_face(ring);
  PolygonSoup r = parse(geom::test::write_string(s, FileFormat::kPly), FileFormat::kPly);
  EXPECT_TRUE(geom::test::same_geometry(s, r));
}

TEST(Ply, ErrorsNameByteOffsetOrLine) {
  std::string good = geom::test::write_string(geom::test::tetra(), FileFormat::kPly);
  // Truncated binary body.
  try {
    parse(good.substr(0, good.size() - 3), FileFormat::kPly, "t.ply");
    ADD_FAILURE();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.unit(), ParseError::Unit::kByte);
    EXPECT_NE(std::string(e.what()).find("t.ply: byte"), std::string::npos) << e.what();
  }
  // A header claiming 10^12 vertices fails before allocating.
  std::string huge = good;
  huge.replace(huge.find("vertex 4"), 8, "vertex 1000000000000");
  EXPECT_THROW(parse(huge, FileFormat::kPly), ParseError);
  // Index out of range in ascii names the line.
  try {
    parse("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
          "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
          FileFormat::kPly, "a.ply");
    ADD_FAILURE();
  } catch (const ParseError& e) {
    EXPECT_EQ(e.unit(), ParseError::Unit::kLine);
    EXPECT_EQ(e.where(), 13u) << e.what();
  }
  EXPECT_THROW(parse("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n", FileFormat::kPly),
               ParseError);
  EXPECT_THROW(parse("ply\nformat binary_middle_endian 1.0\nend_header\n", FileFormat::kPly), ParseError);
  EXPECT_THROW(parse("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n", FileFormat::kPly), ParseError);
}

TEST(Ply, FloatExactnessAtTheEdgesOfTheFloatRange) {
  auto type_of = [](double v) {
    PolygonSoup s;
    s.positions = {{v, 0, 0}};
    const std::string text = geom::test::write_string(s, FileFormat::kPly);
    PolygonSoup r = parse(text, FileFormat::kPly);
    EXPECT_TRUE(geom::test::same_bits(r.positions[0].x(), v)) << v;
    return text.find("property float x") != std::string::npos ? "float" : "double";
  };
  EXPECT_STREQ(type_of(std::ldexp(1.0, -149)), "float");   // smallest float subnormal
  EXPECT_STREQ(type_of(std::ldexp(1.0, -150)), "double");
  EXPECT_STREQ(type_of(std::ldexp(3.0, -149)), "float");
  EXPECT_STREQ(type_of(std::ldexp(1.0, -126) * (1 + std::ldexp(1.0, -23))), "float");
  EXPECT_STREQ(type_of(std::ldexp(1.0, -126) * (1 + std::ldexp(1.0, -24))), "double");
  EXPECT_STREQ(type_of(static_cast<double>(std::numeric_limits<float>::max())), "float");
  EXPECT_STREQ(type_of(std::ldexp(1.0, 128)), "double");
  EXPECT_STREQ(type_of(0.1), "double");
  EXPECT_STREQ(type_of(-0.0), "float");
  EXPECT_STREQ(type_of(16777217.0), "double");
  EXPECT_STREQ(type_of(16777216.0), "float");
  // ascii: FLT_MAX prints as 3.4028235e+38, above FLT_MAX as a double; it must read back as
  // FLT_MAX because the property is declared float.
  for (double v : {static_cast<double>(std::numeric_limits<float>::max()),
                   -static_cast<double>(std::numeric_limits<float>::max()),
                   static_cast<double>(std::numeric_limits<float>::denorm_min())}) {
    PolygonSoup s;
    s.positions = {{v, 0, 0}};
    WriteOptions o;
    o.binary = false;
    PolygonSoup r = parse(geom::test::write_string(s, FileFormat::kPly, o), FileFormat::kPly);
    EXPECT_TRUE(geom::test::same_bits(r.positions[0].x(), v)) << v;
  }
}

// A file of no vertex and no face is not a mesh: read_soup refuses it naming the file, even
// when its header declares the zero counts, so an empty soup writes but does not read back.
TEST(Ply, EmptySoupsAreWrittenButRefusedOnReading) {
  for (FileFormat f : {FileFormat::kPly, FileFormat::kObj, FileFormat::kOff, FileFormat::kStl}) {
    for (bool binary : {true, false}) {
      WriteOptions o;
      o.binary = binary;
      try {
        parse(geom::test::write_string(PolygonSoup{}, f, o), f, "empty");
        ADD_FAILURE() << format_name(f);
      } catch (const ParseError& e) {
        EXPECT_NE(std::string(e.what()).find("empty: no geometry"), std::string::npos) << e.what();
      }
    }
  }
}

namespace {

/// Eight vertices, then a tristrips element (before the face element, so that the order of
/// the result is not the file's) of two records, then one face 0 1 7. The strips, in the
/// Stanford scans' form: "0 1 2 3 3 4 4 5 6 -1 6 5 1 7" (stitching degenerates and a restart)
/// and "3 2 1 <last>" (a record starts a new strip).
std::string tristrips_ply(const std::string& format, std::int32_t last = 0) {
  const std::vector<std::int32_t> strips[2] = {{0, 1, 2, 3, 3, 4, 4, 5, 6, -1, 6, 5, 1, 7},
                                               {3, 2, 1, last}};
  const bool ascii = format == "ascii", big = format == "binary_big_endian";
  std::string s = "ply\nformat " + format + " 1.0\nelement vertex 8\n"
                  "property float x\nproperty float y\nproperty float z\n"
                  "element tristrips 2\nproperty list int int vertex_indices\n"
                  "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  for (int v = 0; v < 8; ++v) {
    if (ascii) s += std::to_string(v) + " " + std::to_string(v % 3) + " 0\n";
    for (float c : {static_cast<float>(v), static_cast<float>(v % 3), 0.0f})
      if (!ascii) put(s, c, big);
  }
  for (const auto& strip : strips) {
    if (ascii) s += std::to_string(strip.size());
    else put(s, static_cast<std::int32_t>(strip.size()), big);
    for (std::int32_t i : strip) {
      if (ascii) s += " " + std::to_string(i);
      else put(s, i, big);
    }
    if (ascii) s += "\n";
  }
  if (ascii) return s + "3 0 1 7\n";
  put(s, std::uint8_t{3}, big);
  for (std::int32_t i : {0, 1, 7}) put(s, i, big);
  return s;
}

constexpr const char* kPlyFormats[] = {"ascii", "binary_little_endian", "binary_big_endian"};

}  // namespace

TEST(Ply, TristripsAreTrianglesAfterTheFaces) {
  // Odd triangles of a strip are turned (b, a, c) so that all face one way, the count going
  // on across the dropped stitches; -1 and a new record both restart.
  const std::vector<std::vector<std::uint32_t>> want = {{0, 1, 7}, {0, 1, 2}, {2, 1, 3}, {4, 5, 6},
                                                        {6, 5, 1}, {1, 5, 7}, {3, 2, 1}, {1, 2, 0}};
  for (const char* format : kPlyFormats) {
    SCOPED_TRACE(format);
    const PolygonSoup s = parse(tristrips_ply(format), FileFormat::kPly);
    EXPECT_EQ(s.positions.size(), 8u);
    EXPECT_EQ(s.positions[7], Point(7, 1, 0));
    ASSERT_EQ(s.n_faces(), want.size());
    for (std::size_t f = 0; f < want.size(); ++f)
      EXPECT_EQ(std::vector<std::uint32_t>(s.face(f).begin(), s.face(f).end()), want[f])
          << "face " << f;
  }
}

TEST(Ply, TristripIndexOutOfRangeNamesTheElementAndRecord) {
  for (const char* format : kPlyFormats) {
    SCOPED_TRACE(format);
    const std::string text = tristrips_ply(format, 8);
    try {
      parse(text, FileFormat::kPly, "s.ply");
      ADD_FAILURE();
    } catch (const ParseError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("element 'tristrips' record 1: vertex index 8 out of range (8 vertices"),
                std::string::npos)
          << msg;
      // ascii: the second record's line; binary: the bad value, before the 13-byte face record.
      EXPECT_EQ(e.where(), std::string(format) == "ascii" ? 21u : text.size() - 13 - 4) << msg;
    }
  }
  EXPECT_THROW(parse(tristrips_ply("ascii", -2), FileFormat::kPly), ParseError);
}

// Old Mac exporters end lines in a bare '\r'; the first line says which line end the header
// uses, so a binary body starts right after end_header's even when its first byte is 0x0A.
TEST(Ply, HeaderLinesMayEndInCrOrCrlf) {
  const float x0 = std::bit_cast<float>(std::uint32_t{0x3f80000a});  // little-endian: 0a 00 80 3f
  for (const std::string eol : {"\n", "\r\n", "\r"}) {
    SCOPED_TRACE(eol == "\r" ? "CR" : eol == "\n" ? "LF" : "CRLF");
    auto header = [&eol](const std::string& format) {
      const std::string lines = "ply\nformat " + format +
                                " 1.0\ncomment Mac\nelement vertex 3\nproperty float x\n"
                                "property float y\nproperty float z\nelement face 1\n"
                                "property list uchar int vertex_indices\nend_header\n";
      std::string h;
      for (char c : lines) h += c == '\n' ? eol : std::string(1, c);
      return h;
    };
    std::string binary = header("binary_little_endian");
    const std::size_t body = binary.size();
    for (float c : {x0, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f}) put(binary, c, false);
    put(binary, std::uint8_t{3}, false);
    for (std::int32_t i : {0, 1, 2}) put(binary, i, false);
    ASSERT_EQ(binary[body], '\x0a');
    const PolygonSoup b = parse(binary, FileFormat::kPly);
    ASSERT_EQ(b.positions.size(), 3u);
    EXPECT_EQ(b.positions[0].x(), x0);
    EXPECT_EQ(b.n_faces(), 1u);

    const std::string vertices = "0 0 0" + eol + "1 0 0" + eol + "0 1 0" + eol;
    const PolygonSoup a = parse(header("ascii") + vertices + "3 0 1 2" + eol, FileFormat::kPly);
    EXPECT_EQ(a.positions.size(), 3u);
    EXPECT_EQ(a.n_faces(), 1u);
    EXPECT_EQ(sniff_format(geom::test::bytes(binary)), FileFormat::kPly);
    // Errors count lines at any of the three line ends: the face is line 14.
    try {
      parse(header("ascii") + vertices + "3 0 1 3" + eol, FileFormat::kPly);
      ADD_FAILURE();
    } catch (const ParseError& e) {
      EXPECT_EQ(e.where(), 14u) << e.what();
    }
  }
}
