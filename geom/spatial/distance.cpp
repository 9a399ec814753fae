#include <geom/spatial/distance.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>

namespace geom {

namespace {

// Samples on the surface: first every vertex used by a face and the midpoint of every edge,
// then `samples` random points spread in proportion to triangle area. Only the area samples
// enter mean/RMS, so those stay area-weighted; the vertices and midpoints only sharpen the
// maximum. The midpoints matter because a simplified surface's largest error often sits
// inside an edge that cuts across a crease of the other surface: a spot so small that random
// samples find it only by luck.
struct SurfaceSamples {
  std::vector<Point> points;
  std::size_t n_fixed = 0;  ///< leading points (vertices, edge midpoints) kept out of the mean
  std::vector<std::uint32_t> slot;  ///< per vertex of the mesh: its point (kNoSlot if unused)
  std::vector<std::uint64_t> edges;  ///< distinct edges (i << 32 | j, i < j); midpoint e is
                                     ///< point n_used + e
  std::size_t n_used = 0;            ///< vertices used by a face (the first points)
};

constexpr std::uint32_t kNoSlot = 0xffffffffu;

// The distinct edges (unordered index pairs) of the triangles, sorted.
std::vector<std::uint64_t> distinct_edges(const TriangleBvh& mesh) {
  std::vector<std::uint64_t> edges;
  edges.reserve(3 * mesh.n_triangles());
  for (std::uint32_t t = 0; t < mesh.n_triangles(); ++t) {
    const auto& c = mesh.triangle_indices(t);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = c[k], j = c[(k + 1) % 3];
      if (i == j) continue;
      edges.push_back(std::uint64_t{std::min(i, j)} << 32 | std::max(i, j));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

SurfaceSamples sample_surface(const TriangleBvh& mesh, const DistanceOptions& options) {
  SurfaceSamples out;
  const std::size_t nt = mesh.n_triangles();
  std::vector<double> areas(nt);
  double total = 0;
  std::vector<std::uint8_t> used(mesh.positions().size(), 0);
  for (std::uint32_t t = 0; t < nt; ++t) {
    const auto [a, b, c] = mesh.triangle(t);
    double area = 0.5 * (b - a).cross(c - a).norm();
    if (!std::isfinite(area)) area = 0;
    areas[t] = area;
    total += area;
    for (std::uint32_t i : mesh.triangle_indices(t)) used[i] = 1;
  }
  out.slot.assign(used.size(), kNoSlot);
  for (std::size_t i = 0; i < used.size(); ++i)
    if (used[i]) {
      out.slot[i] = static_cast<std::uint32_t>(out.points.size());
      out.points.push_back(mesh.positions()[i]);
    }
  out.n_used = out.points.size();
  out.edges = distinct_edges(mesh);
  const auto& pos = mesh.positions();
  for (std::uint64_t e : out.edges) out.points.push_back(0.5 * (pos[e >> 32] + pos[e & 0xffffffffu]));
  out.n_fixed = out.points.size();
  if (!(total > 0) || options.samples == 0) return out;
  out.points.reserve(out.n_fixed + options.samples + nt);
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  const double per_area = static_cast<double>(options.samples) / total;
  for (std::uint32_t t = 0; t < nt; ++t) {
    // Expected count areas·S/total, rounded stochastically so the total stays near S.
    const double expected = areas[t] * per_area;
    auto k = static_cast<std::size_t>(expected);
    if (uni(rng) < expected - static_cast<double>(k)) ++k;
    const auto [a, b, c] = mesh.triangle(t);
    for (std::size_t i = 0; i < k; ++i) {
      const double r1 = std::sqrt(uni(rng)), r2 = uni(rng);
      out.points.push_back((1 - r1) * a + r1 * (1 - r2) * b + r1 * r2 * c);
    }
  }
  return out;
}

// Edges are searched more closely where the first pass came near its maximum: an edge
// whose ends or middle are within kRefineFraction of it gets kRefineSteps − 1 evenly spaced
// points (its midpoint is one already). A sharp peak inside an edge (an edge that cuts
// across a crease, away from its middle) then shows; the edges far below the maximum, nearly
// all of them, cost nothing more. At most max(kRefineMinEdges, E / kRefineShare) edges, the
// highest first, so two parallel surfaces (every edge near the maximum) stay cheap.
constexpr double kRefineFraction = 0.5;
constexpr int kRefineSteps = 16;
constexpr std::size_t kRefineMinEdges = 4096, kRefineShare = 16;

struct Refined {
  double max2 = 0;
  std::size_t points = 0;
};

Refined refine_edges(const SurfaceSamples& s, const std::vector<double>& d2, const TriangleBvh& from,
                     const TriangleBvh& to, double max2) {
  const double floor2 = kRefineFraction * kRefineFraction * max2;
  std::vector<std::pair<double, std::uint32_t>> high;  // (largest d² of the edge, edge)
  for (std::uint32_t e = 0; e < s.edges.size(); ++e) {
    const double m2 = std::max({d2[s.slot[s.edges[e] >> 32]], d2[s.slot[s.edges[e] & 0xffffffffu]],
                                d2[s.n_used + e]});
    if (m2 >= floor2 && m2 > 0) high.push_back({m2, e});
  }
  const std::size_t cap = std::max(kRefineMinEdges, s.edges.size() / kRefineShare);
  if (high.size() > cap) {
    std::nth_element(high.begin(), high.begin() + static_cast<std::ptrdiff_t>(cap), high.end(),
                     std::greater<>());
    high.resize(cap);
  }
  std::vector<double> best(high.size(), 0);
  const auto& pos = from.positions();
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, high.size(), 64),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i) {
                        const std::uint64_t e = s.edges[high[i].second];
                        const Point& a = pos[e >> 32];
                        const Point& b = pos[e & 0xffffffffu];
                        for (int k = 1; k < kRefineSteps; ++k) {
                          if (2 * k == kRefineSteps) continue;  // the midpoint, measured
                          const double t = double(k) / kRefineSteps;
                          best[i] = std::max(best[i], to.distance_squared((1 - t) * a + t * b));
                        }
                      }
                    });
  Refined out;
  for (double b : best) out.max2 = std::max(out.max2, b);
  out.points = high.size() * (kRefineSteps - 2);
  return out;
}

}  // namespace

