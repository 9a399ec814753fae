#pragma once
/// \file
/// Voronoi diagram of planar points, every cell clipped to a convex region.

#include <geom/compgeom/delaunay2.h>

#include <Eigen/Core>

#include <cstdint>
#include <span>
#include <vector>

namespace geom {

struct VoronoiOptions {
  /// Convex clip polygon, counter-clockwise, at least three vertices. Empty: the bounding
  /// box of the points grown by `margin` of its size on every side (a degenerate box gets
  /// size 1).
  std::vector<Eigen::Vector2d> clip;
  double margin = 0.1;
};

struct VoronoiResult {
  /// cells[i]: the Voronoi cell of point i intersected with the clip polygon,
  /// counter-clockwise; empty for a repeated point (see vertex_of) or when the cell misses
  /// the clip region. The non-empty cells tile the clip polygon.
  std::vector<std::vector<Eigen::Vector2d>> cells;
  std::vector<std::uint32_t> vertex_of;  ///< as in DelaunayResult
  std::vector<Eigen::Vector2d> clip;     ///< the clip polygon used
  DelaunayResult delaunay;               ///< the dual triangulation
};

/// Axis-aligned box as a counter-clockwise polygon.
std::vector<Eigen::Vector2d> box_polygon(double xmin, double ymin, double xmax, double ymax);

/// Voronoi cells as the intersection of the clip polygon with the half-planes of the
/// Delaunay neighbours (the dual of delaunay_2d, so degenerate and cocircular input is safe).
/// Cell vertices are computed in floating point relative to the cell's site.
/// Pre: none on the points (duplicates, collinear input allowed).
/// Throws: InvalidArgument for a non-finite coordinate (names the point) or a clip polygon
///         that is not strictly convex and counter-clockwise, or has non-finite vertices.
/// Complexity: O(n log n) for the triangulation plus O(sum of cell sizes x degree).
/// Ref: F. Aurenhammer, "Voronoi diagrams — a survey", ACM Computing Surveys 23(3), 1991.
VoronoiResult voronoi_2d(std::span<const Eigen::Vector2d> points,
                         const VoronoiOptions& options = {});

}  // namespace geom
