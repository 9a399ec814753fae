// An independent checker of Delaunay triangulations, used by the tests and the benchmark's
// "what accuracy costs" table. Everything is decided by exact predicates.

#include <geom/compgeom/delaunay2.h>
#include <geom/compgeom/hull2.h>

#include <algorithm>
#include <string>
#include <tuple>

namespace geom {

namespace {
std::string edge_name(std::uint32_t a, std::uint32_t b) {
  return "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")";
}
}  // namespace

std::string check_delaunay_2d(std::span<const Eigen::Vector2d> given,
                              std::span<const std::array<std::uint32_t, 3>> triangles,
                              std::span<const Segment> constrained) {
  check_finite(given);  // as delaunay_2d refuses them: NaN would compare as collinear
  std::vector<Eigen::Vector2d> scaled;  // as delaunay_2d scales them
  const std::span<const Eigen::Vector2d> points = in_predicate_range(given, scaled);
  const std::size_t n = points.size();
  // Representatives: the first copy of each repeated point.
  std::vector<std::uint32_t> s(n), rep(n);
  for (std::uint32_t i = 0; i < n; ++i) s[i] = i;
  std::sort(s.begin(), s.end(), [&](std::uint32_t a, std::uint32_t b) {
    const auto &p = points[a], &q = points[b];
    return std::tie(p.x(), p.y(), a) < std::tie(q.x(), q.y(), b);
  });
  std::size_t distinct = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (i > 0 && points[s[i]] == points[rep[s[i - 1]]]) {
      rep[s[i]] = rep[s[i - 1]];
    } else {
      rep[s[i]] = s[i];
      ++distinct;
    }
  }
  if (triangles.empty()) {
    for (std::size_t i = 2; i < n; ++i)
      if (orient2d(points[s[0]], points[s[n - 1]], points[s[i]]) != 0 && distinct >= 3)
        return "no triangles, but the points are not collinear (point " + std::to_string(s[i]) +
               ")";
    return {};
  }
  struct E {
    std::uint32_t lo, hi, t;
    int i;  // edge opposite corner i of triangle t
  };
  std::vector<E> edges;
  edges.reserve(3 * triangles.size());
  std::vector<std::uint8_t> used(n, 0);
  for (std::uint32_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    for (std::uint32_t x : tri) {
      if (x >= n) return "triangle " + std::to_string(t) + " has an out-of-range index";
      if (rep[x] != x) return "triangle " + std::to_string(t) + " uses a repeated point";
      used[x] = 1;
    }
    if (orient2d(points[tri[0]], points[tri[1]], points[tri[2]]) <= 0)
      return "triangle " + std::to_string(t) + " is not counter-clockwise";
    for (int i = 0; i < 3; ++i) {
      std::uint32_t a = tri[(i + 1) % 3], b = tri[(i + 2) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), t, i});
    }
  }
  for (std::uint32_t i = 0; i < n; ++i)
    if (rep[i] == i && !used[i]) return "point " + std::to_string(i) + " is not a vertex";
  std::sort(edges.begin(), edges.end(),
            [](const E& x, const E& y) { return std::tie(x.lo, x.hi) < std::tie(y.lo, y.hi); });
  std::vector<std::pair<std::uint32_t, std::uint32_t>> cons;
  for (const Segment& sg : constrained)
    cons.push_back({std::min(sg.a, sg.b), std::max(sg.a, sg.b)});
  std::sort(cons.begin(), cons.end());
  std::vector<std::uint32_t> next(n, 0xFFFFFFFFu);
  std::size_t boundary = 0;
  for (std::size_t k = 0; k < edges.size();) {
    std::size_t m = k;
    while (m < edges.size() && edges[m].lo == edges[k].lo && edges[m].hi == edges[k].hi) ++m;
    const E& e = edges[k];
    if (m - k > 2) return edge_name(e.lo, e.hi) + " has more than two triangles";
    const auto& t0 = triangles[e.t];
    std::uint32_t a = t0[(e.i + 1) % 3], b = t0[(e.i + 2) % 3];
    if (m - k == 1) {
      if (next[a] != 0xFFFFFFFFu)
        return "boundary is not a simple loop at point " + std::to_string(a);
      next[a] = b;
      ++boundary;
    } else {
      const E& f = edges[k + 1];
      const auto& t1 = triangles[f.t];
      if (t1[(f.i + 1) % 3] != b) return edge_name(a, b) + " is used twice in the same direction";
      bool is_constrained =
          std::binary_search(cons.begin(), cons.end(), std::make_pair(e.lo, e.hi));
      if (!is_constrained &&
          incircle(points[t0[0]], points[t0[1]], points[t0[2]], points[t1[f.i]]) > 0)
        return edge_name(a, b) + " is not locally Delaunay";
    }
    k = m;
  }
  // One convex boundary loop.
  std::uint32_t start = 0;
  while (next[start] == 0xFFFFFFFFu) ++start;
  std::size_t len = 0;
  std::uint32_t a = start;
  do {
    std::uint32_t b = next[a];
    if (b == 0xFFFFFFFFu) return "boundary is open at point " + std::to_string(a);
    std::uint32_t c = next[b];
    if (c == 0xFFFFFFFFu) return "boundary is open at point " + std::to_string(b);
    if (orient2d(points[a], points[b], points[c]) < 0)
      return "boundary is not convex at point " + std::to_string(b);
    a = b;
    if (++len > boundary) break;
  } while (a != start);
  if (len != boundary) return "boundary has more than one loop";
  if (triangles.size() != 2 * distinct - boundary - 2)
    return "triangle count " + std::to_string(triangles.size()) +
           " differs from 2n - h - 2 = " + std::to_string(2 * distinct - boundary - 2);
  return {};
}

}  // namespace geom
