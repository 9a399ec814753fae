#include <geom/compgeom/spatial_sort.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace geom::detail {

namespace {

// Hilbert index of (x, y) on a 2^16 x 2^16 grid. The frame of the remaining bits is a
// composition of "flip both axes" (f) and "swap axes" (s); tracking it as two bits keeps
// the loop free of data-dependent branches.
std::uint32_t hilbert2(std::uint32_t x, std::uint32_t y) {
  std::uint32_t d = 0, f = 0, s = 0;
  for (int level = 15; level >= 0; --level) {
    std::uint32_t rx = ((x >> level) & 1u) ^ f;
    std::uint32_t ry = ((y >> level) & 1u) ^ f;
    std::uint32_t t = (rx ^ ry) & s;
    rx ^= t;
    ry ^= t;
    d = (d << 2) | ((3u * rx) ^ ry);
    std::uint32_t m = ry ^ 1u;  // lower half: rotate the frame
    f ^= rx & m;
    s ^= m;
  }
  return d;
}

// Sorts (key, index) by key with two 16-bit counting passes; stable.
std::vector<std::uint32_t> radix_order(const std::vector<std::uint32_t>& key) {
  const std::size_t n = key.size();
  std::vector<std::uint32_t> a(n), b(n);
  for (std::uint32_t i = 0; i < n; ++i) a[i] = i;
  std::vector<std::uint32_t> count(1u << 16);
  for (int pass = 0; pass < 2; ++pass) {
    const int shift = 16 * pass;
    std::fill(count.begin(), count.end(), 0);
    for (std::uint32_t i : a) ++count[(key[i] >> shift) & 0xFFFF];
    std::uint32_t sum = 0;
    for (auto& c : count) {
      std::uint32_t t = c;
      c = sum;
      sum += t;
    }
    for (std::uint32_t i : a) b[count[(key[i] >> shift) & 0xFFFF]++] = i;
    a.swap(b);
  }
  return a;
}

}  // namespace

std::vector<std::uint32_t> hilbert_order_2d(const double* xy, std::size_t n, std::size_t stride) {
  double lo[2] = {std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  double hi[2] = {-lo[0], -lo[1]};
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 2; ++k) {
      lo[k] = std::min(lo[k], xy[i * stride + k]);
      hi[k] = std::max(hi[k], xy[i * stride + k]);
    }
  double ext = std::max(hi[0] - lo[0], hi[1] - lo[1]);
  double scale = ext > 0 ? 65535.0 / ext : 0.0;
  std::vector<std::uint32_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    auto q = [&](int k) {
      double v = (xy[i * stride + k] - lo[k]) * scale;
      if (!(v > 0)) v = 0;  // also NaN, from an overflowing range near the double limits
      return static_cast<std::uint32_t>(std::min(v, 65535.0));
    };
    key[i] = hilbert2(q(0), q(1));
  }
  return radix_order(key);
}

std::vector<std::uint32_t> hilbert_order_3d(const double* xyz, std::size_t n) {
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = std::numeric_limits<double>::infinity(), hi[k] = -lo[k];
  for (std::size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], xyz[3 * i + k]);
      hi[k] = std::max(hi[k], xyz[3 * i + k]);
    }
  double ext = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  double scale = ext > 0 ? 1023.0 / ext : 0.0;
  std::vector<std::uint32_t> key(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t c[3];
    for (int k = 0; k < 3; ++k) {
      double v = (xyz[3 * i + k] - lo[k]) * scale;
      if (!(v > 0)) v = 0;
      c[k] = static_cast<std::uint32_t>(std::min(v, 1023.0));
    }
    // Skilling's transform: Gray-code the axes so interleaved bits follow a Hilbert curve.
    for (std::uint32_t m = 1u << 9; m > 1; m >>= 1) {
      std::uint32_t p = m - 1;
      for (int k = 0; k < 3; ++k) {
        if (c[k] & m) {
          c[0] ^= p;
        } else {
          std::uint32_t t = (c[0] ^ c[k]) & p;
          c[0] ^= t;
          c[k] ^= t;
        }
      }
    }
    for (int k = 1; k < 3; ++k) c[k] ^= c[k - 1];
    std::uint32_t t = 0;
    for (std::uint32_t m = 1u << 9; m > 1; m >>= 1)
      if (c[2] & m) t ^= m - 1;
    for (int k = 0; k < 3; ++k) c[k] ^= t;
    std::uint32_t h = 0;
    for (int bit = 9; bit >= 0; --bit)
      for (int k = 0; k < 3; ++k) h = (h << 1) | ((c[k] >> bit) & 1u);
    key[i] = h;
  }
  return radix_order(key);
}

}  // namespace geom::detail
