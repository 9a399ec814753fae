// OBJ's named face sets ("o", "g", "usemtl") and material files ("mtllib"): read, written back
// where they were, carried through a built mesh, and named as lost by formats without them.

#include "io_test_util.h"

#include <geom/core/build.h>
#include <geom/io/gltf.h>
#include <geom/io/io.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <span>
#include <string>
#include <vector>

using namespace geom;
using geom::test::parse;

namespace {

constexpr std::uint32_t kNo = FaceNames::kUnnamed;

/// The name of each face ("" for none).
std::vector<std::string> per_face(const FaceNames& n, std::size_t faces) {
  std::vector<std::string> out(faces);
  for (std::size_t f = 0; f < n.of_face.size(); ++f)
    if (n.of_face[f] != kNo) out[f] = n.names[n.of_face[f]];
  return out;
}

const char* kNamed =
    "mtllib shop.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
    "f 1 2 3\n"                        // before any name
    "o chair\ng seat  back\nusemtl oak\n"
    "f 1 3 4\n"
    "f 1 2 4\n"
    "g\nusemtl steel\n"                // a bare g: no group from here
    "f 2 3 4\n"
    "mtllib extra.mtl\n"
    "g legs\n"
    "f 4 3 2 1\n";

}  // namespace

TEST(ObjNames, ReadAsGivenWithFacesBeforeAnyNameUnnamed) {
  const PolygonSoup s = parse(kNamed, FileFormat::kObj);
  ASSERT_EQ(s.n_faces(), 5u);
  EXPECT_EQ(per_face(s.face_objects, 5), (std::vector<std::string>{"", "chair", "chair", "chair", "chair"}));
  EXPECT_EQ(per_face(s.face_groups, 5), (std::vector<std::string>{"", "seat back", "seat back", "", "legs"}));
  EXPECT_EQ(per_face(s.face_materials, 5), (std::vector<std::string>{"", "oak", "oak", "steel", "steel"}));
  EXPECT_EQ(s.material_libraries, (std::vector<std::string>{"shop.mtl", "extra.mtl"}));
  // A file without names has none.
  EXPECT_TRUE(parse("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", FileFormat::kObj).face_groups.empty());
}

TEST(ObjNames, WrittenWhereTheyChangeAndReadBackTheSame) {
  const PolygonSoup s = parse(kNamed, FileFormat::kObj);
  const std::string text = geom::test::write_string(s, FileFormat::kObj);
  EXPECT_NE(text.find("mtllib shop.mtl\nmtllib extra.mtl\n"), std::string::npos) << text;
  EXPECT_NE(text.find("o chair\ng seat back\nusemtl oak\nf 1 3 4\nf 1 2 4\ng\nusemtl steel\n"), std::string::npos)
      << text;
  const PolygonSoup back = parse(text, FileFormat::kObj);
  for (auto [a, b] : {std::pair{&s.face_objects, &back.face_objects}, std::pair{&s.face_groups, &back.face_groups},
                      std::pair{&s.face_materials, &back.face_materials}})
    EXPECT_EQ(per_face(*a, 5), per_face(*b, 5));
  EXPECT_EQ(back.material_libraries, s.material_libraries);
}

TEST(ObjNames, CarriedThroughABuiltMesh) {
  const PolygonSoup s = parse(kNamed, FileFormat::kObj);
  const BuildResult built = build(s);
  ASSERT_EQ(built.mesh.n_faces(), 5u);
  const PolygonSoup back = to_soup(built.mesh);
  EXPECT_EQ(per_face(back.face_groups, 5), per_face(s.face_groups, 5));
  EXPECT_EQ(per_face(back.face_materials, 5), per_face(s.face_materials, 5));
  EXPECT_EQ(per_face(back.face_objects, 5), per_face(s.face_objects, 5));
  // A dropped face takes its name with it; the others keep theirs.
  PolygonSoup degenerate = s;
  degenerate.face_indices[0] = degenerate.face_indices[1];  // face 0 repeats a vertex
  const PolygonSoup kept = to_soup(build(degenerate).mesh);
  ASSERT_EQ(kept.n_faces(), 4u);
  EXPECT_EQ(per_face(kept.face_materials, 4), (std::vector<std::string>{"oak", "oak", "steel", "steel"}));
}

