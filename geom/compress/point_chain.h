#pragma once
/// \file
/// An order for points that are coded as deltas from the point before them: the isolated
/// (face-less) vertices, which have no connectivity to predict from. A chain through near
/// neighbours makes the deltas short (on the Stanford bunny's 1113 isolated scan points about
/// 21 bits per point against 33 in file order). Encoder-side only: the decoder simply reads
/// the points in stream order.

#include <geom/compress/predict.h>

#include <cstdint>
#include <span>
#include <vector>

namespace geom::codec::detail {

/// A greedy chain: start at the point first in Morton order, then repeatedly step to the
/// nearest (Euclidean) of the next `window` unvisited points in Morton order (ties: the
/// earlier in Morton order). Returns indices into q, a permutation. Deterministic.
/// Complexity: O(n log n + n · window).
std::vector<std::uint32_t> point_chain(std::span<const QPoint> q, unsigned window = 32);

/// For each query point, the index of a nearest site (Euclidean; ties: the lowest index):
/// the anchors of isolated vertices near a scanned surface (predictor 5). Exact, over a
/// uniform grid of cells holding about two sites each, searched in growing shells.
/// Pre: sites is not empty. Complexity: O(S + Q · (cells and sites within the answer's
/// reach)); a query far outside the sites' box visits more cells.
std::vector<std::uint32_t> nearest_sites(std::span<const QPoint> sites,
                                         std::span<const QPoint> queries);

}  // namespace geom::codec::detail
