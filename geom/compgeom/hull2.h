#pragma once
/// \file
/// Convex hull of a planar point set (exact orientation tests).

#include <geom/predicates/predicates.h>

#include <Eigen/Core>

#include <cstdint>
#include <span>
#include <vector>

namespace geom {

struct Hull2Options {
  /// Discard points inside the octagon of extreme points before sorting (Akl-Toussaint);
  /// the result is identical either way.
  bool prefilter = true;
};

struct Hull2Result {
  /// Indices of the extreme points, counter-clockwise, starting at the lexicographically
  /// smallest (x, then y). Points on hull edges and repeated copies are not included (for
  /// repeated extreme points the smallest index is reported). One vertex for a single
  /// distinct point, two for collinear input, none for empty input.
  std::vector<std::uint32_t> vertices;
  /// True when the hull has no interior (fewer than three extreme points).
  bool degenerate = false;
  /// Points passed to the sort after the prefilter.
  std::size_t candidates = 0;
  PredicateStats predicates;
};

/// Convex hull of points by Andrew's monotone chain with exact orient2d.
/// Pre: none (any count, duplicates and collinear points allowed).
/// Throws: InvalidArgument when a coordinate is NaN or infinite (the message names the point).
/// Complexity: O(n log n); O(n) for the prefilter plus a sort of the surviving points.
/// Ref: A. M. Andrew, "Another efficient algorithm for convex hulls in two dimensions",
///      IPL 9(5), 1979; S. G. Akl, G. T. Toussaint, "A fast convex hull algorithm", IPL 7(5), 1978.
Hull2Result convex_hull_2d(std::span<const Eigen::Vector2d> points,
                           const Hull2Options& options = {});

/// Throws InvalidArgument naming the first point with a non-finite coordinate.
void check_finite(std::span<const Eigen::Vector2d> points);
void check_finite(std::span<const Eigen::Vector3d> points);

/// The points as the exact predicates can take them: the points themselves, or, when a
/// coordinate magnitude is above 2^239 or a nonzero one below 2^-176, a copy (in `storage`)
/// scaled by a power of two that puts the largest at 2^239. Outside that window the products
/// inside incircle (degree 4) overflow or underflow and its signs are garbage; a power-of-two
/// scaling is exact, so every predicate keeps its sign and the triangulation its triangles.
/// Throws: InvalidArgument naming a point when a nonzero coordinate is more than 2^400 times
/// smaller than the largest (1 beside 1e300): no double arithmetic decides those exactly.
std::span<const Eigen::Vector2d> in_predicate_range(std::span<const Eigen::Vector2d> points,
                                                    std::vector<Eigen::Vector2d>& storage);
std::span<const Eigen::Vector3d> in_predicate_range(std::span<const Eigen::Vector3d> points,
                                                    std::vector<Eigen::Vector3d>& storage);

}  // namespace geom
