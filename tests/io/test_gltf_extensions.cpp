// glTF files as real exporters write them: sparse accessors, quantized attributes
// (KHR_mesh_quantization), meshopt- and Draco-compressed data, point and line primitives,
// appearance-only required extensions, percent-encoded URIs, colours; and the bounds geom
// writes.

#include "io_test_util.h"

#include <geom/core/errors.h>
#include <geom/io/gltf.h>
#include <geom/io/io.h>

#include <draco/compression/encode.h>
#include <draco/core/encoder_buffer.h>
#include <draco/mesh/mesh.h>
#include <gtest/gtest.h>
#include <meshoptimizer.h>
#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace geom {
namespace {

using nlohmann::json;
using test::bytes;

/// A glTF document under construction: one binary buffer, views and accessors appended.
struct Doc {
  json j = {{"asset", {{"version", "2.0"}}}, {"buffers", json::array()}, {"bufferViews", json::array()},
            {"accessors", json::array()}};
  std::string bin;

  int view(const std::string& data) {
    while (bin.size() % 4) bin.push_back('\0');
    j["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", data.size()}});
    bin += data;
    return static_cast<int>(j["bufferViews"].size() - 1);
  }
  template <class T>
  int view(const std::vector<T>& v) {
    return view(std::string(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T)));
  }
  int accessor(json a) {
    j["accessors"].push_back(std::move(a));
    return static_cast<int>(j["accessors"].size() - 1);
  }
  void mesh(json primitives) {
    j["meshes"] = json::array({{{"primitives", std::move(primitives)}}});
    j["nodes"] = json::array({{{"mesh", 0}}});
  }
  /// GLB bytes: header, JSON chunk, BIN chunk.
  std::string glb() {
    while (bin.size() % 4) bin.push_back('\0');
    if (j["buffers"].empty()) j["buffers"].push_back(json::object());
    j["buffers"][0]["byteLength"] = bin.size();
    std::string text = j.dump();
    while (text.size() % 4) text.push_back(' ');
    std::string out;
    auto u32 = [&](std::uint32_t v) { test::put(out, v, false); };
    u32(0x46546C67), u32(2), u32(static_cast<std::uint32_t>(12 + 8 + text.size() + 8 + bin.size()));
    u32(static_cast<std::uint32_t>(text.size())), u32(0x4E4F534A);
    out += text;
    u32(static_cast<std::uint32_t>(bin.size())), u32(0x004E4942);
    return out + bin;
  }
};

int float_accessor(Doc& d, const std::vector<float>& v, const char* type, int n) {
  return d.accessor({{"bufferView", d.view(v)}, {"componentType", 5126}, {"count", v.size() / n}, {"type", type}});
}

int index_accessor(Doc& d, const std::vector<std::uint32_t>& v) {
  return d.accessor({{"bufferView", d.view(v)}, {"componentType", 5125}, {"count", v.size()}, {"type", "SCALAR"}});
}

const std::vector<float> kSquare = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
const std::vector<std::uint32_t> kTwoTriangles = {0, 1, 2, 0, 2, 3};

PolygonSoup read_glb(Doc& d) { return flatten(read_gltf(bytes(d.glb()), "t.glb")); }

TEST(GltfExtensions, PositionBoundsArePerAxis) {
  // The first vertex's x (5) lies outside the y and z ranges: bounds seeded from it were wrong.
  PolygonSoup s;
  s.positions = {{5, 0, 0}, {6, 1, -3}, {7, -2, 1}};
  s.add_face({0, 1, 2});
  const json j = json::parse(write_gltf(gltf_from_soup(s), false));
  const json& acc = j["accessors"][j["meshes"][0]["primitives"][0]["attributes"]["POSITION"].get<int>()];
  EXPECT_EQ(acc["min"], json({5.0, -2.0, -3.0}));
  EXPECT_EQ(acc["max"], json({7.0, 1.0, 1.0}));
}

