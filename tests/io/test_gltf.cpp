// glTF 2.0: round trips, hierarchy, MSFT_lod chains, and clear errors on bad files.

#include <geom/core/errors.h>
#include <geom/io/gltf.h>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstring>

namespace geom {
namespace {

std::span<const std::byte> bytes(const std::string& s) {
  return {reinterpret_cast<const std::byte*>(s.data()), s.size()};
}

PolygonSoup quad_and_triangle() {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 2, 0.25}};
  s.add_face({0, 1, 2, 3});
  s.add_face({3, 2, 4});
  s.vertex_normals.assign(5, Normal(0, 0, 1));
  s.vertex_texcoords = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 1.5}};
  return s;
}

std::uint32_t le32(const std::string& s, std::size_t at) {
  std::uint32_t v;
  std::memcpy(&v, s.data() + at, 4);
  return v;
}

std::string error_of(const std::string& data) {
  try {
    read_gltf(bytes(data), "bad.gltf");
  } catch (const ParseError& e) {
    return e.what();
  }
  return "";
}

TEST(Gltf, GlbAndJsonRoundTripTriangulatedWithAttributes) {
  for (bool binary : {true, false}) {
    std::string data = write_gltf(gltf_from_soup(quad_and_triangle()), binary);
    EXPECT_EQ(data.substr(0, 4) == "glTF", binary);
    GltfDocument doc = read_gltf(bytes(data), "x");
    ASSERT_EQ(doc.meshes.size(), 1u);
    const PolygonSoup& s = doc.meshes[0];
    EXPECT_EQ(s.positions.size(), 5u);
    EXPECT_EQ(s.n_faces(), 3u);  // the quad became two triangles
    EXPECT_EQ(s.positions[4], Point(0.5, 2, 0.25));
    ASSERT_EQ(s.vertex_normals.size(), 5u);
    ASSERT_EQ(s.vertex_texcoords.size(), 5u);
    EXPECT_EQ(s.vertex_texcoords[4], TexCoord(0.5, 1.5));
    EXPECT_EQ(doc.roots, std::vector<int>{0});
  }
}

// Without corner attributes the vertex list goes out as it is: a round trip keeps vertex
// numbers (morph targets and draw ranges depend on them) and the vertices no face uses.
TEST(Gltf, VertexOrderAndUnusedVerticesSurviveARoundTrip) {
  PolygonSoup s;
  s.positions = {{9, 9, 9}, {0, 1, 0}, {1, 0, 0}, {0, 0, 0}, {0.5, 0.5, 1}};
  s.add_face({3, 2, 1});
  s.add_face({2, 4, 1});
  for (bool binary : {true, false}) {
    const PolygonSoup back = flatten(read_gltf(bytes(write_gltf(gltf_from_soup(s), binary)), "x"));
    EXPECT_EQ(back.positions, s.positions);
    EXPECT_EQ(back.face_indices, s.face_indices);
  }
}

TEST(Gltf, CornerTexcoordsSplitVerticesAtSeams) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  s.add_face({0, 1, 2});
  s.add_face({0, 2, 3});
  // Vertex 0 and 2 carry different uvs in the two faces: a seam along the diagonal.
  s.corner_texcoords = {{0, 0}, {1, 0}, {1, 1}, {0.5, 0}, {1, 1}, {0, 1}};
  // The file holds vertex 0 twice (split at the seam); reading welds it into one vertex
  // whose two texture coordinates are corner values again.
  const std::string glb = write_gltf(gltf_from_soup(s), true);
  EXPECT_EQ(nlohmann::json::parse(glb.substr(20, le32(glb, 12)))["accessors"][0]["count"], 5);
  PolygonSoup back = read_gltf(bytes(glb), "x").meshes[0];
  EXPECT_EQ(back.positions, s.positions);
  EXPECT_EQ(back.face_indices, s.face_indices);
  EXPECT_EQ(back.corner_texcoords, s.corner_texcoords);
  // Flattening a document keeps per-corner values (it used to keep per-vertex ones only),
  // mirrored instances reversing them with their faces.
  GltfDocument doc = gltf_from_soup(s);
  EXPECT_EQ(flatten(doc).corner_texcoords, s.corner_texcoords);
  doc.nodes[0].matrix.diagonal() << -1, 1, 1, 1;
  const PolygonSoup mirrored = flatten(doc);
  EXPECT_EQ(mirrored.face_indices, (std::vector<std::uint32_t>{2, 1, 0, 3, 2, 0}));
  EXPECT_EQ(mirrored.corner_texcoords[0], s.corner_texcoords[2]);
  EXPECT_EQ(mirrored.corner_texcoords[5], s.corner_texcoords[3]);
}


