#pragma once
/// \file
/// Delaunay triangulation of planar points, optionally with constrained edges.

#include <geom/predicates/predicates.h>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace geom {

struct DelaunayOptions {
  /// Exact-adaptive predicates (the default). false uses the plain floating-point
  /// determinants; it exists to measure what exactness costs, and may produce an invalid
  /// triangulation or throw geom::Error on near-degenerate input.
  bool exact = true;
};

struct DelaunayResult {
  /// Counter-clockwise triangles; indices refer to the input points (a repeated point is
  /// represented by its first copy).
  std::vector<std::array<std::uint32_t, 3>> triangles;
  /// For every input point, the input index of the point that represents it (itself unless
  /// it repeats an earlier point exactly).
  std::vector<std::uint32_t> vertex_of;
  std::size_t vertices = 0;    ///< distinct points
  std::size_t duplicates = 0;  ///< input points merged into an earlier copy
  /// True when the distinct points are collinear (or fewer than three): no triangles; the
  /// points are then listed in `chain`, sorted along the line (lexicographically).
  bool collinear = false;
  std::vector<std::uint32_t> chain;
  /// In-circle tests that were exactly zero (cocircular points) and were decided by
  /// symbolic perturbation.
  std::size_t cocircular = 0;
  PredicateStats predicates;
};

/// Delaunay triangulation of points: spatial sort along a Hilbert curve, then incremental
/// insertion (Bowyer-Watson cavities) with a visibility walk from the previous insertion.
/// Cocircular points are resolved by Simulation of Simplicity on the insertion rank (the
/// Hilbert order, itself a deterministic function of the input), so the result is the
/// Delaunay triangulation of infinitesimally lifted points: deterministic for a given input.
/// Pre: none (duplicates, collinear input, 0, 1 or 2 points allowed).
/// Throws: InvalidArgument when a coordinate is NaN or infinite (names the point index);
///         also when nonzero coordinates are more than 2^400 apart (in_predicate_range);
///         any other range is scaled exactly, without changing the result.
///         geom::Error only with options.exact = false, when the inexact predicates make the
///         point location loop.
/// Complexity: O(n log n) expected for well-distributed points.
/// Ref: A. Bowyer, "Computing Dirichlet tessellations", 1981; D. F. Watson, 1981;
///      O. Devillers, S. Pion, M. Teillaud, "Walking in a triangulation", 2002.
DelaunayResult delaunay_2d(std::span<const Eigen::Vector2d> points,
                           const DelaunayOptions& options = {});

/// An edge that a constrained triangulation must contain, by input point indices.
struct Segment {
  std::uint32_t a = 0, b = 0;
};

struct ConstrainedDelaunayResult : DelaunayResult {
  /// The constrained edges present in the triangulation (input indices, representative
  /// points); a segment that passes exactly through input points appears as several edges.
  std::vector<Segment> constrained_edges;
  /// Segments that were split at input points lying exactly on them.
  std::size_t split_segments = 0;
};

/// Constrained Delaunay triangulation: the Delaunay triangulation, then each segment is
/// forced in by flipping the edges it crosses, then Delaunay flips restore the constrained
/// Delaunay property. No point is added. A segment that passes exactly through an input
/// point is split there.
/// Pre: segments reference valid indices.
/// Throws: InvalidArgument for a non-finite coordinate, an out-of-range index, a segment
///         whose endpoints coincide, or two segments that cross (the message names both).
/// Complexity: O(n log n + k) expected, k the number of crossed edges.
/// Ref: S. W. Sloan, "A fast algorithm for generating constrained Delaunay triangulations",
///      Computers & Structures 47(3), 1993.
ConstrainedDelaunayResult constrained_delaunay_2d(std::span<const Eigen::Vector2d> points,
                                                  std::span<const Segment> segments,
                                                  const DelaunayOptions& options = {});

/// Checks that `triangles` is the Delaunay triangulation of `points` (with the repeated
/// points merged into their representatives): every triangle counter-clockwise, every edge
/// shared by at most two triangles, the boundary one convex loop, the triangle count
/// 2n - h - 2, every interior edge locally Delaunay under the exact in-circle test
/// (edges in `constrained` are exempt). Returns an empty string when all hold, else a
/// description of the first failure.
/// Throws: InvalidArgument, naming the point, on a non-finite coordinate or on coordinates
/// more than 2^400 apart (as delaunay_2d does).
/// Complexity: O(n log n).
std::string check_delaunay_2d(std::span<const Eigen::Vector2d> points,
                              std::span<const std::array<std::uint32_t, 3>> triangles,
                              std::span<const Segment> constrained = {});

}  // namespace geom
