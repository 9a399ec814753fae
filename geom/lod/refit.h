#pragma once
/// \file
/// Refit a simplified mesh's vertex positions to the surface it was simplified from, keeping
/// its connectivity: the "fit" step of Hoppe et al.'s mesh optimisation. Edge collapse places
/// each vertex by the quadrics of the planes it absorbed, which never look at the surface
/// again; refitting measures where the original surface actually lies relative to the
/// simplified triangles and moves vertices to shrink those distances.
///
/// Ref: Hoppe, DeRose, Duchamp, McDonald, Stuetzle, "Mesh Optimization", SIGGRAPH 1993 (§4.2,
/// fit step with fixed connectivity; here point-to-plane, one vertex at a time).

#include <geom/core/surface_mesh.h>

#include <cstddef>
#include <span>

namespace geom {

struct RefitOptions {
  /// Rounds of (project samples, move every free vertex once).
  int iterations = 1;
  /// Regulariser λ·|x − x_current|² relative to the vertex's data weight: keeps directions
  /// the samples do not constrain (tangential ones) where they are.
  double regularization = 1.0;
  /// Surface samples per original triangle on top of its vertices (0: vertices only).
  /// Negative: automatic, 1 while the original has fewer than two vertices per simplified
  /// triangle (a dense output, which its vertices alone fit loosely), else 0.
  int samples_per_triangle = -1;
  /// A move is halved (twice at most, then dropped) when it would raise the local Hausdorff
  /// distance (see refit.cpp), turn a fan triangle by 90° or more, or leave one with quality
  /// 4√3·area/Σ edge² below this (unless it was already worse).
  double min_triangle_quality = 0.02;
};

/// Move the non-boundary vertices of the triangle mesh `simplified` towards the surface
/// `original` (point-to-plane least squares over samples of `original` assigned to their
/// closest simplified triangle; Gauss–Seidel, one 3×3 solve per vertex, blocks of vertices
/// in parallel: the result does not depend on the number of threads). Vertices in `fixed`
/// and boundary vertices do not move; connectivity never changes.
/// `survivor`, when given (simplify() does), names for each vertex of `original` (by index)
/// the vertex of `simplified` it was collapsed into: each sample's closest triangle is then
/// searched by walking from that vertex's fan, not in a tree over all of `simplified`.
/// Throws: InvalidArgument when `original` gives 2^30 samples or more.
/// Complexity: O(iterations · S log F) for S samples and F simplified faces; with
/// `survivor`, O(iterations · S) in practice.
/// Whether refitting `simplified` needs samples inside the original's triangles (see
/// RefitOptions::samples_per_triangle): with fewer than two original vertices per simplified
/// triangle, the vertices alone fit a dense output loosely.
inline bool refit_needs_surface_samples(std::size_t original_vertices,
                                        std::size_t simplified_faces) {
  return original_vertices < 2 * simplified_faces;
}

void refit_to_surface(SurfaceMesh& simplified, const SurfaceMesh& original,
                      const RefitOptions& options = {}, std::span<const Vertex> fixed = {},
                      std::span<const Vertex> survivor = {});

namespace detail {
/// A vertex the refit moves along a line only: through its position, along `direction`.
struct RefitLine {
  Vertex vertex;
  Eigen::Vector3d direction;
};

/// refit_to_surface() with the weights of the original's vertex samples given (simplify()
/// has them from its setup, which sums every triangle's area anyway; the refit's own sum
/// walks the whole input again): vertex_area[i] is a third of the area of input vertex i's
/// triangles (polygons split as the caller split them), 0 for none. Empty, or not sized to
/// original.vertices_size(): computed from `original`. A vertex of `lines` not in `fixed`
/// moves along its line only (simplify(): each attribute-seam vertex along the input's normal
/// there, so that it keeps its place on the seam).
void refit_to_surface(SurfaceMesh& simplified, const SurfaceMesh& original,
                      const RefitOptions& options, std::span<const Vertex> fixed,
                      std::span<const Vertex> survivor, std::span<const double> vertex_area,
                      std::span<const RefitLine> lines);
}  // namespace detail

}  // namespace geom