TEST(GltfExtensions, SparseAccessorReplacesListedElements) {
  Doc d;
  const int pos = float_accessor(d, kSquare, "VEC3", 3);
  d.j["accessors"][pos]["sparse"] = {
      {"count", 2},
      {"indices", {{"bufferView", d.view(std::vector<std::uint16_t>{1, 3})}, {"componentType", 5123}}},
      {"values", {{"bufferView", d.view(std::vector<float>{2, 0, 0, 0, 2, 5})}}}};
  d.mesh({{{"attributes", {{"POSITION", pos}}}, {"indices", index_accessor(d, kTwoTriangles)}}});
  const PolygonSoup s = read_glb(d);
  ASSERT_EQ(s.positions.size(), 4u);
  EXPECT_EQ(s.positions[1], Point(2, 0, 0));
  EXPECT_EQ(s.positions[2], Point(1, 1, 0));
  EXPECT_EQ(s.positions[3], Point(0, 2, 5));
  // Indices must increase and stay below the count.
  d.j["accessors"][pos]["sparse"]["indices"]["bufferView"] = d.view(std::vector<std::uint16_t>{3, 1});
  EXPECT_THROW(read_glb(d), ParseError);
}

TEST(GltfExtensions, SparseAccessorWithoutBufferViewStartsFromZeros) {
  Doc d;
  const int pos = d.accessor({{"componentType", 5126}, {"count", 3}, {"type", "VEC3"},
                              {"sparse", {{"count", 1},
                                          {"indices", {{"bufferView", d.view(std::vector<std::uint8_t>{2, 0, 0, 0})},
                                                       {"componentType", 5121}}},
                                          {"values", {{"bufferView", d.view(std::vector<float>{1, 2, 3})}}}}}});
  d.mesh({{{"attributes", {{"POSITION", pos}}}}});
  const PolygonSoup s = read_glb(d);
  // Elements 0 and 1 stay zeros: one vertex once the mesh is welded.
  ASSERT_EQ(s.positions.size(), 2u);
  EXPECT_EQ(s.positions[0], Point(0, 0, 0));
  EXPECT_EQ(s.positions[1], Point(1, 2, 3));
  EXPECT_EQ(s.face_indices, (std::vector<std::uint32_t>{0, 0, 1}));
}

TEST(GltfExtensions, QuantizedAttributesAreDequantized) {
  Doc d;
  d.j["extensionsUsed"] = {"KHR_mesh_quantization"};
  d.j["extensionsRequired"] = {"KHR_mesh_quantization"};
  // Positions as int16 (stride 8: each element padded to 4 bytes), normals as normalized
  // int8, texture coordinates as normalized uint16.
  const std::vector<std::int16_t> pos = {0, 0, 0, 0, 100, 0, 0, 0, 100, -7, 0, 0, 0, 100, 0, 0};
  const int p = d.accessor({{"bufferView", d.view(pos)}, {"componentType", 5122}, {"count", 4}, {"type", "VEC3"}});
  d.j["bufferViews"][d.j["accessors"][p]["bufferView"].get<int>()]["byteStride"] = 8;
  const std::vector<std::int8_t> nrm = {0, 0, 127, 0, 0, 0, 127, 0, 0, 0, 127, 0, 0, 0, -128, 0};
  const int n = d.accessor({{"bufferView", d.view(nrm)}, {"componentType", 5120}, {"count", 4}, {"type", "VEC3"},
                            {"normalized", true}});
  d.j["bufferViews"][d.j["accessors"][n]["bufferView"].get<int>()]["byteStride"] = 4;
  const std::vector<std::uint16_t> uv = {0, 0, 65535, 0, 65535, 65535, 0, 32768};
  const int t = d.accessor({{"bufferView", d.view(uv)}, {"componentType", 5123}, {"count", 4}, {"type", "VEC2"},
                            {"normalized", true}});
  d.mesh({{{"attributes", {{"POSITION", p}, {"NORMAL", n}, {"TEXCOORD_0", t}}},
           {"indices", index_accessor(d, kTwoTriangles)}}});
  const PolygonSoup s = read_glb(d);
  ASSERT_EQ(s.positions.size(), 4u);
  EXPECT_EQ(s.positions[2], Point(100, -7, 0));
  EXPECT_EQ(s.vertex_normals[3], Normal(0, 0, -1));  // -128 clamps to -1
  EXPECT_EQ(s.vertex_texcoords[2], TexCoord(1, 1));
  EXPECT_DOUBLE_EQ(s.vertex_texcoords[3].y(), 32768 / 65535.0);
}

