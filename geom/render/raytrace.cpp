// The ray tracer: used only when the scene asks for shadows or mirrors. Primary rays use the
// same camera mapping and shading as the rasteriser, so effect-free scenes match.

#include <geom/render/raster.h>
#include <geom/render/shade.h>
#include <geom/spatial/bvh.h>

#include <tbb/parallel_for.h>

#include <atomic>
#include <chrono>
#include <cmath>

namespace geom::detail {
namespace {

// A small deterministic hash → [0, 1) for sample jitter (splitmix64 finaliser).
double unit_hash(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  x ^= x >> 31;
  return static_cast<double>(x >> 11) * (1.0 / 9007199254740992.0);
}

struct Counters {
  std::atomic<std::uint64_t> primary{0}, shadow{0}, reflection{0};
};

class Tracer {
 public:
  Tracer(const Scene& scene, const FlatScene& flat, const TriangleBvh& bvh, Counters& counters)
      : scene_(scene), flat_(flat), bvh_(bvh), counters_(counters) {
    double diag = flat.bounds.isEmpty() ? 1.0 : flat.bounds.diagonal().norm();
    offset_ = 1e-6 * diag + 1e-300;
  }

  /// Radiance along a ray; `inv_depth_along` receives 1/(view depth) of the first hit when
  /// non-null (for the wireframe pass).
  Color trace(const Point& origin, const Eigen::Vector3d& dir, int depth, double* t_hit) const {
    auto hit = bvh_.intersect(origin, dir, 0.0);
    if (!hit) return scene_.background;
    if (t_hit) *t_hit = hit->t;
    Eigen::Vector3d b(1.0 - hit->u - hit->v, hit->u, hit->v);
    SurfacePoint sp = surface_at(flat_, hit->triangle, b);
    const Eigen::Vector3d to_eye = -dir.normalized();
    // Shade the side the ray arrived on.
    Normal n = sp.normal.dot(to_eye) < 0 ? Normal(-sp.normal) : sp.normal;
    const bool back = sp.geometric.dot(to_eye) < 0;
    Normal ng = back ? Normal(-sp.geometric) : sp.geometric;
    const Point lifted = sp.position + ng * offset_;
    const Point shadow_from = terminator_safe(hit->triangle, b, sp.position, back) + ng * offset_;
    const Material& m = flat_.materials[flat_.tri_material[hit->triangle]];
    Color c = blinn_phong(scene_, m, sp.position, n, to_eye,
                          [&](std::size_t, const Eigen::Vector3d& L, double dist) {
                            counters_.shadow.fetch_add(1, std::memory_order_relaxed);
                            return !bvh_.any_hit(shadow_from, L, 0.0, dist - 2 * offset_);
                          });
    if (m.reflectance > 0 && depth < scene_.max_reflection_depth) {
      counters_.reflection.fetch_add(1, std::memory_order_relaxed);
      Eigen::Vector3d d = dir.normalized();
      Eigen::Vector3d r = d - 2 * d.dot(n) * n;
      // The smooth normal can tilt the mirror direction below the triangle itself; reflect
      // about the true face then, or the ray would hit its own surface from behind.
      if (r.dot(ng) <= 0) r = d - 2 * d.dot(ng) * ng;
      c = (1 - m.reflectance) * c + m.reflectance * trace(lifted, r, depth + 1, nullptr);
    }
    return c;
  }

 private:
  // Shadow rays from a flat facet of a smooth-shaded mesh are blocked by the neighbouring
  // facets near the terminator, where the smooth normal still faces the light: blocky
  // self-shadows. Starting them from the point lifted onto the corners' tangent planes (the
  // curved surface the normals describe) removes that. Ref: Hanika, "Hacking the Shadow
  // Terminator", Ray Tracing Gems II, 2021.
  Point terminator_safe(std::uint32_t t, const Eigen::Vector3d& b, const Point& p, bool back) const {
    if (!flat_.smooth) return p;
    const auto& v = flat_.tris[t];
    const auto& n = flat_.tri_normals[t];
    Point out = p;
    for (int i = 0; i < 3; ++i) {
      Normal ni = back ? Normal(-flat_.normals[n[i]]) : flat_.normals[n[i]];
      double below = std::min(0.0, (p - flat_.positions[v[i]]).dot(ni));
      out -= b[i] * below * ni;
    }
    return out;
  }

  const Scene& scene_;
  const FlatScene& flat_;
  const TriangleBvh& bvh_;
  Counters& counters_;
  double offset_;
};

}  // namespace

void ray_trace(const Scene& scene, const FlatScene& flat, const Camera& camera, Frame& frame,
               RenderStats& stats) {
  auto t0 = std::chrono::steady_clock::now();
  TriangleBvh bvh(flat.positions, flat.tris);
  stats.bvh_built = true;
  stats.seconds_bvh = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  Counters counters;
  Tracer tracer(scene, flat, bvh, counters);
  const int k = std::max(1, static_cast<int>(std::lround(std::sqrt(scene.samples))));
  const double aspect = static_cast<double>(frame.width) / frame.height;
  const Eigen::Vector3d forward = (camera.at - camera.eye).normalized();
  tbb::parallel_for(0, frame.height, [&](int y) {
    for (int x = 0; x < frame.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * frame.width + x;
      Color sum = Color::Zero();
      for (int s = 0; s < k * k; ++s) {
        // Stratified jitter on a k×k grid; one sample sits at the pixel centre.
        double jx = 0.5, jy = 0.5;
        if (k > 1) {
          jx = ((s % k) + unit_hash(i * 131 + s * 2)) / k;
          jy = ((s / k) + unit_hash(i * 131 + s * 2 + 1)) / k;
        }
        double sx = (x + jx) / frame.width * 2 - 1, sy = 1 - (y + jy) / frame.height * 2;
        Eigen::Vector3d dir = camera.ray_direction(sx, sy, aspect);
        double t = -1;
        sum += tracer.trace(camera.eye, dir, 0, s == 0 ? &t : nullptr);
        if (s == 0 && t > 0) frame.inv_depth[i] = static_cast<float>(1.0 / (t * dir.dot(forward)));
      }
      counters.primary.fetch_add(static_cast<std::uint64_t>(k * k), std::memory_order_relaxed);
      frame.color[i] = (sum / (k * k)).cast<float>();
    }
  });
  stats.primary_rays = counters.primary;
  stats.shadow_rays = counters.shadow;
  stats.reflection_rays = counters.reflection;
}

}  // namespace geom::detail
