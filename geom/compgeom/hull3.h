#pragma once
/// \file
/// Convex hull of points in space (exact orientation tests).

#include <geom/core/surface_mesh.h>
#include <geom/predicates/predicates.h>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace geom {

struct Hull3Result {
  /// Boundary triangles, counter-clockwise seen from outside, over input indices. Coplanar
  /// facets are triangulated without adding or dropping points. Empty unless dimension == 3.
  std::vector<std::array<std::uint32_t, 3>> triangles;
  /// The extreme points (hull vertices), ascending. Points on hull edges or faces and
  /// repeated copies are excluded; a repeated extreme point is represented by its first copy.
  std::vector<std::uint32_t> vertices;
  /// Affine dimension of the input: -1 empty, 0 one distinct point, 1 collinear, 2 coplanar
  /// (then `planar` is set), 3 solid.
  int dimension = -1;
  /// All points coplanar: `polygon` is the planar hull (extreme points only),
  /// counter-clockwise seen from the positive side of coordinate axis `projection_axis`
  /// (0 = x, 1 = y, 2 = z), an axis the plane is not parallel to.
  bool planar = false;
  std::vector<std::uint32_t> polygon;
  int projection_axis = -1;
  /// Points that were not extreme but became vertices of the first pass (they lie on hull
  /// edges or coplanar facets); a second pass over the extreme points removed them.
  std::size_t non_extreme_removed = 0;
  PredicateStats predicates;
};

/// Convex hull by Quickhull with conflict lists, every visibility decision by exact orient3d
/// (a point sees a face only when strictly above its plane).
/// Pre: none (duplicates, coplanar, collinear and empty input allowed).
/// Throws: InvalidArgument when a coordinate is NaN or infinite (names the point).
///         also when nonzero coordinates are more than 2^400 apart (in_predicate_range);
///         any other range is scaled exactly, without changing the result.
/// Complexity: O(n log n) expected; O(n h) worst case.
/// Ref: C. B. Barber, D. P. Dobkin, H. Huhdanpaa, "The Quickhull algorithm for convex
///      hulls", ACM TOMS 22(4), 1996.
Hull3Result convex_hull_3d(std::span<const Eigen::Vector3d> points);

/// The hull as a closed triangle mesh whose vertices are the hull vertices (in ascending
/// input order); empty for dimension < 3.
SurfaceMesh hull_mesh(std::span<const Eigen::Vector3d> points, const Hull3Result& hull);

}  // namespace geom