TEST(GltfExtensions, MeshoptCompressedViewsDecode) {
  const std::size_t n = 200;
  std::vector<float> pos;
  for (std::size_t i = 0; i < n; ++i) pos.insert(pos.end(), {float(i % 10), float(i / 10), float(i * 0.5)});
  std::vector<std::uint32_t> tri;
  for (std::uint32_t i = 0; i + 2 < n; ++i) tri.insert(tri.end(), {i, i + 1, i + 2});
  std::vector<unsigned char> vbuf(meshopt_encodeVertexBufferBound(n, 12));
  vbuf.resize(meshopt_encodeVertexBuffer(vbuf.data(), vbuf.size(), pos.data(), n, 12));
  std::vector<unsigned char> ibuf(meshopt_encodeIndexBufferBound(tri.size(), n));
  ibuf.resize(meshopt_encodeIndexBuffer(ibuf.data(), ibuf.size(), tri.data(), tri.size()));
  Doc d;
  d.j["extensionsUsed"] = d.j["extensionsRequired"] = {"EXT_meshopt_compression"};
  const int vc = d.view(vbuf), ic = d.view(ibuf);
  // Views 2 and 3 live in a fallback buffer (1) that has no data; their bytes come from the
  // compressed views in buffer 0.
  auto compressed = [&](int from, std::size_t length, std::size_t stride, std::size_t count, const char* mode) {
    json ext = d.j["bufferViews"][from];
    ext.erase("buffer");
    ext["buffer"] = 0;
    ext["byteStride"] = stride, ext["count"] = count, ext["mode"] = mode;
    d.j["bufferViews"].push_back({{"buffer", 1}, {"byteLength", length}, {"extensions", {{"EXT_meshopt_compression", ext}}}});
    return static_cast<int>(d.j["bufferViews"].size() - 1);
  };
  const int pv = compressed(vc, n * 12, 12, n, "ATTRIBUTES");
  const int iv = compressed(ic, tri.size() * 4, 4, tri.size(), "TRIANGLES");
  const int p = d.accessor({{"bufferView", pv}, {"componentType", 5126}, {"count", n}, {"type", "VEC3"}});
  const int i = d.accessor({{"bufferView", iv}, {"componentType", 5125}, {"count", tri.size()}, {"type", "SCALAR"}});
  d.mesh({{{"attributes", {{"POSITION", p}}}, {"indices", i}}});
  d.j["buffers"] = {json::object(), {{"byteLength", tri.size() * 4 + n * 12},
                                     {"extensions", {{"EXT_meshopt_compression", {{"fallback", true}}}}}}};
  const PolygonSoup s = flatten(read_gltf(bytes(d.glb()), "meshopt.glb"));
  ASSERT_EQ(s.positions.size(), n);
  ASSERT_EQ(s.n_faces(), tri.size() / 3);
  for (std::size_t v = 0; v < n; ++v) EXPECT_EQ(s.positions[v], Point(pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]));
  // The index codec keeps each triangle's winding but may start it at another corner.
  auto lowest_first = [](std::vector<std::uint32_t> t) {
    std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
    return t;
  };
  for (std::size_t f = 0; f < s.n_faces(); ++f)
    EXPECT_EQ(lowest_first({s.face(f).begin(), s.face(f).end()}),
              lowest_first({tri.begin() + 3 * f, tri.begin() + 3 * f + 3}));
  // A truncated stream is an error naming the view, not a crash.
  d.j["bufferViews"][pv]["extensions"]["EXT_meshopt_compression"]["byteLength"] = vbuf.size() / 2;
  try {
    flatten(read_gltf(bytes(d.glb()), "meshopt.glb"));
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("bufferViews[2].extensions.EXT_meshopt_compression: meshopt stream is malformed"),
              std::string::npos)
        << e.what();
  }
}

