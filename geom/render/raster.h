#pragma once
// Internal: the two render paths.

#include <geom/render/frame.h>
#include <geom/render/render.h>

namespace geom::detail {

/// Rasterise and shade (no shadows, no reflections) into the frame.
void rasterize(const Scene& scene, const FlatScene& flat, const Camera& camera, Frame& frame);

/// Ray trace into the frame: jittered samples, shadow rays for lights with shadows, mirror
/// rays for reflective materials. Builds the BVH (counted in stats).
void ray_trace(const Scene& scene, const FlatScene& flat, const Camera& camera, Frame& frame,
               RenderStats& stats);

}  // namespace geom::detail
