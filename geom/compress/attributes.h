#pragma once
/// \file
/// Per-vertex attributes of the mesh codec: normals by octahedral quantisation, texture
/// coordinates on a uniform grid. Both become two-component grid points and travel through
/// the position coder (multi-parallelogram prediction on the decoded connectivity, residual
/// lengths rANS-coded), with the third component always 0.
///
/// Ref: Q. Meyer et al., "On floating-point normal vectors", EGSR 2010 (octahedral mapping);
/// Z. Cigolle et al., "A survey of efficient representations for independent unit vectors",
/// JCGT 3(2), 2014.

#include <geom/compress/predict.h>
#include <geom/compress/quantise.h>
#include <geom/core/surface_mesh.h>

#include <span>
#include <vector>

namespace geom::codec::detail {

/// Octahedral grid point of a normal (any length; a zero normal maps to +z), u, v < 2^bits.
/// Throws: InvalidArgument naming `vertex` for a non-finite normal.
QPoint octahedral_quantise(const Normal& n, unsigned bits, std::size_t vertex);
/// The unit normal of an octahedral grid point.
Normal octahedral_dequantise(const QPoint& q, unsigned bits);

/// The grid of the texture coordinates: 2^bits − 1 steps across their larger extent.
/// Throws: InvalidArgument naming the vertex of a non-finite coordinate.
Quantiser texcoord_quantiser(std::span<const TexCoord> uv, unsigned bits);

/// Code grid points (decoded vertex order, third component 0) with multi-parallelogram
/// prediction on `table`. Returns the rANS and raw byte streams.
void encode_attribute(const CornerTable& table, std::span<const QPoint> q, unsigned bits,
                      std::vector<std::uint8_t>& rans, std::vector<std::uint8_t>& raw);

/// Decode n grid points; base offsets locate the two sections in the whole buffer.
/// Throws: DecodeError on truncated data, a value off the grid or a non-zero third component.
void decode_attribute(const CornerTable& table, std::size_t n, unsigned bits,
                      std::span<const std::uint8_t> rans, std::uint64_t rans_base,
                      std::span<const std::uint8_t> raw, std::uint64_t raw_base,
                      std::vector<QPoint>& q, unsigned rans_lanes = 2);

}  // namespace geom::codec::detail