TEST(GltfExtensions, DracoCompressedPrimitiveDecodes) {
  draco::Mesh mesh;
  mesh.set_num_points(4);
  draco::GeometryAttribute ga;
  ga.Init(draco::GeometryAttribute::POSITION, nullptr, 3, draco::DT_FLOAT32, false, 12, 0);
  const int id = mesh.AddAttribute(ga, true, 4);
  for (std::uint32_t v = 0; v < 4; ++v) mesh.attribute(id)->SetAttributeValue(draco::AttributeValueIndex(v), &kSquare[3 * v]);
  mesh.AddFace({draco::PointIndex(0), draco::PointIndex(1), draco::PointIndex(2)});
  mesh.AddFace({draco::PointIndex(0), draco::PointIndex(2), draco::PointIndex(3)});
  draco::Encoder encoder;
  encoder.SetEncodingMethod(draco::MESH_SEQUENTIAL_ENCODING);
  draco::EncoderBuffer buffer;
  ASSERT_TRUE(encoder.EncodeMeshToBuffer(mesh, &buffer).ok());
  Doc d;
  d.j["extensionsUsed"] = d.j["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  const int view = d.view(std::string(buffer.data(), buffer.size()));
  const int p = d.accessor({{"componentType", 5126}, {"count", 4}, {"type", "VEC3"}});
  const int i = d.accessor({{"componentType", 5125}, {"count", 6}, {"type", "SCALAR"}});
  d.mesh({{{"attributes", {{"POSITION", p}}},
           {"indices", i},
           {"extensions",
            {{"KHR_draco_mesh_compression",
              {{"bufferView", view}, {"attributes", {{"POSITION", mesh.attribute(id)->unique_id()}}}}}}}}});
  const PolygonSoup s = read_glb(d);
  ASSERT_EQ(s.positions.size(), 4u);
  ASSERT_EQ(s.n_faces(), 2u);
  for (std::size_t f = 0; f < 2; ++f)
    for (std::size_t k = 0; k < 3; ++k) {
      const Point& p = s.positions[s.face(f)[k]];
      const std::uint32_t v = kTwoTriangles[3 * f + k];
      EXPECT_EQ(p, Point(kSquare[3 * v], kSquare[3 * v + 1], kSquare[3 * v + 2]));
    }
  // A truncated stream is refused naming the primitive.
  d.bin.resize(d.j["bufferViews"][view]["byteOffset"].get<std::size_t>() + 12);
  d.j["bufferViews"][view]["byteLength"] = 12;
  try {
    read_glb(d);
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("meshes[0].primitives[0].extensions.KHR_draco_mesh_compression"),
              std::string::npos)
        << e.what();
  }
}

TEST(GltfExtensions, PointAndLinePrimitivesAreSkippedWithAWarning) {
  Doc d;
  const int p = float_accessor(d, kSquare, "VEC3", 3);
  d.mesh({{{"attributes", {{"POSITION", p}}}, {"mode", 0}},
          {{"attributes", {{"POSITION", p}}}, {"mode", 1}},
          {{"attributes", {{"POSITION", p}}}, {"indices", index_accessor(d, kTwoTriangles)}}});
  const PolygonSoup s = read_glb(d);
  EXPECT_EQ(s.positions.size(), 4u);  // only the triangles' primitive
  EXPECT_EQ(s.n_faces(), 2u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0], "meshes[0]: 2 point or line primitives were skipped (geom reads surfaces)");
}

TEST(GltfExtensions, AFileOfLinesOnlyIsRefusedSayingWhatWasSkipped) {
  Doc d;
  d.mesh({{{"attributes", {{"POSITION", float_accessor(d, kSquare, "VEC3", 3)}}}, {"mode", 3}}});
  try {
    read_soup(bytes(d.glb()), FileFormat::kGlb, "lines.glb");
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_EQ(std::string(e.what()),
              "lines.glb: no geometry: the file holds no vertex and no face; meshes[0]: 1 point or line "
              "primitive was skipped (geom reads surfaces)");
  }
}

TEST(GltfExtensions, AppearanceOnlyRequiredExtensionsAreIgnoredWithAWarning) {
  Doc d;
  d.mesh({{{"attributes", {{"POSITION", float_accessor(d, kSquare, "VEC3", 3)}}},
           {"indices", index_accessor(d, kTwoTriangles)}}});
  d.j["extensionsRequired"] = {"KHR_texture_transform", "KHR_materials_unlit"};
  const PolygonSoup s = read_glb(d);
  EXPECT_EQ(s.n_faces(), 2u);
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0],
            "required extensions that change only appearance were ignored: KHR_texture_transform, KHR_materials_unlit");
  // One that places geometry is refused, naming it.
  d.j["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
  try {
    read_glb(d);
    FAIL() << "expected ParseError";
  } catch (const ParseError& e) {
    EXPECT_NE(std::string(e.what()).find("'EXT_mesh_gpu_instancing' is not supported"), std::string::npos) << e.what();
  }
}

