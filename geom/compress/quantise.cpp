#include <geom/compress/quantise.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace geom::codec {

namespace {

struct Box {
  Eigen::Vector3d lo, hi;
};

Box bounds(std::span<const Point> points) {
  Box b{Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()};
  if (points.empty()) return b;
  b.lo = b.hi = points[0];
  for (const Point& p : points) {
    if (!p.allFinite()) throw InvalidArgument("quantise: a position is not finite");
    b.lo = b.lo.cwiseMin(p);
    b.hi = b.hi.cwiseMax(p);
  }
  return b;
}

}  // namespace

std::array<std::uint32_t, 3> Quantiser::quantise(const Point& p) const {
  const double top = static_cast<double>((std::uint64_t{1} << bits) - 1);
  std::array<std::uint32_t, 3> q;
  for (int a = 0; a < 3; ++a) {
    const double t = std::round((p[a] - origin[a]) / step);
    // NaN (never expected from a grid built here) maps to cell 0 rather than to undefined
    // behaviour in the conversion.
    q[a] = t >= 0 ? static_cast<std::uint32_t>(std::min(t, top)) : 0;
  }
  return q;
}

Quantiser quantiser_for_bits(std::span<const Point> points, unsigned bits) {
  if (bits < 1 || bits > 30)
    throw InvalidArgument("quantisation bits must be in [1, 30], got " + std::to_string(bits));
  const Box b = bounds(points);
  const double extent = (b.hi - b.lo).maxCoeff();
  Quantiser q;
  q.origin = b.lo;
  q.bits = bits;
  const double steps = static_cast<double>((std::uint64_t{1} << bits) - 1);
  q.step = extent > 0 ? extent / steps : 1.0;
  // Extremes of double: an extent of a few subnormals divides to zero (every cell would be
  // 0/0), and coordinates near ±1e308 can span more than a double holds, so no grid over
  // them could be decoded.
  if (!std::isfinite(extent))
    throw InvalidArgument("quantise: the coordinates span more than a double can hold");
  if (!(q.step > 0)) q.step = extent > 0 ? extent : 1.0;
  return q;
}

Quantiser quantiser_for_precision(std::span<const Point> points, double precision) {
  if (!(precision > 0) || !std::isfinite(precision))
    throw InvalidArgument("quantisation precision must be positive and finite");
  const Box b = bounds(points);
  const double extent = (b.hi - b.lo).maxCoeff();
  Quantiser q;
  q.origin = b.lo;
  q.step = 2.0 * precision;
  const double cells = std::ceil(extent / q.step) + 1.0;
  unsigned bits = 1;
  while (bits <= 30 && static_cast<double>(std::uint64_t{1} << bits) < cells) ++bits;
  if (bits > 30)
    throw InvalidArgument("precision " + std::to_string(precision) + " over an extent of " +
                          std::to_string(extent) + " needs more than 30 bits per coordinate");
  q.bits = bits;
  return q;
}

}  // namespace geom::codec
