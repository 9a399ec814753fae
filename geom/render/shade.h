#pragma once
// Internal: the one shading function both render paths share, so that a scene without
// effects looks the same rasterised and ray traced.

#include <geom/render/scene.h>

#include <algorithm>
#include <cmath>

namespace geom::detail {

/// Unit vector from p towards the light and the distance to it (infinite for directional).
inline Eigen::Vector3d to_light(const Light& l, const Point& p, double& distance) {
  if (l.kind == Light::Kind::kDirectional) {
    distance = std::numeric_limits<double>::infinity();
    return -l.direction.normalized();
  }
  Eigen::Vector3d d = l.position - p;
  distance = d.norm();
  return distance > 0 ? Eigen::Vector3d(d / distance) : Eigen::Vector3d::UnitY();
}

/// Blinn-Phong: ambient + Σ visible lights (diffuse + specular). `visible(i, dir, dist)`
/// answers whether light i reaches p (shadow rays; always true when the light has none).
/// Point lights have no distance falloff: intensity is what reaches the surface.
template <class Visible>
Color blinn_phong(const Scene& scene, const Material& m, const Point& p, const Normal& n,
                  const Eigen::Vector3d& to_eye, Visible&& visible) {
  Color c = scene.ambient * m.diffuse;
  for (std::size_t i = 0; i < scene.lights.size(); ++i) {
    const Light& l = scene.lights[i];
    double dist;
    Eigen::Vector3d L = to_light(l, p, dist);
    double ndl = n.dot(L);
    if (ndl <= 0) continue;
    if (l.shadows && !visible(i, L, dist)) continue;
    Eigen::Vector3d h = (L + to_eye).normalized();
    double spec = std::pow(std::max(0.0, n.dot(h)), m.shininess);
    c += (l.intensity * (m.diffuse * ndl + m.specular * spec)).cwiseProduct(l.color);
  }
  return c;
}

/// Linear → 8-bit sRGB-like (gamma 2.2), clamped.
inline std::uint8_t to_srgb8(double v) {
  v = std::clamp(v, 0.0, 1.0);
  return static_cast<std::uint8_t>(std::lround(std::pow(v, 1.0 / 2.2) * 255.0));
}

}  // namespace geom::detail
