#include <geom/compress/point_chain.h>

#include <algorithm>
#include <bit>
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

}  // namespace geom::codec::detail
