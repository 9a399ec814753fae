#include <geom/compgeom/hull2.h>
#include <geom/compgeom/voronoi2.h>
#include <geom/core/errors.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace geom {

std::vector<Eigen::Vector2d> box_polygon(double xmin, double ymin, double xmax, double ymax) {
  return {{xmin, ymin}, {xmax, ymin}, {xmax, ymax}, {xmin, ymax}};
}

namespace {

using V2 = Eigen::Vector2d;

// Keeps the part of `poly` where (x - site) . d <= |d|^2 / 2, i.e. closer to site than to
// site + d. Working relative to the site keeps the arithmetic small for offset inputs.
void clip_halfplane(std::vector<V2>& poly, std::vector<V2>& tmp, const V2& site, const V2& d) {
  const double c = 0.5 * d.squaredNorm();
  tmp.clear();
  const std::size_t m = poly.size();
  for (std::size_t k = 0; k < m; ++k) {
    const V2& a = poly[k];
    const V2& b = poly[(k + 1) % m];
    double fa = (a - site).dot(d) - c, fb = (b - site).dot(d) - c;
    if (fa <= 0) tmp.push_back(a);
    if ((fa < 0 && fb > 0) || (fa > 0 && fb < 0)) {
      double t = fa / (fa - fb);
      tmp.push_back(a + t * (b - a));
    }
  }
  poly.swap(tmp);
}

}  // namespace

VoronoiResult voronoi_2d(std::span<const Eigen::Vector2d> points, const VoronoiOptions& options) {
  check_finite(points);
  VoronoiResult res;
  const std::size_t n = points.size();
  if (!options.clip.empty()) {
    const auto& c = options.clip;
    check_finite(std::span<const V2>(c));
    if (c.size() < 3)
      throw InvalidArgument("voronoi_2d: clip polygon has " + std::to_string(c.size()) +
                            " vertices; expected at least 3");
    for (std::size_t k = 0; k < c.size(); ++k)
      if (orient2d(c[k], c[(k + 1) % c.size()], c[(k + 2) % c.size()]) <= 0)
        throw InvalidArgument(
            "voronoi_2d: clip polygon is not strictly convex and "
            "counter-clockwise at vertex " +
            std::to_string((k + 1) % c.size()));
    res.clip = c;
  } else {
    V2 lo(0, 0), hi(0, 0);
    if (n > 0) {
      lo = hi = points[0];
      for (const V2& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    }
    V2 size = hi - lo;
    double s = std::max(size.x(), size.y());
    if (!(s > 0)) s = 1;
    for (int k = 0; k < 2; ++k)
      if (!(size[k] > 0)) size[k] = s;
    V2 g = options.margin * size;
    V2 mid = 0.5 * (lo + hi);
    lo = lo.cwiseMin(mid - 0.5 * size) - g;
    hi = hi.cwiseMax(mid + 0.5 * size) + g;
    res.clip = box_polygon(lo.x(), lo.y(), hi.x(), hi.y());
  }
  res.delaunay = delaunay_2d(points);
  res.vertex_of = res.delaunay.vertex_of;
  res.cells.resize(n);
  // Delaunay neighbours of every vertex (chain neighbours for collinear input).
  std::vector<std::uint32_t> off(n + 1, 0), adj;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  const auto& D = res.delaunay;
  if (D.collinear) {
    for (std::size_t k = 1; k < D.chain.size(); ++k) {
      edges.push_back({D.chain[k - 1], D.chain[k]});
      edges.push_back({D.chain[k], D.chain[k - 1]});
    }
  } else {
    edges.reserve(6 * D.triangles.size());
    for (const auto& t : D.triangles)
      for (int i = 0; i < 3; ++i)
        edges.push_back({t[i], t[(i + 1) % 3]}), edges.push_back({t[(i + 1) % 3], t[i]});
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  for (const auto& e : edges) ++off[e.first + 1];
  for (std::size_t i = 0; i < n; ++i) off[i + 1] += off[i];
  adj.resize(edges.size());
  for (std::size_t k = 0; k < edges.size(); ++k) adj[k] = edges[k].second;  // sorted by first
  std::vector<V2> tmp;
  for (std::uint32_t i = 0; i < n; ++i) {
    if (res.vertex_of[i] != i) continue;
    std::vector<V2> poly = res.clip;
    for (std::uint32_t k = off[i]; k < off[i + 1] && !poly.empty(); ++k)
      clip_halfplane(poly, tmp, points[i], points[adj[k]] - points[i]);
    res.cells[i] = std::move(poly);
  }
  return res;
}

}  // namespace geom
