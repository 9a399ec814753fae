#include <geom/render/render.h>

#include <geom/render/raster.h>

#include <chrono>
#include <cmath>

namespace geom {
namespace {

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

bool needs_ray_tracing(const Scene& scene) {
  bool has_geometry = false, reflective = false;
  for (const SceneNode& n : scene.nodes) {
    if (n.mesh < 0) continue;
    has_geometry = true;
    if (n.material >= 0 && n.material < static_cast<int>(scene.materials.size()) &&
        scene.materials[n.material].reflectance > 0)
      reflective = true;
  }
  if (!has_geometry) return false;
  for (const Light& l : scene.lights)
    if (l.shadows) return true;
  return reflective;
}

RenderResult render(const Scene& scene, const RenderOptions& options) {
  if (scene.width < 1 || scene.height < 1 || scene.width > 16384 || scene.height > 16384)
    throw InvalidArgument("render: image size must be 1..16384 per side");
  RenderResult result;
  RenderStats& st = result.stats;
  const bool trace = options.path == RenderPath::kRayTrace ||
                     (options.path == RenderPath::kAuto && needs_ray_tracing(scene));
  st.path = trace ? "raytrace" : "raster";

  auto t0 = std::chrono::steady_clock::now();
  detail::FlatScene flat = detail::flatten(scene, scene.wireframe);
  st.normals_computed = flat.smooth;
  st.triangles = flat.tris.size();
  const Camera camera = detail::scene_camera(scene, flat);
  st.seconds_setup = since(t0);

  // The rasteriser supersamples on a k×k grid; the ray tracer jitters k×k samples per pixel.
  const int k = std::max(1, static_cast<int>(std::lround(std::sqrt(scene.samples))));
  const int scale = trace ? 1 : k;
  detail::Frame frame(scene.width * scale, scene.height * scale, scene.background);
  t0 = std::chrono::steady_clock::now();
  if (trace) {
    detail::ray_trace(scene, flat, camera, frame, st);
  } else {
    detail::rasterize(scene, flat, camera, frame);
    st.primary_rays = 0;
  }
  st.seconds_render = since(t0) - st.seconds_bvh;

  if (scene.wireframe) {
    t0 = std::chrono::steady_clock::now();
    detail::Projector proj(camera, frame.width, frame.height, flat.bounds);
    detail::draw_wireframe(flat, proj, scale, frame);
    st.seconds_wireframe = since(t0);
  }
  result.image = detail::resolve(frame, scale);
  return result;
}

}  // namespace geom
