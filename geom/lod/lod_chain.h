#pragma once
/// \file
/// LOD chains for renderers: a few levels of one mesh, each with its measured error
/// (sampled symmetric Hausdorff and RMS distance to the input).

#include <geom/core/surface_mesh.h>
#include <geom/lod/simplify.h>
#include <geom/spatial/distance.h>

#include <vector>

namespace geom {

struct LodLevel {
  SurfaceMesh mesh;
  double ratio = 1.0;          ///< requested fraction of the input's triangles
  std::size_t faces = 0;       ///< achieved triangle count
  MeshDistance error;          ///< measured against the input (zeros when not measured)
};

struct LodChainOptions {
  /// Fractions of the input's triangle count, each in (0, 1], any order.
  std::vector<double> ratios{0.5, 0.25, 0.125, 0.0625};
  /// Settings for the collapses (its target fields are ignored).
  SimplifyOptions simplify{};
  /// Measure each level's distance to the input.
  bool measure = true;
  DistanceOptions distance{};
};

/// Levels of detail, each a coarsening of the next finer one; levels come out in the order
/// of options.ratios. Without attributes they come from one collapse sequence (a progressive
/// mesh); with attributes (options.simplify's, or those the mesh holds when keep_attributes)
/// each level is simplify() of the next finer one, so every level carries them, seams kept.
/// Throws: InvalidArgument when a ratio is outside (0, 1] or as simplify() does.
/// Complexity: O(F log F + levels × (F + S log F)) with S distance samples.
std::vector<LodLevel> lod_chain(const SurfaceMesh& mesh, const LodChainOptions& options = {});

}  // namespace geom
