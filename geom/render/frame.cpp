#include <geom/render/frame.h>

#include <geom/render/shade.h>

#include <algorithm>
#include <cmath>

namespace geom::detail {

Projector::Projector(const Camera& camera, int w, int h, const Eigen::AlignedBox3d& bounds)
    : width(w), height(h) {
  // Depth is stored as 1/w, so only the near plane matters for precision; keep it as far
  // out as the scene allows without cutting it.
  double radius = bounds.isEmpty() ? 1.0 : 0.5 * bounds.diagonal().norm();
  double dist = bounds.isEmpty() ? 1.0 : (camera.eye - bounds.center()).norm();
  double near = std::max(dist - 1.01 * radius, 1e-5 * (dist + radius));
  if (!(near > 0)) near = 1e-6;
  double far = dist + 10 * radius + near;
  view_projection = camera.projection(static_cast<double>(w) / h, near, far) * camera.view();
}

std::size_t draw_wireframe(const FlatScene& flat, const Projector& proj, int thickness, Frame& frame) {
  const Eigen::Vector3f ink(0.02f, 0.025f, 0.04f);
  // Dense meshes would drown in ink: fade the lines when edges are only a few pixels long.
  double sum = 0;
  std::size_t sampled = 0;
  const std::size_t stride = std::max<std::size_t>(1, flat.edges.size() / 2000);
  for (std::size_t i = 0; i < flat.edges.size(); i += stride) {
    Eigen::Vector4d a = proj.clip(flat.edges[i][0]), b = proj.clip(flat.edges[i][1]);
    if (a.w() <= 0 || b.w() <= 0) continue;
    sum += (proj.screen(a) - proj.screen(b)).norm() / thickness;
    ++sampled;
  }
  const double mean_px = sampled ? sum / sampled : 10.0;
  // Ink per pixel grows with edge density as 1/length²; below ~3 px per edge the lines
  // would only darken the surface, so they are left out.
  const float alpha = static_cast<float>(std::min(0.8, (mean_px / 12.0) * (mean_px / 12.0)));
  if (alpha < 0.05f) return 0;
  std::size_t drawn = 0;
  for (const auto& e : flat.edges) {
    Eigen::Vector4d a = proj.clip(e[0]), b = proj.clip(e[1]);
    double da = a.z() + a.w(), db = b.z() + b.w();  // ≥ 0 in front of the near plane
    if (da < 0 && db < 0) continue;
    if (da < 0) a = a + (b - a) * (da / (da - db));
    if (db < 0) b = b + (a - b) * (db / (db - da));
    Eigen::Vector2d sa = proj.screen(a), sb = proj.screen(b);
    double ia = 1.0 / a.w(), ib = 1.0 / b.w();
    // Counts and pixel positions stay doubles until they are known to fit an int: a huge
    // transform puts screen points far outside the frame (or at infinity).
    const int max_steps = 4 * (frame.width + frame.height);
    const double length = std::ceil((sb - sa).cwiseAbs().maxCoeff() * 2) + 1;
    const int steps = length < max_steps ? static_cast<int>(length) : max_steps;
    ++drawn;
    for (int s = 0; s <= steps; ++s) {
      double t = static_cast<double>(s) / steps;
      Eigen::Vector2d p = sa + t * (sb - sa);
      double iw = ia + t * (ib - ia);  // 1/w is affine in screen space
      const double fx = std::floor(p.x() - 0.5 * thickness + 0.5);
      const double fy = std::floor(p.y() - 0.5 * thickness + 0.5);
      if (!(fx > -thickness && fx < frame.width && fy > -thickness && fy < frame.height)) continue;
      const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
      for (int y = y0; y < y0 + thickness; ++y)
        for (int x = x0; x < x0 + thickness; ++x) {
          if (x < 0 || y < 0 || x >= frame.width || y >= frame.height) continue;
          std::size_t i = static_cast<std::size_t>(y) * frame.width + x;
          // Visible when no surface is nearer than the edge by more than a small margin.
          if (frame.inv_depth[i] > 0 && iw * 1.003 < frame.inv_depth[i]) continue;
          frame.color[i] = frame.color[i] * (1 - alpha) + ink * alpha;
        }
    }
  }
  return drawn;
}

Image resolve(const Frame& frame, int scale) {
  Image out(frame.width / scale, frame.height / scale);
  const float norm = 1.0f / static_cast<float>(scale * scale);
  for (int y = 0; y < out.height(); ++y)
    for (int x = 0; x < out.width(); ++x) {
      Eigen::Vector3f sum = Eigen::Vector3f::Zero();
      for (int sy = 0; sy < scale; ++sy)
        for (int sx = 0; sx < scale; ++sx)
          sum += frame.color[static_cast<std::size_t>(y * scale + sy) * frame.width + x * scale + sx];
      sum *= norm;
      out.at(x, y) = {to_srgb8(sum.x()), to_srgb8(sum.y()), to_srgb8(sum.z())};
    }
  return out;
}

}  // namespace geom::detail
