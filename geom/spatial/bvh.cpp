#include <geom/spatial/bvh.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace geom {

namespace {

constexpr std::uint32_t kLeafSize = 4;
constexpr int kBins = 16;
constexpr std::uint32_t kMaxSahDepth = 64;
// Depth ≤ 64 + 32 for 2^32 triangles; a traversal holds at most depth + 2 entries.
constexpr int kStack = 128;

double box_distance_squared(const Eigen::AlignedBox3d& box, const Point& q) {
  double d = 0;
  for (int k = 0; k < 3; ++k) {
    double e = std::max({box.min()[k] - q[k], 0.0, q[k] - box.max()[k]});
    d += e * e;
  }
  return d;
}

// Slab test; axes with a zero direction component are handled apart so that 0 × ∞ never
// produces a NaN that would silently accept or reject a box.
bool ray_box(const Eigen::AlignedBox3d& box, const Point& o, const Vector3& inv_dir,
             const Vector3& dir, double tmin, double tmax) {
  for (int k = 0; k < 3; ++k) {
    if (dir[k] == 0.0) {
      if (o[k] < box.min()[k] || o[k] > box.max()[k]) return false;
      continue;
    }
    double t0 = (box.min()[k] - o[k]) * inv_dir[k];
    double t1 = (box.max()[k] - o[k]) * inv_dir[k];
    if (t0 > t1) std::swap(t0, t1);
    tmin = std::max(tmin, t0);
    tmax = std::min(tmax, t1);
    if (tmin > tmax) return false;
  }
  return true;
}

Point closest_on_segment(const Point& p, const Point& a, const Point& b) {
  Vector3 ab = b - a;
  double len2 = ab.squaredNorm();
  if (!(len2 > 0)) return a;
  double t = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
  return a + t * ab;
}

}  // namespace

Point closest_point_on_triangle(const Point& p, const Point& a, const Point& b, const Point& c) {
  // Voronoi-region walk (Ericson §5.1.5): vertex regions, then edge regions, then the face.
  const Vector3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vector3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double den = d1 - d3;
    if (den > 0) return a + (d1 / den) * ab;
  }
  const Vector3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double den = d2 - d6;
    if (den > 0) return a + (d2 / den) * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double den = (d4 - d3) + (d5 - d6);
    if (den > 0) return b + ((d4 - d3) / den) * (c - b);
  }
  const double den = va + vb + vc;
  if (den > 0 && std::isfinite(den)) {
    const double v = vb / den, w = vc / den;
    return a + ab * v + ac * w;
  }
  // Degenerate (zero-area) triangle: the answer lies on one of its edges.
  Point best = closest_on_segment(p, a, b);
  double best_d = (p - best).squaredNorm();
  for (const Point& q : {closest_on_segment(p, b, c), closest_on_segment(p, c, a)}) {
    double d = (p - q).squaredNorm();
    if (d < best_d) best_d = d, best = q;
  }
  return best;
}

std::optional<RayHit> intersect_triangle(const Point& origin, const Vector3& dir, double tmin,
                                         double tmax, const Point& a, const Point& b,
                                         const Point& c) {
  const Vector3 e1 = b - a, e2 = c - a;
  const Vector3 pvec = dir.cross(e2);
  const double det = e1.dot(pvec);
  if (det == 0.0 || !std::isfinite(det)) return std::nullopt;
  const double inv = 1.0 / det;
  const Vector3 tvec = origin - a;
  const double u = tvec.dot(pvec) * inv;
  if (u < 0.0 || u > 1.0) return std::nullopt;
  const Vector3 qvec = tvec.cross(e1);
  const double v = dir.dot(qvec) * inv;
  if (v < 0.0 || u + v > 1.0) return std::nullopt;
  const double t = e2.dot(qvec) * inv;
  if (t < tmin || t > tmax) return std::nullopt;
  return RayHit{t, 0, u, v};
}

TriangleBvh::TriangleBvh(const SurfaceMesh& mesh) {
  positions_.resize(mesh.vertices_size());
  for (Vertex v : mesh.vertices()) positions_[v.idx()] = mesh.position(v);
  triangles_.reserve(mesh.n_faces());
  triangle_faces_.reserve(mesh.n_faces());
  for (Face f : mesh.faces()) {
    Halfedge h0 = mesh.halfedge(f);
    const std::uint32_t a = mesh.to_vertex(h0).idx();
    for (Halfedge h = mesh.next(h0); mesh.next(h) != h0; h = mesh.next(h)) {
      triangles_.push_back({a, mesh.to_vertex(h).idx(), mesh.to_vertex(mesh.next(h)).idx()});
      triangle_faces_.push_back(f);
    }
  }
  build();
}

