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

}  // namespace geom::codec::detail
