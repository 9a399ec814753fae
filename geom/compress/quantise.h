#pragma once
/// \file
/// Uniform quantisation of positions on a grid anchored at the bounding box's minimum corner.
/// The grid step is the same on all three axes, so the error bound is isotropic: every
/// coordinate comes back within step/2 of the original.

#include <geom/core/surface_mesh.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace geom::codec {

/// The grid: q = round((p − origin) / step), p' = origin + q · step, 0 ≤ q < 2^bits.
struct Quantiser {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  double step = 1.0;
  unsigned bits = 11;

  /// Largest distance of a dequantised coordinate from the original (per axis).
  double max_error() const { return 0.5 * step; }
  std::array<std::uint32_t, 3> quantise(const Point& p) const;
  Point dequantise(const std::array<std::uint32_t, 3>& q) const {
    return origin + step * Eigen::Vector3d(q[0], q[1], q[2]);
  }
  /// dequantise() rounded to floats, written to out[0..3) (the flat decoder's output).
  void dequantise_into(const std::array<std::uint32_t, 3>& q, float* out) const {
    for (int a = 0; a < 3; ++a) out[a] = static_cast<float>(origin[a] + step * q[a]);
  }
};

/// A grid with 2^bits − 1 steps across the largest bounding-box extent.
/// Pre: 1 ≤ bits ≤ 30; finite coordinates.
/// Throws: InvalidArgument when bits is out of range or a coordinate is not finite.
/// Complexity: O(n).
Quantiser quantiser_for_bits(std::span<const Point> points, unsigned bits);

/// A grid whose step is 2·precision, so every coordinate is within `precision` of the
/// original however long the object is; bits is the smallest count that covers the box.
/// Pre: precision > 0 and the box needs at most 30 bits at that precision.
/// Throws: InvalidArgument otherwise (the message gives the bits the box would need).
/// Complexity: O(n).
Quantiser quantiser_for_precision(std::span<const Point> points, double precision);

}  // namespace geom::codec