TEST(ObjNames, FormatsWithoutThemSaySo) {
  const PolygonSoup s = parse(kNamed, FileFormat::kObj);
  EXPECT_TRUE(unstored(s, FileFormat::kObj).empty());
  const std::vector<std::string> ply = unstored(s, FileFormat::kPly);
  auto said = [&](const std::string& line) { return std::find(ply.begin(), ply.end(), line) != ply.end(); };
  EXPECT_TRUE(said("face names (1 object, 2 groups, 2 materials) are not stored (ply has no place for them)"))
      << ::testing::PrintToString(ply);
  EXPECT_TRUE(said("material libraries (mtllib shop.mtl, extra.mtl) are not stored (ply has no place for them)"))
      << ::testing::PrintToString(ply);
}

TEST(ObjNames, BadSoupNamesAreRefused) {
  PolygonSoup s = parse(kNamed, FileFormat::kObj);
  s.face_groups.of_face[2] = 7;  // only 2 names
  EXPECT_THROW(check_soup(s), InvalidArgument);
  s.face_groups.of_face.pop_back();
  EXPECT_THROW(check_soup(s), InvalidArgument);
}

TEST(ObjNames, LargeFilesReadInPiecesKeepTheNameCurrentAtEachPieceStart) {
  // Over 8 MB so that the reader splits it; names change rarely, so most pieces start in
  // the middle of a named run and must inherit it from the piece before.
  std::string text = "mtllib big.mtl\n";
  const int n = 120000;
  for (int i = 0; i < n + 2; ++i) text += "v " + std::to_string(i) + " " + std::to_string(i % 3) + " 0\n";
  std::vector<std::string> groups, materials;
  for (int i = 0; i < n; ++i) {
    if (i % 40000 == 10) text += "g part" + std::to_string(i / 40000) + "\n";
    if (i == 5) text += "usemtl only\n";
    text += "f " + std::to_string(i + 1) + " " + std::to_string(i + 2) + " " + std::to_string(i + 3) +
            "  # a comment to make the file larger than the reader's piece size\n";
    groups.push_back(i < 10 ? "" : "part" + std::to_string((i - 10) / 40000));
    materials.push_back(i < 5 ? "" : "only");
  }
  ASSERT_GT(text.size(), 9u << 20);
  const PolygonSoup s = parse(text, FileFormat::kObj);
  ASSERT_EQ(s.n_faces(), static_cast<std::size_t>(n));
  EXPECT_EQ(per_face(s.face_groups, n), groups);
  EXPECT_EQ(per_face(s.face_materials, n), materials);
  EXPECT_EQ(s.face_materials.names.size(), 1u);
  EXPECT_EQ(s.material_libraries, std::vector<std::string>{"big.mtl"});
}

namespace geom {
namespace {

TEST(ObjNames, GltfKeepsMaterialNamesAsPrimitives) {
  const PolygonSoup s = parse(kNamed, FileFormat::kObj);
  const std::vector<std::string> glb = unstored(s, FileFormat::kGlb);
  EXPECT_NE(std::find(glb.begin(), glb.end(),
                      "face names (1 object, 2 groups) are not stored (glb has no place for them)"),
            glb.end())
      << ::testing::PrintToString(glb);
  const std::string data = write_gltf(gltf_from_soup(s), true);
  const PolygonSoup back =
      flatten(read_gltf(std::as_bytes(std::span(data.data(), data.size())), "x.glb"));
  ASSERT_EQ(back.n_faces(), 6u);  // the quad is two triangles
  EXPECT_EQ(per_face(back.face_materials, 6),
            (std::vector<std::string>{"", "oak", "oak", "steel", "steel", "steel"}));
}

}  // namespace
}  // namespace geom
