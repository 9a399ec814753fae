#pragma once
/// \file
/// The preview renderer. It does only what the scene asks for: a scene without shadowed
/// lights or mirror materials is rasterised and builds no BVH; shadow rays are cast only for
/// lights with `shadows`, reflection rays only for materials with reflectance > 0. The stats
/// say which path ran and what it cost.

#include <geom/render/image.h>
#include <geom/render/scene.h>

#include <cstdint>
#include <string>

namespace geom {

enum class RenderPath { kAuto, kRaster, kRayTrace };

struct RenderOptions {
  /// kAuto: ray trace only when a light casts shadows or a material reflects.
  RenderPath path = RenderPath::kAuto;
};

struct RenderStats {
  std::string path;  ///< "raster" or "raytrace"
  bool bvh_built = false;
  bool normals_computed = false;  ///< smooth corner normals were derived
  std::size_t triangles = 0;
  std::uint64_t primary_rays = 0, shadow_rays = 0, reflection_rays = 0;
  double seconds_setup = 0;    ///< flattening the scene, normals
  double seconds_bvh = 0;
  double seconds_render = 0;   ///< rasterising or tracing, shading
  double seconds_wireframe = 0;
};

struct RenderResult {
  Image image;
  RenderStats stats;
};

/// Render the scene. Throws: InvalidArgument when the scene is inconsistent (a node
/// referring to a missing mesh or material, a cycle in the hierarchy).
/// Complexity: O(T log T) for T triangles when ray tracing (BVH), O(T + pixels) rasterised.
/// Ref: Blinn, "Models of Light Reflection for Computer Synthesized Pictures", 1977;
/// Whitted, "An Improved Illumination Model for Shaded Display", 1980.
RenderResult render(const Scene& scene, const RenderOptions& options = {});

/// Does this scene need ray tracing (shadowed lights or reflective materials in use)?
bool needs_ray_tracing(const Scene& scene);

}  // namespace geom
