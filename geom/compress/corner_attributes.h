#pragma once
/// \file
/// Per-corner attributes with seams (UV islands, normal creases) on the decoded corner
/// table. One bit per interior edge says whether the attribute jumps across it; corners
/// around a vertex joined by edges without a jump form a *wedge* that holds one value. Each
/// wedge's value is coded once, in decoding order, predicted by parallelograms inside its
/// chart (across edges without a seam), else by a known corner of one of its triangles
/// (triangles never straddle a seam), else by the vertex's previous wedge.
///
/// Ref: M. Isenburg, J. Snoeyink, "Compressing texture coordinates with selective linear
/// predictions", CGI 2003 (seam-aware parallelograms); Draco's mesh attribute corner table
/// (attribute seams as per-edge flags, values per wedge).

#include <geom/compress/connectivity.h>
#include <geom/compress/rans.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace geom::codec::detail {

/// A two-component grid point (texture coordinate or octahedral normal).
using Grid2 = std::array<std::uint32_t, 2>;

/// Code one grid point per corner of `table` (seam bits, then wedge values) into one rANS
/// stream and one raw bit stream. Polygon diagonals carry no bit: both sides are corners of
/// the same polygon and always share the value.
/// Pre: q.size() == table.vertex.size(), every component < 2^bits, 1 ≤ bits ≤ 30; the
/// corners of one polygon at the same vertex hold equal values.
/// Returns: the number of wedges coded. Complexity: O(C α(C)) for C corners.
std::size_t encode_corner_values(const CornerTable& table, std::span<const Grid2> q, unsigned bits,
                                 RansEncoder& rans, BitWriter& raw);

/// Decode one grid point per corner of `table`.
/// Throws: DecodeError naming the byte offset on truncated data or a value off the grid.
/// Complexity: O(C α(C)).
void decode_corner_values(const CornerTable& table, unsigned bits, RansDecoder& rans,
                          BitReader& raw, std::vector<Grid2>& q);

}  // namespace geom::codec::detail