// Found by fuzz_gltf: an empty mesh was written with zero-count accessors and a buffer that
// the GLB form then left without data, which our own reader (rightly) refused. glTF has no
// empty mesh, so the writer leaves it out; a point cloud (no faces) goes the same way.
TEST(Gltf, MeshWithoutTrianglesIsWrittenAsAValidDocumentWithoutMeshes) {
  PolygonSoup points;
  points.positions = {{0, 0, 0}, {1, 2, 3}};
  for (const PolygonSoup& s : {PolygonSoup{}, points}) {
    for (bool binary : {true, false}) {
      const std::string data = write_gltf(gltf_from_soup(s), binary);
      const std::string text = binary ? data.substr(20, le32(data, 12)) : data;
      const nlohmann::json j = nlohmann::json::parse(text);
      for (const char* key : {"meshes", "accessors", "bufferViews", "buffers"})
        EXPECT_FALSE(j.contains(key)) << key;
      if (binary) {
        EXPECT_EQ(data.size(), 20 + text.size());  // no BIN chunk
      }
      ASSERT_EQ(j["nodes"].size(), 1u);
      EXPECT_FALSE(j["nodes"][0].contains("mesh"));
      const PolygonSoup back = flatten(read_gltf(bytes(data), "x"));
      EXPECT_EQ(back.positions.size(), 0u);
      EXPECT_EQ(back.n_faces(), 0u);
    }
  }
  // Beside a mesh with triangles, the empty one drops out and node indices stay right.
  GltfDocument doc = gltf_lod_chain({PolygonSoup{}, quad_and_triangle()});
  const GltfDocument back = read_gltf(bytes(write_gltf(doc, true)), "x");
  ASSERT_EQ(back.meshes.size(), 1u);
  ASSERT_EQ(back.nodes.size(), 2u);
  EXPECT_LT(back.nodes[0].mesh, 0);
  EXPECT_EQ(back.nodes[1].mesh, 0);
  EXPECT_EQ(back.meshes[0].n_faces(), 3u);
}
TEST(Gltf, HierarchyIsKeptAndFlattened) {
  GltfDocument d = gltf_from_soup(quad_and_triangle());
  d.nodes[0].mesh = -1;
  d.nodes[0].matrix(0, 3) = 10;  // parent moves by +10 in x
  GltfNode child{"child", Eigen::Matrix4d::Identity(), 0, {}, {}};
  child.matrix(1, 1) = 2;  // child scales y by 2
  d.nodes.push_back(child);
  d.nodes[0].children = {1};
  GltfDocument back = read_gltf(bytes(write_gltf(d, true)), "x");
  ASSERT_EQ(back.nodes.size(), 2u);
  EXPECT_EQ(back.nodes[0].children, std::vector<int>{1});
  EXPECT_DOUBLE_EQ(back.nodes[0].matrix(0, 3), 10);
  PolygonSoup flat = flatten(back);
  EXPECT_EQ(flat.positions[4], Point(10.5, 4, 0.25));
  d.nodes[1].children = {0};
  EXPECT_THROW(flatten(d), InvalidArgument);
}

