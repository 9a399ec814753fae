#include <geom/compgeom/hull2.h>
#include <geom/core/errors.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <string>

namespace geom {

namespace {
// Shortest round-trip form: std::to_string prints 1e300 as 301 digits and 1e-300 as 0.000000.
std::string number(double v) {
  char buf[32];
  return std::string(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
}

template <class V>
void check_finite_impl(std::span<const V> points) {
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < V::RowsAtCompileTime; ++k)
      if (!std::isfinite(points[i][k]))
        throw InvalidArgument("point " + std::to_string(i) + " has a non-finite coordinate (" +
                              number(points[i][k]) + "); expected finite numbers");
}

bool lex_less(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
}
}  // namespace

void check_finite(std::span<const Eigen::Vector2d> points) { check_finite_impl(points); }
void check_finite(std::span<const Eigen::Vector3d> points) { check_finite_impl(points); }

namespace {
template <class V>
std::span<const V> in_predicate_range_impl(std::span<const V> points, std::vector<V>& storage) {
  // The exact predicates' products (incircle: degree 4 in differences as small as 2^-53 of
  // a coordinate, with error terms 2^-106 below those) must neither overflow nor underflow:
  // every magnitude at most 2^239, every nonzero one at least 2^-176. A power-of-two scaling
  // that puts the largest at 2^239 meets both for magnitudes down to 2^-400 of the largest;
  // beyond that, no double arithmetic decides exactly.
  constexpr int kTop = 239, kSpan = 400, kBottom = -176;
  double largest = 0, smallest = std::numeric_limits<double>::infinity();
  std::size_t at_smallest = 0;
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < V::RowsAtCompileTime; ++k) {
      const double a = std::abs(points[i][k]);
      largest = std::max(largest, a);
      if (a > 0 && a < smallest) smallest = a, at_smallest = i;
    }
  if (largest == 0) return points;
  if (smallest < std::ldexp(largest, -kSpan))
    throw InvalidArgument("point " + std::to_string(at_smallest) + " has a coordinate of magnitude " +
                          number(smallest) + " beside " + number(largest) +
                          ": coordinates more than 2^400 apart are beyond what exact predicates "
                          "in double arithmetic can decide");
  const int e = std::ilogb(largest);
  if (e <= kTop && std::ilogb(smallest) >= kBottom) return points;  // the usual case: no copy
  // By a power of two (exact: no predicate changes), coordinate by coordinate, since the
  // factor itself may be beyond the double range (2^1226 for a set at 2^-987).
  storage.assign(points.begin(), points.end());
  for (V& p : storage)
    for (int k = 0; k < V::RowsAtCompileTime; ++k) p[k] = std::ldexp(p[k], kTop - e);
  return storage;
}
}  // namespace

std::span<const Eigen::Vector2d> in_predicate_range(std::span<const Eigen::Vector2d> points,
                                                    std::vector<Eigen::Vector2d>& storage) {
  return in_predicate_range_impl(points, storage);
}
std::span<const Eigen::Vector3d> in_predicate_range(std::span<const Eigen::Vector3d> points,
                                                    std::vector<Eigen::Vector3d>& storage) {
  return in_predicate_range_impl(points, storage);
}

