#include <geom/compress/point_chain.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numeric>

namespace geom::codec::detail {

namespace {

/// Interleaves the top 21 bits of each coordinate (grids have at most 30 bits; the low bits
/// only break ties between points that close).
std::uint64_t morton(const QPoint& p, unsigned shift) {
  std::uint64_t key = 0;
  for (unsigned b = 0; b < 21; ++b)
    for (unsigned a = 0; a < 3; ++a) key |= std::uint64_t{(p[a] >> shift >> b) & 1u} << (3 * b + a);
  return key;
}

std::uint64_t distance2(const QPoint& p, const QPoint& r) {
  std::uint64_t d = 0;
  for (int a = 0; a < 3; ++a) {
    const std::int64_t x = std::int64_t{p[a]} - std::int64_t{r[a]};
    d += static_cast<std::uint64_t>(x * x);
  }
  return d;
}

}  // namespace

std::vector<std::uint32_t> point_chain(std::span<const QPoint> q, unsigned window) {
  const auto n = static_cast<std::uint32_t>(q.size());
  std::vector<std::uint32_t> sorted(n);
  std::iota(sorted.begin(), sorted.end(), 0u);
  if (n <= 2) return sorted;
  std::uint32_t high = 0;
  for (const QPoint& p : q) high |= p[0] | p[1] | p[2];
  const unsigned width = static_cast<unsigned>(std::bit_width(high));
  const unsigned shift = width > 21 ? width - 21 : 0;
  std::vector<std::uint64_t> key(n);
  for (std::uint32_t i = 0; i < n; ++i) key[i] = morton(q[i], shift);
  std::stable_sort(sorted.begin(), sorted.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return key[a] < key[b]; });
  // Unvisited points as a linked list over Morton positions; slot n is the end.
  std::vector<std::uint32_t> next(n + 1), prev(n + 1);
  for (std::uint32_t i = 0; i <= n; ++i) next[i] = i + 1, prev[i] = i == 0 ? n : i - 1;
  std::uint32_t head = 0;
  auto unlink = [&](std::uint32_t i) {
    if (i == head) head = next[i];
    else next[prev[i]] = next[i];
    if (next[i] < n) prev[next[i]] = prev[i];
  };
  std::vector<std::uint32_t> chain;
  chain.reserve(n);
  std::uint32_t current = 0;
  unlink(0);
  chain.push_back(sorted[0]);
  while (chain.size() < n) {
    std::uint32_t best = head;
    std::uint64_t best_d = std::numeric_limits<std::uint64_t>::max();
    std::uint32_t i = head;
    for (unsigned k = 0; k < window && i < n; ++k, i = next[i]) {
      const std::uint64_t d = distance2(q[sorted[i]], q[sorted[current]]);
      if (d < best_d) best_d = d, best = i;
    }
    unlink(best);
    chain.push_back(sorted[best]);
    current = best;
  }
  return chain;
}

std::vector<std::uint32_t> nearest_sites(std::span<const QPoint> sites,
                                         std::span<const QPoint> queries) {
  std::uint32_t lo[3], hi[3];
  for (int a = 0; a < 3; ++a) lo[a] = hi[a] = sites[0][a];
  for (const QPoint& p : sites)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
  std::uint64_t extent = 1;
  for (int a = 0; a < 3; ++a)
    extent = std::max<std::uint64_t>(extent, std::uint64_t{hi[a]} - lo[a] + 1);
  // About two sites a cell; at most 2^8 cells an axis, so the cell table stays small.
  const auto per_axis =
      static_cast<std::uint64_t>(std::clamp(std::cbrt(double(sites.size()) / 2.0), 1.0, 256.0));
  const std::uint64_t cell = (extent + per_axis - 1) / per_axis;
  std::int64_t dim[3];
  for (int a = 0; a < 3; ++a)
    dim[a] = static_cast<std::int64_t>((std::uint64_t{hi[a]} - lo[a]) / cell + 1);
  auto cell_of = [&](const QPoint& p, int a) {
    const std::int64_t x = (std::int64_t{p[a]} - std::int64_t{lo[a]}) / std::int64_t(cell);
    return std::clamp<std::int64_t>(x, 0, dim[a] - 1);  // queries outside the box: the edge
  };
  auto index = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
    return static_cast<std::size_t>((z * dim[1] + y) * dim[0] + x);
  };
  // Sites bucketed by cell (counting sort; ascending index within a cell).
  std::vector<std::uint32_t> start(static_cast<std::size_t>(dim[0] * dim[1] * dim[2]) + 1, 0),
      in_cell(sites.size());
  for (const QPoint& p : sites) ++start[index(cell_of(p, 0), cell_of(p, 1), cell_of(p, 2)) + 1];
  for (std::size_t i = 1; i < start.size(); ++i) start[i] += start[i - 1];
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t i = 0; i < sites.size(); ++i)
      in_cell[fill[index(cell_of(sites[i], 0), cell_of(sites[i], 1), cell_of(sites[i], 2))]++] = i;
  }
  std::vector<std::uint32_t> nearest(queries.size());
  for (std::size_t qi = 0; qi < queries.size(); ++qi) {
    const QPoint& p = queries[qi];
    const std::int64_t c[3] = {cell_of(p, 0), cell_of(p, 1), cell_of(p, 2)};
    std::uint64_t best_d = std::numeric_limits<std::uint64_t>::max();
    std::uint32_t best = 0;
    auto visit = [&](std::int64_t x, std::int64_t y, std::int64_t z) {
      const std::size_t k = index(x, y, z);
      for (std::uint32_t j = start[k]; j < start[k + 1]; ++j) {
        const std::uint32_t s = in_cell[j];
        const std::uint64_t d = distance2(p, sites[s]);
        if (d < best_d || (d == best_d && s < best)) best_d = d, best = s;
      }
    };
    const std::int64_t reach = std::max({dim[0], dim[1], dim[2]});
    for (std::int64_t r = 0; r <= reach; ++r) {
      // The cells at Chebyshev distance r from c; a site beyond them is at least r·cell away.
      for (std::int64_t x = std::max<std::int64_t>(c[0] - r, 0);
           x <= std::min(c[0] + r, dim[0] - 1); ++x)
        for (std::int64_t y = std::max<std::int64_t>(c[1] - r, 0);
             y <= std::min(c[1] + r, dim[1] - 1); ++y) {
          if (std::abs(x - c[0]) == r || std::abs(y - c[1]) == r) {
            for (std::int64_t z = std::max<std::int64_t>(c[2] - r, 0);
                 z <= std::min(c[2] + r, dim[2] - 1); ++z)
              visit(x, y, z);
          } else {
            if (c[2] - r >= 0) visit(x, y, c[2] - r);
            if (r > 0 && c[2] + r < dim[2]) visit(x, y, c[2] + r);
          }
        }
      const double bound = double(r) * double(cell);
      if (best_d != std::numeric_limits<std::uint64_t>::max() && double(best_d) <= bound * bound)
        break;
    }
    nearest[qi] = best;
  }
  return nearest;
}

}  // namespace geom::codec::detail