OneSidedDistance one_sided_distance(const TriangleBvh& from, const TriangleBvh& to,
                                    const DistanceOptions& options) {
  OneSidedDistance out;
  if (from.empty()) return out;
  if (to.empty()) throw InvalidArgument("distance to an empty surface: the target has no faces");
  const SurfaceSamples s = sample_surface(from, options);
  std::vector<double> d2(s.points.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, s.points.size(), 1024),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t i = r.begin(); i != r.end(); ++i)
                        d2[i] = to.distance_squared(s.points[i]);
                    });
  double max2 = 0, sum = 0, sum2 = 0;
  for (std::size_t i = 0; i < d2.size(); ++i) {
    max2 = std::max(max2, d2[i]);
    if (i >= s.n_fixed) {
      sum += std::sqrt(d2[i]);
      sum2 += d2[i];
    }
  }
  const std::size_t n_area = d2.size() - s.n_fixed;
  const Refined refined = refine_edges(s, d2, from, to, max2);
  out.max = std::sqrt(std::max(max2, refined.max2));
  out.samples = d2.size() + refined.points;
  if (n_area > 0) {
    out.mean = sum / static_cast<double>(n_area);
    out.rms = std::sqrt(sum2 / static_cast<double>(n_area));
  }
  return out;
}

MeshDistance mesh_distance(const TriangleBvh& a, const TriangleBvh& b,
                           const DistanceOptions& options) {
  if (a.empty() != b.empty())
    throw InvalidArgument(std::string("mesh distance: surface ") + (a.empty() ? "A" : "B") +
                          " has no triangles while the other has some");
  MeshDistance out;
  if (a.empty()) return out;
  out.a_to_b = one_sided_distance(a, b, options);
  out.b_to_a = one_sided_distance(b, a, options);
  out.hausdorff = std::max(out.a_to_b.max, out.b_to_a.max);
  out.rms = std::sqrt(0.5 * (out.a_to_b.rms * out.a_to_b.rms + out.b_to_a.rms * out.b_to_a.rms));
  Eigen::AlignedBox3d box = a.bounds();
  box.extend(b.bounds());
  out.diagonal = box.diagonal().norm();
  return out;
}

MeshDistance mesh_distance(const SurfaceMesh& a, const SurfaceMesh& b,
                           const DistanceOptions& options) {
  if ((a.n_faces() == 0) != (b.n_faces() == 0))
    throw InvalidArgument(std::string("mesh distance: mesh ") + (a.n_faces() == 0 ? "A" : "B") +
                          " has no faces while the other has some");
  return mesh_distance(TriangleBvh(a), TriangleBvh(b), options);
}

}  // namespace geom
