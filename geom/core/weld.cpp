#include <geom/core/weld.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>
#include <tuple>

namespace geom {

namespace {

bool finite(const Point& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z());
}

// Union-find keeping the smallest index as representative, so welding keeps the first vertex.
std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}
void unite(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
  a = find_root(parent, a);
  b = find_root(parent, b);
  if (a < b) parent[b] = a;
  else if (b < a) parent[a] = b;
}

}  // namespace

std::vector<std::uint32_t> weld_map(std::span<const Point> P, double eps) {
  if (!(eps >= 0) || !std::isfinite(eps))
    throw InvalidArgument("weld_map: tolerance must be a finite number >= 0, got " + std::to_string(eps));
  const auto n = static_cast<std::uint32_t>(P.size());
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<std::uint32_t> order;
  order.reserve(n);
  for (std::uint32_t v = 0; v < n; ++v)
    if (finite(P[v])) order.push_back(v);
  if (eps == 0) {
    auto less = [&](std::uint32_t a, std::uint32_t b) {
      const Point &p = P[a], &q = P[b];
      if (p.x() != q.x()) return p.x() < q.x();
      if (p.y() != q.y()) return p.y() < q.y();
      if (p.z() != q.z()) return p.z() < q.z();
      return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    for (std::size_t i = 1; i < order.size(); ++i)
      if (P[order[i]] == P[order[i - 1]]) unite(parent, order[i], order[i - 1]);
  } else {
    // Grid of cell size eps: points within eps lie in the same or a neighbouring cell.
    struct Cell {
      std::int64_t x, y, z;
      std::uint32_t v;
    };
    auto key = [&](double c) {
      double k = std::floor(c / eps);
      return static_cast<std::int64_t>(std::clamp(k, -4.0e18, 4.0e18));
    };
    std::vector<Cell> cells;
    cells.reserve(order.size());
    for (std::uint32_t v : order) cells.push_back({key(P[v].x()), key(P[v].y()), key(P[v].z()), v});
    auto cmp = [](const Cell& a, const Cell& b) { return std::tie(a.x, a.y, a.z, a.v) < std::tie(b.x, b.y, b.z, b.v); };
    std::sort(cells.begin(), cells.end(), cmp);
    for (const Cell& c : cells)
      for (std::int64_t dx = -1; dx <= 1; ++dx)
        for (std::int64_t dy = -1; dy <= 1; ++dy)
          for (std::int64_t dz = -1; dz <= 1; ++dz) {
            Cell probe{c.x + dx, c.y + dy, c.z + dz, 0};
            auto it = std::lower_bound(cells.begin(), cells.end(), probe, cmp);
            for (; it != cells.end() && it->x == probe.x && it->y == probe.y && it->z == probe.z; ++it)
              if (it->v < c.v && (P[it->v] - P[c.v]).norm() <= eps) unite(parent, it->v, c.v);
          }
  }
  for (std::uint32_t v = 0; v < n; ++v) parent[v] = find_root(parent, v);
  return parent;
}

namespace {

template <class T>
std::size_t differing(const std::vector<T>& values, std::span<const std::uint32_t> same) {
  std::size_t n = 0;
  if (!values.empty())
    for (std::size_t v = 0; v < same.size(); ++v) n += same[v] != v && values[v] != values[same[v]];
  return n;
}

template <class T>
void to_corners(const std::vector<std::uint32_t>& face_indices, std::vector<T>& per_vertex,
                std::vector<T>& per_corner) {
  per_corner.reserve(face_indices.size());
  for (std::uint32_t v : face_indices) per_corner.push_back(v < per_vertex.size() ? per_vertex[v] : T::Zero());
  per_vertex.clear();
}

}  // namespace

SeamCount count_seams(const PolygonSoup& soup, std::span<const std::uint32_t> same) {
  return {soup.corner_texcoords.empty() ? differing(soup.vertex_texcoords, same) : 0,
          soup.corner_normals.empty() ? differing(soup.vertex_normals, same) : 0,
          differing(soup.vertex_colors, same)};
}

SeamCount seams_to_corners(PolygonSoup& soup, std::span<const std::uint32_t> same) {
  const SeamCount n = count_seams(soup, same);
  if (n.texcoords) to_corners(soup.face_indices, soup.vertex_texcoords, soup.corner_texcoords);
  if (n.normals) to_corners(soup.face_indices, soup.vertex_normals, soup.corner_normals);
  return n;
}

}  // namespace geom
