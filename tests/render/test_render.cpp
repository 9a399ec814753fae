// Rendering with exact expectations: silhouette areas, visibility, effects only when asked.

#include <geom/render/render.h>

#include "meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace geom {
namespace {

const Rgb8 kMagenta{255, 0, 255};

Scene head_on(std::shared_ptr<const SurfaceMesh> mesh, double distance, int size) {
  Scene s = scene_for_mesh(std::move(mesh));
  s.width = s.height = size;
  s.samples = 1;
  s.background = Color(1, 0, 1);
  s.camera = Camera{};
  s.camera->eye = Eigen::Vector3d(0, 0, distance);
  s.camera->at = Eigen::Vector3d::Zero();
  s.camera->fov_y_degrees = 40;
  return s;
}

std::size_t covered(const Image& img) {
  std::size_t n = 0;
  for (Rgb8 p : img.pixels()) n += p == kMagenta ? 0 : 1;
  return n;
}

TEST(Render, SphereSilhouetteMatchesAnalyticProjectedArea) {
  const double d = 5.0, fov = 40.0;
  const int size = 256;
  for (RenderPath path : {RenderPath::kRaster, RenderPath::kRayTrace}) {
    RenderResult r = render(head_on(test::icosphere(5), d, size), {.path = path});
    // A sphere seen from its axis projects to a disk of angular radius asin(1/d).
    const double radius_px = std::tan(std::asin(1.0 / d)) / std::tan(fov / 2 * std::numbers::pi / 180) * size / 2;
    const double area = std::numbers::pi * radius_px * radius_px;
    const double count = static_cast<double>(covered(r.image));
    EXPECT_NEAR(count, area, 0.05 * 2 * std::numbers::pi * radius_px + 10) << r.stats.path;
  }
}

TEST(Render, NearerObjectHidesFartherWhateverTheOrder) {
  auto near_sphere = test::icosphere(3, 0.6, Point(0, 0, 1));
  auto far_sphere = test::icosphere(3, 1.0, Point(0, 0, -1));
  for (bool near_first : {true, false}) {
    Scene s = head_on(near_first ? near_sphere : far_sphere, 6, 64);
    s.meshes.push_back(near_first ? far_sphere : near_sphere);
    s.nodes.push_back(SceneNode{"second", Eigen::Matrix4d::Identity(), 1, 1, {}});
    s.roots.push_back(1);
    Material red, blue;
    red.diffuse = Color(1, 0, 0);
    red.specular = Color::Zero();
    blue.diffuse = Color(0, 0, 1);
    blue.specular = Color::Zero();
    s.materials = near_first ? std::vector<Material>{red, blue} : std::vector<Material>{blue, red};
    Rgb8 centre = render(s).image.at(32, 32);
    EXPECT_GT(centre.r, 100) << "near sphere must be in front";
    EXPECT_EQ(centre.b, 0);
    EXPECT_EQ(centre.g, 0);
  }
}

TEST(Render, EffectFreeSceneRastersWithoutBvhOrSecondaryRays) {
  RenderResult r = render(head_on(test::icosphere(2), 5, 64));
  EXPECT_EQ(r.stats.path, "raster");
  EXPECT_FALSE(r.stats.bvh_built);
  EXPECT_EQ(r.stats.primary_rays, 0u);
  EXPECT_EQ(r.stats.shadow_rays, 0u);
  EXPECT_EQ(r.stats.reflection_rays, 0u);
  EXPECT_TRUE(r.stats.normals_computed);
  Scene flat = head_on(test::icosphere(2), 5, 64);
  flat.shading = Shading::kFlat;
  EXPECT_FALSE(render(flat).stats.normals_computed);  // no normals nobody asked for
}

TEST(Render, RasterAndRayTraceAgreeWithoutEffects) {
  Scene s = head_on(test::icosphere(4), 4, 128);
  s.lights = default_lights();
  Image a = render(s, {.path = RenderPath::kRaster}).image;
  Image b = render(s, {.path = RenderPath::kRayTrace}).image;
  std::size_t close = 0, total = 0;
  double sum = 0;
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x) {
      Rgb8 p = a.at(x, y), q = b.at(x, y);
      int d = std::max({std::abs(p.r - q.r), std::abs(p.g - q.g), std::abs(p.b - q.b)});
      sum += d;
      close += d <= 2 ? 1 : 0;
      ++total;
    }
  EXPECT_LT(sum / total, 0.5);
  EXPECT_GT(static_cast<double>(close) / total, 0.995);
}