TriangleBvh::TriangleBvh(std::vector<Point> positions,
                         std::vector<std::array<std::uint32_t, 3>> triangles)
    : positions_(std::move(positions)), triangles_(std::move(triangles)) {
  for (std::size_t t = 0; t < triangles_.size(); ++t)
    for (std::uint32_t i : triangles_[t])
      if (i >= positions_.size())
        throw InvalidArgument("triangle " + std::to_string(t) + " has index " +
                              std::to_string(i) + ", expected < " +
                              std::to_string(positions_.size()));
  build();
}

void TriangleBvh::build() {
  const std::size_t n = triangles_.size();
  bounds_.setEmpty();
  nodes_.clear();
  order_.resize(n);
  if (n == 0) return;
  std::vector<Eigen::AlignedBox3d> boxes(n);
  std::vector<Point> centroids(n);
  for (std::size_t t = 0; t < n; ++t) {
    const auto& i = triangles_[t];
    boxes[t].setEmpty();
    for (std::uint32_t k : i) boxes[t].extend(positions_[k]);
    centroids[t] = (positions_[i[0]] + positions_[i[1]] + positions_[i[2]]) / 3.0;
    bounds_.extend(boxes[t]);
    order_[t] = static_cast<std::uint32_t>(t);
  }
  nodes_.reserve(2 * (n / kLeafSize + 1));
  nodes_.push_back(Node{bounds_, 0, static_cast<std::uint32_t>(n)});

  struct Task {
    std::uint32_t node, begin, end, depth;
  };
  std::vector<Task> stack{{0, 0, static_cast<std::uint32_t>(n), 0}};
  struct Bin {
    Eigen::AlignedBox3d box;
    std::uint32_t count;
  };
  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    const std::uint32_t count = task.end - task.begin;
    Eigen::AlignedBox3d box, cbox;
    box.setEmpty();
    cbox.setEmpty();
    for (std::uint32_t i = task.begin; i < task.end; ++i) {
      box.extend(boxes[order_[i]]);
      cbox.extend(centroids[order_[i]]);
    }
    nodes_[task.node].box = box;
    nodes_[task.node].first = task.begin;
    nodes_[task.node].count = count;
    if (count <= kLeafSize) continue;

    int axis;
    const Vector3 extent = cbox.sizes();
    extent.maxCoeff(&axis);
    std::uint32_t mid = task.begin;
    // Past kMaxSahDepth only balanced splits are made, which bounds the depth (and so the
    // fixed traversal stacks) by kMaxSahDepth + log2(T).
    if (extent[axis] > 0 && task.depth < kMaxSahDepth) {
      // Binned surface-area heuristic along the widest centroid axis.
      Bin bins[kBins];
      for (auto& b : bins) b.box.setEmpty(), b.count = 0;
      const double lo = cbox.min()[axis];
      const double scale = kBins / extent[axis];
      auto bin_of = [&](std::uint32_t t) {
        int b = static_cast<int>((centroids[t][axis] - lo) * scale);
        return std::clamp(b, 0, kBins - 1);
      };
      for (std::uint32_t i = task.begin; i < task.end; ++i) {
        Bin& b = bins[bin_of(order_[i])];
        b.box.extend(boxes[order_[i]]);
        ++b.count;
      }
      auto area = [](const Eigen::AlignedBox3d& b) {
        if (b.isEmpty()) return 0.0;
        Vector3 s = b.sizes();
        return s.x() * s.y() + s.y() * s.z() + s.z() * s.x();
      };
      double right_area[kBins];
      std::uint32_t right_count[kBins];
      Eigen::AlignedBox3d acc;
      acc.setEmpty();
      std::uint32_t c = 0;
      for (int b = kBins - 1; b > 0; --b) {
        acc.extend(bins[b].box);
        c += bins[b].count;
        right_area[b] = area(acc);
        right_count[b] = c;
      }
      acc.setEmpty();
      c = 0;
      double best = std::numeric_limits<double>::infinity();
      int best_split = -1;
      for (int b = 1; b < kBins; ++b) {
        acc.extend(bins[b - 1].box);
        c += bins[b - 1].count;
        if (c == 0 || right_count[b] == 0) continue;
        double cost = area(acc) * c + right_area[b] * right_count[b];
        if (cost < best) best = cost, best_split = b;
      }
      if (best_split > 0) {
        auto it = std::partition(order_.begin() + task.begin, order_.begin() + task.end,
                                 [&](std::uint32_t t) { return bin_of(t) < best_split; });
        mid = static_cast<std::uint32_t>(it - order_.begin());
      }
    }
    if (mid == task.begin || mid == task.end) {
      // All centroids in one bin (or coincident): split by count so depth stays bounded.
      mid = task.begin + count / 2;
      std::nth_element(order_.begin() + task.begin, order_.begin() + mid,
                       order_.begin() + task.end, [&](std::uint32_t a, std::uint32_t b) {
                         return centroids[a][axis] < centroids[b][axis];
                       });
    }
    const auto left = static_cast<std::uint32_t>(nodes_.size());
    nodes_.push_back(Node{});
    nodes_.push_back(Node{});
    nodes_[task.node].first = left;
    nodes_[task.node].count = 0;
    stack.push_back({left + 1, mid, task.end, task.depth + 1});
    stack.push_back({left, task.begin, mid, task.depth + 1});
  }
}

