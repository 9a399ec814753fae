// unstored(): what each format leaves out of a soup is named, with counts, and nothing is
// named that the file keeps.

#include <geom/io/io.h>

#include <gtest/gtest.h>

namespace geom {
namespace {

/// A quad and a pentagon beside a triangle, an unused vertex, and every kind of attribute:
/// UVs with a seam (vertex 0's corners disagree), colours, a vertex and a face scalar, a crease.
PolygonSoup everything() {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}, {3, 0, 0}, {9, 9, 9}};
  s.add_face({0, 1, 2, 3});
  s.add_face({1, 4, 6, 5, 2});
  s.add_face({0, 3, 1});
  s.corner_texcoords.assign(s.face_indices.size(), TexCoord(0, 0));
  s.corner_texcoords[9] = TexCoord(1, 1);
  s.vertex_colors.assign(8, Color(1, 0, 0));
  s.vertex_scalars.push_back({"quality", std::vector<double>(8, 1.0)});
  s.face_scalars.push_back({"material", {0, 1, 2}});
  s.creases.push_back({0, 1, 2.0});
  return s;
}

TEST(Unstored, ObjLosesOnlyScalars) {
  EXPECT_EQ(unstored(everything(), FileFormat::kObj),
            (std::vector<std::string>{"vertex properties 'quality' are not stored (obj has no place for them)",
                                      "face properties 'material' are not stored (obj has no place for them)"}));
}

TEST(Unstored, PlyLosesSeamsAndTags) {
  EXPECT_EQ(unstored(everything(), FileFormat::kPly),
            (std::vector<std::string>{
                "texture coordinates per face corner (UV seams) are not stored (ply keeps one per vertex)",
                "subdivision tags (1 crease, 0 corners) are not stored (ply has no place for them)"}));
}

TEST(Unstored, StlKeepsPositionsOnly) {
  EXPECT_EQ(unstored(everything(), FileFormat::kStl),
            (std::vector<std::string>{
                "1 vertex that no face uses is not stored (stl keeps only vertices of triangles)",
                "2 polygons of more than 3 corners are split into 5 triangles (stl holds triangles only)",
                "colours are not stored (stl has no place for them)",
                "texture coordinates are not stored (stl has no place for them)",
                "vertex properties 'quality' are not stored (stl has no place for them)",
                "face properties 'material' are not stored (stl has no place for them)",
                "subdivision tags (1 crease, 0 corners) are not stored (stl has no place for them)"}));
}

TEST(Unstored, GltfSplitsPolygonsButKeepsSeamsAndColours) {
  const auto lines = unstored(everything(), FileFormat::kGlb);
  ASSERT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines[0], "2 polygons of more than 3 corners are split into 5 triangles (glb holds triangles only)");
}

TEST(Unstored, GltfNamesZeroNormalsAndClampedColours) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.add_face({0, 1, 2});
  s.vertex_normals = {{0, 0, 1}, {0, 0, 0}, {0, 0, 2}};
  s.vertex_colors = {{1, 0, 0}, {1.5, 0, 0}, {0, -0.1, 0}};
  EXPECT_EQ(unstored(s, FileFormat::kGlb),
            (std::vector<std::string>{"normals are not stored: 1 is zero or not finite (glTF needs unit normals)",
                                      "2 colours outside [0, 1] are clamped (glTF's range)"}));
}

TEST(Unstored, NothingIsNamedWhenTheFileKeepsEverythingOrAttributesWereTurnedOff) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.add_face({0, 1, 2});
  s.vertex_normals.assign(3, Normal(0, 0, 1));
  for (FileFormat f : {FileFormat::kObj, FileFormat::kPly, FileFormat::kOff, FileFormat::kDrc, FileFormat::kGlb})
    EXPECT_TRUE(unstored(s, f).empty()) << format_name(f);
  EXPECT_EQ(unstored(s, FileFormat::kStl).size(), 1u);
  WriteOptions no_attributes;
  no_attributes.attributes = false;
  EXPECT_TRUE(unstored(s, FileFormat::kStl, no_attributes).empty());
}

}  // namespace
}  // namespace geom