// A sphere floating over the ground, lit from straight above.
Scene shadow_scene(bool shadows) {
  Scene s = scene_for_mesh(test::icosphere(3, 1.0, Point(0, 1.5, 0)));
  s.width = s.height = 96;
  s.samples = 1;
  s.ground = true;
  s.camera = Camera{};
  s.camera->eye = Eigen::Vector3d(0, 7, 7);
  s.camera->at = Eigen::Vector3d(0, 0, 0);
  Light sun;
  sun.direction = Eigen::Vector3d(0, -1, 0);
  sun.shadows = shadows;
  s.lights = {sun};
  return s;
}

TEST(Render, ShadowAppearsExactlyWhenTheLightCastsShadows) {
  RenderResult lit = render(shadow_scene(false));
  RenderResult shadowed = render(shadow_scene(true));
  EXPECT_EQ(lit.stats.path, "raster");
  EXPECT_EQ(lit.stats.shadow_rays, 0u);
  EXPECT_EQ(shadowed.stats.path, "raytrace");
  EXPECT_TRUE(shadowed.stats.bvh_built);
  EXPECT_GT(shadowed.stats.shadow_rays, 0u);
  EXPECT_EQ(shadowed.stats.reflection_rays, 0u);
  // The ground point under the sphere's centre projects to the pixel of world (0, ~-0.003, 0).
  Camera cam = *shadow_scene(true).camera;
  Eigen::Vector3d dir = (Eigen::Vector3d(0, 0, 0) - cam.eye).normalized();
  EXPECT_GT(dir.norm(), 0);
  // The world origin is the camera's look-at point: the image centre.
  Rgb8 in_lit = lit.image.at(48, 48), in_shadow = shadowed.image.at(48, 48);
  EXPECT_LT(in_shadow.r + 40, in_lit.r) << "ground under the sphere must darken";
  // Far from the sphere the ground is equally lit either way.
  Rgb8 a = lit.image.at(48, 90), b = shadowed.image.at(48, 90);
  EXPECT_NEAR(a.r, b.r, 2);
}

TEST(Render, MirrorMaterialTracesReflectionRays) {
  Scene s = shadow_scene(false);
  s.materials[0].reflectance = 0.5;
  RenderResult r = render(s);
  EXPECT_EQ(r.stats.path, "raytrace");
  EXPECT_GT(r.stats.reflection_rays, 0u);
  EXPECT_EQ(r.stats.shadow_rays, 0u);
}

TEST(Render, InstancesShareOneMeshThroughNestedTransforms) {
  auto m = test::cube();
  Scene s = scene_for_mesh(m);
  s.nodes.clear();
  s.roots.clear();
  Eigen::Affine3d left(Eigen::Translation3d(-2, 0, 0)), up(Eigen::Translation3d(0, 3, 0));
  s.nodes.push_back({"group", left.matrix(), -1, 0, {1, 2}});
  s.nodes.push_back({"a", Eigen::Matrix4d::Identity(), 0, 0, {}});
  s.nodes.push_back({"b", up.matrix(), 0, 0, {}});
  s.roots = {0};
  RenderResult r = render(s);
  EXPECT_EQ(r.stats.triangles, 24u);  // 2 instances × 6 quads × 2 triangles
  s.nodes[2].children = {0};          // a cycle
  EXPECT_THROW(render(s), InvalidArgument);
}

TEST(Render, WireframeDrawsOnlyVisibleEdges) {
  Scene s = head_on(test::cube(), 6, 128);
  s.shading = Shading::kFlat;
  Image plain = render(s).image;
  s.wireframe = true;
  Image wire = render(s).image;
  // Head-on, the front face's outline is visible: the centre row crosses two edges, and the
  // hidden back edges (which project onto the same square here) add nothing inside it.
  int dark = 0, changed = 0;
  for (int x = 0; x < 128; ++x) {
    Rgb8 p = wire.at(x, 64);
    dark += (p.r < 60 && p.g < 60) ? 1 : 0;
    changed += p == plain.at(x, 64) ? 0 : 1;
  }
  EXPECT_GE(dark, 2);
  EXPECT_LE(changed, 6);
}

TEST(Image, PngRoundTripAndMontage) {
  Image img(7, 5, {10, 20, 30});
  img.at(3, 2) = {200, 100, 50};
  auto png = encode_png(img);
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png[1], 'P');
  Image back = decode_png(png);
  ASSERT_EQ(back.width(), 7);
  EXPECT_EQ(back.at(3, 2), (Rgb8{200, 100, 50}));
  EXPECT_EQ(back.at(0, 0), (Rgb8{10, 20, 30}));
  std::vector<std::uint8_t> junk{1, 2, 3};
  EXPECT_THROW(decode_png(junk), ParseError);
  Image m = montage({img, img, img}, {"A", "B", "1.5E-4"}, {.columns = 2});
  EXPECT_GT(m.width(), 2 * 7);
  EXPECT_THROW(montage({img}, {}), InvalidArgument);
  EXPECT_THROW(Image(0, 5), InvalidArgument);
}

}  // namespace
}  // namespace geom
