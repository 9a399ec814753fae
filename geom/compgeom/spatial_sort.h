#pragma once
/// \file
/// Hilbert-curve order of points (internal to compgeom): consecutive points are close, so a
/// walk from the previous insertion is short.

#include <cstdint>
#include <vector>

namespace geom::detail {

/// Indices 0..n-1 ordered along a Hilbert curve over the bounding box of the points
/// (xy holds x0, y0, x1, y1, ...; `stride` doubles per point, the first two used).
/// Complexity: O(n) (two radix passes over 32-bit keys).
std::vector<std::uint32_t> hilbert_order_2d(const double* xy, std::size_t n, std::size_t stride);

/// The same over three coordinates (a 3D Hilbert curve, 10 bits per axis).
std::vector<std::uint32_t> hilbert_order_3d(const double* xyz, std::size_t n);

}  // namespace geom::detail
