#include <geom/compress/attributes.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace geom::codec::detail {

namespace {

double sign_of(double x) { return x < 0 ? -1.0 : 1.0; }

}  // namespace

QPoint octahedral_quantise(const Normal& n, unsigned bits, std::size_t vertex) {
  if (!n.allFinite())
    throw InvalidArgument("compress: normal of vertex " + std::to_string(vertex) + " is not finite");
  const double l1 = n.cwiseAbs().sum();
  double x = 0, y = 0;
  if (l1 > 0) {
    x = n.x() / l1;
    y = n.y() / l1;
    if (n.z() < 0) {
      // Fold the lower half over the diagonals, so the whole sphere fills the square.
      const double fx = (1 - std::abs(y)) * sign_of(x), fy = (1 - std::abs(x)) * sign_of(y);
      x = fx;
      y = fy;
    }
  }
  const double top = static_cast<double>((1u << bits) - 1);
  auto grid = [&](double t) {
    return static_cast<std::uint32_t>(std::clamp(std::lround((t * 0.5 + 0.5) * top), 0L,
                                                 static_cast<long>(top)));
  };
  return {grid(x), grid(y), 0};
}

Normal octahedral_dequantise(const QPoint& q, unsigned bits) {
  const double top = static_cast<double>((1u << bits) - 1);
  double x = q[0] / top * 2 - 1, y = q[1] / top * 2 - 1;
  const double z = 1 - std::abs(x) - std::abs(y);
  if (z < 0) {
    const double fx = (1 - std::abs(y)) * sign_of(x), fy = (1 - std::abs(x)) * sign_of(y);
    x = fx;
    y = fy;
  }
  return Normal(x, y, z).normalized();
}

Quantiser texcoord_quantiser(std::span<const TexCoord> uv, unsigned bits) {
  std::vector<Point> p(uv.size());
  for (std::size_t i = 0; i < uv.size(); ++i) {
    if (!uv[i].allFinite())
      throw InvalidArgument("compress: texture coordinate of vertex " + std::to_string(i) +
                            " is not finite");
    p[i] = Point(uv[i].x(), uv[i].y(), 0.0);
  }
  return quantiser_for_bits(p, bits);
}

void encode_attribute(const CornerTable& table, std::span<const QPoint> q, unsigned bits,
                      std::vector<std::uint8_t>& rans, std::vector<std::uint8_t>& raw) {
  RansEncoder re;
  BitWriter bw;
  encode_positions(table, q, bits, Predictor::kMultiParallelogram, re, bw);
  rans = q.empty() ? std::vector<std::uint8_t>{} : re.finish();
  raw = bw.finish();
}

void decode_attribute(const CornerTable& table, std::size_t n, unsigned bits,
                      std::span<const std::uint8_t> rans, std::uint64_t rans_base,
                      std::span<const std::uint8_t> raw, std::uint64_t raw_base,
                      std::vector<QPoint>& q, unsigned rans_lanes) {
  q.clear();
  if (n == 0) {
    if (!rans.empty() || !raw.empty()) throw DecodeError(rans_base, "attribute data for an empty mesh");
    return;
  }
  RansDecoder rd(rans, rans_base, rans_lanes);
  BitReader br(raw, raw_base);
  decode_positions(table, n, bits, Predictor::kMultiParallelogram, rd, br, q);
  rd.finish();
  for (const QPoint& p : q)
    if (p[2] != 0) throw DecodeError(rans_base, "attribute with a third component");
}

}  // namespace geom::codec::detail
