#pragma once
/// \file
/// Welding: which positions are to be merged into one vertex.

#include <geom/core/surface_mesh.h>

#include <cstdint>
#include <span>
#include <vector>

namespace geom {

/// For each position, the index of the vertex it merges into: the lowest index among the
/// positions connected to it by chains of pairs at distance ≤ tolerance (an absolute
/// distance; 0 merges exactly equal coordinates only, with -0 equal to +0). Non-finite
/// positions never merge. result[i] == i for positions that stay.
/// Pre: tolerance ≥ 0.
/// Throws: InvalidArgument when tolerance is negative or not finite.
/// Complexity: O(n log n) plus the close pairs examined (a grid of cell size tolerance).
std::vector<std::uint32_t> weld_map(std::span<const Point> positions, double tolerance);

}  // namespace geom