Hull2Result convex_hull_2d(std::span<const Eigen::Vector2d> given, const Hull2Options& options) {
  check_finite(given);
  std::vector<Eigen::Vector2d> scaled;
  const std::span<const Eigen::Vector2d> points = in_predicate_range(given, scaled);
  Hull2Result res;
  const std::size_t n = points.size();
  if (n == 0) {
    res.degenerate = true;
    return res;
  }
  std::vector<std::uint32_t> cand;
  cand.reserve(options.prefilter ? n / 8 + 16 : n);
  if (options.prefilter && n > 64) {
    // Extreme points in 16 directions; a point strictly inside their convex polygon cannot
    // be a hull vertex. Ties keep the smallest index so the choice is deterministic.
    constexpr int kDirs = 16;
    double dx[kDirs], dy[kDirs], best[kDirs];
    std::uint32_t ext[kDirs];
    for (int k = 0; k < kDirs; ++k) {
      dx[k] = std::cos(2 * 3.14159265358979323846 * k / kDirs);
      dy[k] = std::sin(2 * 3.14159265358979323846 * k / kDirs);
      best[k] = dx[k] * points[0].x() + dy[k] * points[0].y();
      ext[k] = 0;
    }
    for (std::uint32_t i = 1; i < n; ++i) {
      const double x = points[i].x(), y = points[i].y();
      for (int k = 0; k < kDirs; ++k) {
        double v = dx[k] * x + dy[k] * y;
        if (v > best[k]) best[k] = v, ext[k] = i;
      }
    }
    // The extremes, in direction order, are hull vertices in counter-clockwise order
    // (possibly repeated, or collinear, which only weakens the filter).
    std::vector<std::uint32_t> poly;
    for (int k = 0; k < kDirs; ++k)
      if (poly.empty() || points[poly.back()] != points[ext[k]]) poly.push_back(ext[k]);
    while (poly.size() > 1 && points[poly.front()] == points[poly.back()]) poly.pop_back();
    const std::size_t m = poly.size();
    // A disc certainly inside the polygon rejects most points without orientation tests:
    // its radius is the smallest centre-to-edge distance, shrunk by a bound on the rounding
    // of these floating-point distances.
    Eigen::Vector2d c(0, 0);
    for (std::uint32_t v : poly) c += points[v];
    c /= double(std::max<std::size_t>(m, 1));
    double r = m >= 3 ? std::numeric_limits<double>::infinity() : 0.0;
    double mag = std::fabs(c.x()) + std::fabs(c.y());
    for (std::size_t k = 0; k < m && m >= 3; ++k) {
      const Eigen::Vector2d& a = points[poly[k]];
      const Eigen::Vector2d& b = points[poly[(k + 1) % m]];
      mag = std::max(mag, std::fabs(a.x()) + std::fabs(a.y()));
      Eigen::Vector2d e = b - a;
      double len = e.norm();
      if (!(len > 0)) continue;
      r = std::min(r, (e.x() * (c.y() - a.y()) - e.y() * (c.x() - a.x())) / len);
    }
    double safe = r * (1 - 1e-9) - 1e-12 * mag;
    const double safe2 = safe > 0 ? safe * safe : -1.0;
    for (std::uint32_t i = 0; i < n; ++i) {
      const Eigen::Vector2d& q = points[i];
      if ((q - c).squaredNorm() < safe2) continue;
      const double* p = q.data();
      bool inside = m >= 3;
      for (std::size_t k = 0; k < m && inside; ++k)
        inside = orient2d(points[poly[k]].data(), points[poly[(k + 1) % m]].data(), p,
                          res.predicates) > 0;
      if (!inside) cand.push_back(i);
    }
  } else {
    for (std::uint32_t i = 0; i < n; ++i) cand.push_back(i);
  }
  res.candidates = cand.size();
  std::sort(cand.begin(), cand.end(), [&](std::uint32_t a, std::uint32_t b) {
    return lex_less(points[a], points[b]) || (points[a] == points[b] && a < b);
  });
  // Keep the first (smallest-index) copy of each repeated point.
  cand.erase(std::unique(cand.begin(), cand.end(),
                         [&](std::uint32_t a, std::uint32_t b) { return points[a] == points[b]; }),
             cand.end());
  if (cand.size() <= 2) {
    res.vertices = cand;
    res.degenerate = true;
    return res;
  }
  std::vector<std::uint32_t> h(2 * cand.size());
  std::size_t k = 0;
  auto turn = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    return orient2d(points[a].data(), points[b].data(), points[c].data(), res.predicates);
  };
  for (std::uint32_t i : cand) {  // lower chain
    while (k >= 2 && turn(h[k - 2], h[k - 1], i) <= 0) --k;
    h[k++] = i;
  }
  const std::size_t lower = k + 1;
  for (std::size_t j = cand.size() - 1; j-- > 0;) {  // upper chain
    std::uint32_t i = cand[j];
    while (k >= lower && turn(h[k - 2], h[k - 1], i) <= 0) --k;
    h[k++] = i;
  }
  h.resize(k - 1);  // the last point repeats the first
  res.vertices = std::move(h);
  res.degenerate = res.vertices.size() < 3;
  return res;
}

}  // namespace geom