TEST(Gltf, LodChainUsesMsftLod) {
  PolygonSoup fine = quad_and_triangle(), coarse = quad_and_triangle();
  coarse.face_offsets.pop_back();
  coarse.face_indices.resize(4);
  std::string data = write_gltf(gltf_lod_chain({fine, coarse}), false);
  auto j = nlohmann::json::parse(data);
  EXPECT_EQ(j["extensionsUsed"][0], "MSFT_lod");
  EXPECT_EQ(j["nodes"][0]["extensions"]["MSFT_lod"]["ids"][0], 1);
  GltfDocument back = read_gltf(bytes(data), "x");
  EXPECT_EQ(back.nodes[0].lods, std::vector<int>{1});
  EXPECT_EQ(flatten(back).n_faces(), 3u);  // only the finest level is shown
}

// A minimal valid document with one triangle, to break in the tests below.
nlohmann::json triangle_doc() {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.add_face({0, 1, 2});
  return nlohmann::json::parse(write_gltf(gltf_from_soup(s), false));
}

TEST(Gltf, BadFilesGetErrorsNamingTheElement) {
  auto j = triangle_doc();
  EXPECT_EQ(error_of(j.dump()), "");
  auto k = j;
  k["bufferViews"][0]["byteStride"] = 2;
  EXPECT_NE(error_of(k.dump()).find("bufferViews[0].byteStride"), std::string::npos);
  k = j;
  k["bufferViews"][0]["byteStride"] = 8;  // smaller than a VEC3 of floats
  EXPECT_NE(error_of(k.dump()).find("smaller than the element size"), std::string::npos);
  k = j;
  k["buffers"][0]["uri"] = "missing.bin";
  EXPECT_NE(error_of(k.dump()).find("buffers[0].uri"), std::string::npos);
  k = j;
  k["buffers"][0].erase("uri");
  EXPECT_NE(error_of(k.dump()).find("buffers[0]"), std::string::npos);
  k = j;
  k["accessors"][0]["count"] = 1000000;
  EXPECT_NE(error_of(k.dump()).find("accessors[0]"), std::string::npos);
  k = j;
  k["accessors"][0]["bufferView"] = 9;
  EXPECT_NE(error_of(k.dump()).find("accessors[0].bufferView"), std::string::npos);
  k = j;
  k["meshes"][0]["primitives"][0]["mode"] = 7;
  EXPECT_NE(error_of(k.dump()).find("mode: 7 is not a glTF primitive mode"), std::string::npos);
  k = j;
  k["asset"]["version"] = "1.0";
  EXPECT_NE(error_of(k.dump()).find("asset.version"), std::string::npos);
  k = j;
  k["accessors"][0]["sparse"] = nlohmann::json::object();
  EXPECT_NE(error_of(k.dump()).find("sparse"), std::string::npos);
  k = j;
  k["nodes"][0]["children"] = {5};
  EXPECT_NE(error_of(k.dump()).find("nodes[0].children"), std::string::npos);
  EXPECT_NE(error_of("{\"asset\": ").find("invalid glTF JSON"), std::string::npos);
  // Found by fuzz_gltf: 5e97 as an int was undefined behaviour, and a member of the wrong
  // JSON type threw nlohmann's type_error; both name the member now.
  k = j;
  k["accessors"][0]["componentType"] = 5.14e97;
  EXPECT_NE(error_of(k.dump()).find("accessors[0].componentType: 5.14e+97 is not an integer"), std::string::npos)
      << error_of(k.dump());
  k = j;
  k["accessors"][0]["type"] = 3;
  EXPECT_NE(error_of(k.dump()).find("accessors[0].type: expected a string"), std::string::npos);
  k = j;
  k["meshes"][0]["primitives"][0]["mode"] = "triangles";
  EXPECT_NE(error_of(k.dump()).find("mode: "), std::string::npos);
  k = j;
  k["nodes"][0]["name"] = false;
  EXPECT_NE(error_of(k.dump()).find("nodes[0].name: expected a string"), std::string::npos);
  // Found by fuzz_gltf: a number beyond a double's range was not a ParseError.
  EXPECT_NE(error_of("{\"asset\": {\"version\": 1e999}}").find("invalid glTF JSON"), std::string::npos);
}

