// Scene files: what parses, and errors that name the key at fault.

#include <geom/render/render.h>

#include "meshes.h"

#include <gtest/gtest.h>

namespace geom {
namespace {

std::shared_ptr<const SurfaceMesh> resolver(const std::string& path) {
  if (path == "cube.obj") return test::cube();
  if (path == "tetrahedron.obj") return test::tetrahedron();
  throw Error("cannot open '" + path + "'");
}

std::string error_of(const std::string& json) {
  try {
    parse_scene(json, "scene.json", resolver);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Scene, ParsesHierarchyMaterialsLightsAndCamera) {
  const std::string json = R"({
    "image": {"width": 64, "height": 48, "samples": 1, "background": [0, 0, 0], "wireframe": true},
    "camera": {"eye": [0, 0, 5], "at": [0, 0, 0], "fov": 30},
    "materials": {"red": {"diffuse": [1, 0, 0], "reflectance": 0.25}},
    "meshes": {"box": "cube.obj"},
    "nodes": [{"name": "root", "translate": [1, 0, 0], "children": [
      {"mesh": "box", "material": "red", "scale": 0.5},
      {"mesh": "box", "rotate": [0, 1, 0, 45]}]}],
    "lights": [{"type": "point", "position": [0, 5, 0], "shadows": true}]
  })";
  Scene s = parse_scene(json, "scene.json", resolver);
  EXPECT_EQ(s.width, 64);
  EXPECT_EQ(s.height, 48);
  EXPECT_TRUE(s.wireframe);
  ASSERT_EQ(s.nodes.size(), 3u);
  EXPECT_EQ(s.nodes[0].children.size(), 2u);
  EXPECT_EQ(s.nodes[1].material, 1);
  EXPECT_DOUBLE_EQ(s.materials[1].reflectance, 0.25);
  EXPECT_EQ(s.lights.size(), 1u);
  EXPECT_TRUE(s.lights[0].shadows);
  EXPECT_TRUE(needs_ray_tracing(s));
  RenderResult r = render(s);
  EXPECT_EQ(r.image.width(), 64);
  EXPECT_EQ(r.stats.triangles, 24u);
}

// Found by fuzz_scene: a projective matrix with a huge entry puts screen points near
// infinity, and the wireframe pass converted their step count and pixel positions to int
// (undefined behaviour; the sanitizer build aborts on it). The scene must render; the far
// edges simply leave no ink.
TEST(Scene, HugeTransformsRenderWithoutOverflow) {
  const std::string json = R"({
    "image": {"wireframe": true, "width": 8, "height": 8},
    "meshes": {"m": "tetrahedron.obj"},
    "materials": {"mirror": {"reflectance": 1}},
    "nodes": [{"mesh": "m", "material": "mirror",
               "matrix": [1, 0, 0, 0, 0, 1, 0, 4.4444444444444445e57, 0, 1, 1, 0, 0, 0, 0, 2]}]
  })";
  const RenderResult r = render(parse_scene(json, "scene.json", resolver));
  EXPECT_EQ(r.image.width(), 8);
  EXPECT_EQ(r.stats.path, "raytrace");
}

TEST(Scene, ErrorsNameTheKey) {
  EXPECT_NE(error_of("{ not json").find("invalid JSON"), std::string::npos);
  // Found by fuzz_scene: a number beyond a double's range escaped as nlohmann's out_of_range.
  EXPECT_NE(error_of(R"({"meshes": {}, "image": {"ambient": 1e999}})").find("invalid JSON"), std::string::npos);
  EXPECT_NE(error_of(R"({"meshes": {"a": "missing.obj"}})").find("missing.obj"), std::string::npos);
  std::string e = error_of(R"({"meshes": {"a": "cube.obj"}, "nodes": [{"mesh": "a", "material": "gold"}]})");
  EXPECT_NE(e.find("nodes[0].material"), std::string::npos) << e;
  EXPECT_NE(e.find("gold"), std::string::npos) << e;
  e = error_of(R"({"meshes": {"a": "cube.obj"}, "lights": [{"shadow": true}]})");
  EXPECT_NE(e.find("lights[0].shadow"), std::string::npos) << e;
  e = error_of(R"({"meshes": {"a": "cube.obj"}, "image": {"width": -3}})");
  EXPECT_NE(e.find("image.width"), std::string::npos) << e;
  e = error_of(R"({"meshes": {"a": "cube.obj"}, "nodes": [{"mesh": "b"}]})");
  EXPECT_NE(e.find("unknown mesh 'b'"), std::string::npos) << e;
  e = error_of(R"({"image": {}})");
  EXPECT_NE(e.find("meshes"), std::string::npos) << e;
  e = error_of(R"({"meshes": {"a": "cube.obj"}, "lights": [{"type": "spot"}]})");
  EXPECT_NE(e.find("lights[0].type"), std::string::npos) << e;
  e = error_of(R"({"meshes": {"a": "cube.obj"}, "camera": {"eye": [0, 0, 1], "at": [0, 0, 1]}})");
  EXPECT_NE(e.find("camera"), std::string::npos) << e;
}

}  // namespace
}  // namespace geom