TEST(GltfExtensions, AttributeOnSomePrimitivesOnlyIsDroppedWithAWarning) {
  Doc d;
  const int p = float_accessor(d, kSquare, "VEC3", 3);
  const int n = float_accessor(d, {0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
  const int i = index_accessor(d, kTwoTriangles);
  d.mesh({{{"attributes", {{"POSITION", p}, {"NORMAL", n}}}, {"indices", i}}, {{"attributes", {{"POSITION", p}}}, {"indices", i}}});
  const PolygonSoup s = read_glb(d);
  EXPECT_TRUE(s.vertex_normals.empty());
  ASSERT_EQ(s.warnings.size(), 1u);
  EXPECT_EQ(s.warnings[0], "meshes[0]: NORMAL not kept (only some of its 2 primitives have them)");
}

TEST(GltfExtensions, ColoursRoundTrip) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.add_face({0, 1, 2});
  s.vertex_colors = {{1, 0, 0}, {0, 0.5, 0}, {0, 0, 1}};
  for (bool binary : {true, false}) {
    const std::string data = write_gltf(gltf_from_soup(s), binary);
    const PolygonSoup back = flatten(read_gltf(bytes(data), "c"));
    ASSERT_EQ(back.vertex_colors.size(), 3u);
    EXPECT_EQ(back.vertex_colors[1], Color(0, 0.5, 0));
  }
  // RGBA colours (as unsigned bytes) keep their RGB.
  Doc d;
  const int c = d.accessor({{"bufferView", d.view(std::vector<std::uint8_t>{255, 0, 0, 9, 0, 255, 0, 9, 0, 0, 255, 9, 0, 0, 0, 9})},
                            {"componentType", 5121}, {"count", 4}, {"type", "VEC4"}, {"normalized", true}});
  d.mesh({{{"attributes", {{"POSITION", float_accessor(d, kSquare, "VEC3", 3)}, {"COLOR_0", c}}},
           {"indices", index_accessor(d, kTwoTriangles)}}});
  const PolygonSoup q = read_glb(d);
  ASSERT_EQ(q.vertex_colors.size(), 4u);
  EXPECT_EQ(q.vertex_colors[1], Color(0, 1, 0));
}

TEST(GltfExtensions, NormalsAreWrittenUnitLengthOrNotAtAll) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  s.add_face({0, 1, 2});
  s.vertex_normals = {{0, 0, 2}, {0, 0, 1}, {0, 3, 4}};
  PolygonSoup back = flatten(read_gltf(bytes(write_gltf(gltf_from_soup(s), true)), "n"));
  ASSERT_EQ(back.vertex_normals.size(), 3u);
  EXPECT_NEAR(back.vertex_normals[0].z(), 1.0, 1e-7);
  EXPECT_NEAR(back.vertex_normals[2].y(), 0.6, 1e-7);
  s.vertex_normals[1] = Normal::Zero();  // no direction: NORMAL is left out
  back = flatten(read_gltf(bytes(write_gltf(gltf_from_soup(s), true)), "n"));
  EXPECT_TRUE(back.vertex_normals.empty());
}

TEST(GltfExtensions, ExternalBuffersWithPercentEncodedNamesBesideARelativePath) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("geom_gltf_uri_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  Doc d;
  d.mesh({{{"attributes", {{"POSITION", float_accessor(d, kSquare, "VEC3", 3)}}},
           {"indices", index_accessor(d, kTwoTriangles)}}});
  d.glb();  // pads the buffer and sets its length
  d.j["buffers"][0]["uri"] = "my%20data%2B1.bin";
  std::ofstream(dir / "my data+1.bin", std::ios::binary) << d.bin;
  std::ofstream(dir / "scene.gltf") << d.j.dump();
  const std::filesystem::path cwd = std::filesystem::current_path();
  std::filesystem::current_path(dir);
  PolygonSoup s;
  EXPECT_NO_THROW(s = read_soup("scene.gltf"));  // no folder in the name: the current one
  std::filesystem::current_path(cwd);
  EXPECT_EQ(s.n_faces(), 2u);
  EXPECT_EQ(read_soup(dir / "scene.gltf").positions.size(), 4u);
  d.j["buffers"][0]["uri"] = "my%2";
  std::ofstream(dir / "bad.gltf") << d.j.dump();
  EXPECT_THROW(read_soup(dir / "bad.gltf"), ParseError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace geom