TEST(Gltf, IndexBeyondVertexCountIsRejected) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.add_face({0, 1, 2});
  std::string glb = write_gltf(gltf_from_soup(s), true);
  // The index buffer is the last 12 bytes of the BIN chunk: make one index 7.
  glb[glb.size() - 4] = 7;
  try {
    read_gltf(bytes(glb), "x.glb");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("not below the vertex count 3"), std::string::npos) << e.what();
  }
}

TEST(Gltf, TruncatedGlbIsRejected) {
  PolygonSoup s = quad_and_triangle();
  std::string glb = write_gltf(gltf_from_soup(s), true);
  for (std::size_t len : {std::size_t{3}, std::size_t{12}, std::size_t{19}, glb.size() / 2, glb.size() - 1})
    EXPECT_THROW(read_gltf(bytes(glb.substr(0, len)), "t.glb"), ParseError) << len;
  std::string v1 = glb;
  v1[4] = 1;
  EXPECT_THROW(read_gltf(bytes(v1), "t.glb"), ParseError);
}

}  // namespace
}  // namespace geom

namespace geom {
namespace {

// Two triangles sharing an edge, plus a copy of the first at the same place: a soup that
// keeps vertices apart which welding by position would join.
PolygonSoup with_coincident_copy() {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}};
  s.add_face({0, 1, 2});
  s.add_face({0, 2, 3});
  s.add_face({4, 5, 6});
  return s;
}

TEST(GltfWeld, SplitVerticesAreReadAsOneVertexWithCornerValues) {
  // A file written by another tool: vertex 0 twice (different UVs), vertex 2 twice (same UV,
  // different normal), and vertex 1 twice with different colours, which stay two vertices.
  PolygonSoup split;
  split.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, 0}};
  split.vertex_texcoords = {{0, 0}, {1, 0}, {1, 1}, {0.5, 0}, {1, 1}, {0, 1}, {1, 0}};
  split.vertex_colors = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}, {0, 0, 1}, {1, 1, 1}, {0, 0, 0}};
  split.add_face({0, 1, 2});
  split.add_face({3, 4, 5});
  split.add_face({6, 4, 3});
  // geom marks its own split vertices (_GEOM_VERTEX); another tool's file has no mark.
  auto j = nlohmann::json::parse(write_gltf(gltf_from_soup(split), false));
  ASSERT_EQ(j["meshes"][0]["primitives"][0]["attributes"].erase("_GEOM_VERTEX"), 1u);
  const std::string text = j.dump();
  const PolygonSoup back = read_gltf(bytes(text), "x").meshes[0];
  EXPECT_EQ(back.positions.size(), 5u);  // 0 and 3 one, 2 and 4 one, 1 and 6 apart (colour)
  EXPECT_EQ(back.face_indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 3, 4, 2, 0}));
  ASSERT_EQ(back.corner_texcoords.size(), 9u);
  EXPECT_EQ(back.corner_texcoords[3], TexCoord(0.5, 0));
  EXPECT_TRUE(back.vertex_texcoords.empty());
}

TEST(GltfWeld, VerticesTheSoupKeepsApartComeBackApart) {
  const PolygonSoup s = with_coincident_copy();
  const std::string glb = write_gltf(gltf_from_soup(s), true);
  const auto j = nlohmann::json::parse(glb.substr(20, le32(glb, 12)));
  EXPECT_TRUE(j["meshes"][0]["primitives"][0]["attributes"].contains("_GEOM_VERTEX"));
  const PolygonSoup back = read_gltf(bytes(glb), "x").meshes[0];
  EXPECT_EQ(back.positions, s.positions);
  EXPECT_EQ(back.face_indices, s.face_indices);
  // Without coincident vertices the file carries no id.
  PolygonSoup plain = s;
  plain.positions.resize(4);
  plain.face_offsets.pop_back();
  plain.face_indices.resize(6);
  const std::string small = write_gltf(gltf_from_soup(plain), true);
  EXPECT_EQ(small.find("_GEOM_VERTEX"), std::string::npos);
}

}  // namespace
}  // namespace geom