ClosestPoint TriangleBvh::closest_point(const Point& q, double max_distance) const {
  ClosestPoint best;
  if (nodes_.empty()) return best;
  double best_d = max_distance * max_distance;
  if (std::isinf(max_distance)) best_d = std::numeric_limits<double>::infinity();
  struct Entry {
    std::uint32_t node;
    double d;
  };
  Entry stack[kStack];
  int top = 0;
  stack[top++] = {0, box_distance_squared(nodes_[0].box, q)};
  while (top > 0) {
    const Entry e = stack[--top];
    if (e.d > best_d) continue;
    const Node& node = nodes_[e.node];
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        const std::uint32_t t = order_[i];
        const auto& idx = triangles_[t];
        Point p = closest_point_on_triangle(q, positions_[idx[0]], positions_[idx[1]],
                                            positions_[idx[2]]);
        double d = (p - q).squaredNorm();
        if (d < best_d || (d == best_d && !best.found())) {
          best_d = d;
          best.point = p;
          best.triangle = t;
          best.distance_squared = d;
        }
      }
      continue;
    }
    double dl = box_distance_squared(nodes_[node.first].box, q);
    double dr = box_distance_squared(nodes_[node.first + 1].box, q);
    // Nearer child on top of the stack so it is searched first and tightens best_d.
    if (dl <= dr) {
      if (dr <= best_d) stack[top++] = {node.first + 1, dr};
      if (dl <= best_d) stack[top++] = {node.first, dl};
    } else {
      if (dl <= best_d) stack[top++] = {node.first, dl};
      if (dr <= best_d) stack[top++] = {node.first + 1, dr};
    }
  }
  return best;
}

std::optional<RayHit> TriangleBvh::intersect(const Point& origin, const Vector3& dir,
                                             double tmin, double tmax) const {
  std::optional<RayHit> best;
  if (nodes_.empty() || !(tmin <= tmax)) return best;
  const Vector3 inv = dir.cwiseInverse();
  std::uint32_t stack[kStack];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!ray_box(node.box, origin, inv, dir, tmin, tmax)) continue;
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        const std::uint32_t t = order_[i];
        const auto& idx = triangles_[t];
        auto hit = intersect_triangle(origin, dir, tmin, tmax, positions_[idx[0]],
                                      positions_[idx[1]], positions_[idx[2]]);
        if (hit) {
          hit->triangle = t;
          tmax = hit->t;
          best = hit;
        }
      }
      continue;
    }
    stack[top++] = node.first + 1;
    stack[top++] = node.first;
  }
  return best;
}

bool TriangleBvh::any_hit(const Point& origin, const Vector3& dir, double tmin,
                          double tmax) const {
  if (nodes_.empty() || !(tmin <= tmax)) return false;
  const Vector3 inv = dir.cwiseInverse();
  std::uint32_t stack[kStack];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Node& node = nodes_[stack[--top]];
    if (!ray_box(node.box, origin, inv, dir, tmin, tmax)) continue;
    if (node.count > 0) {
      for (std::uint32_t i = node.first; i < node.first + node.count; ++i) {
        const auto& idx = triangles_[order_[i]];
        if (intersect_triangle(origin, dir, tmin, tmax, positions_[idx[0]], positions_[idx[1]],
                               positions_[idx[2]]))
          return true;
      }
      continue;
    }
    stack[top++] = node.first + 1;
    stack[top++] = node.first;
  }
  return false;
}

}  // namespace geom
