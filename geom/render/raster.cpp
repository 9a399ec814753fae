// The rasteriser: deferred shading over a z-buffer of 1/w, so every visible pixel is shaded
// exactly once however many triangles cover it.

#include <geom/render/raster.h>

#include <geom/render/shade.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace geom::detail {
namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

struct ClipVertex {
  Eigen::Vector4d c;
  Eigen::Vector3d b;  // barycentrics in the original triangle
};

struct GBuffer {
  std::vector<std::uint32_t> tri;
  std::vector<Eigen::Vector2f> bary;  // b1, b2 of the original triangle
};

// Keep the part of the triangle in front of the near plane (z + w ≥ 0): up to 4 vertices.
int clip_near(const std::array<ClipVertex, 3>& in, std::array<ClipVertex, 4>& out) {
  int n = 0;
  for (int i = 0; i < 3; ++i) {
    const ClipVertex& a = in[i];
    const ClipVertex& b = in[(i + 1) % 3];
    double da = a.c.z() + a.c.w(), db = b.c.z() + b.c.w();
    if (da >= 0) out[n++] = a;
    if ((da >= 0) != (db >= 0)) {
      double t = da / (da - db);
      out[n++] = {a.c + t * (b.c - a.c), a.b + t * (b.b - a.b)};
    }
  }
  return n;
}

void raster_triangle(const Projector& proj, const std::array<ClipVertex, 3>& v, std::uint32_t id,
                     bool cull, Frame& frame, GBuffer& g) {
  Eigen::Vector2d s[3];
  double iw[3];
  for (int i = 0; i < 3; ++i) {
    s[i] = proj.screen(v[i].c);
    iw[i] = 1.0 / v[i].c.w();
  }
  auto edge = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, double x, double y) {
    return (b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x());
  };
  double area = edge(s[0], s[1], s[2].x(), s[2].y());
  if (area == 0 || !std::isfinite(area)) return;
  // Counter-clockwise in the world reads clockwise on screen (y points down).
  if (cull && area > 0) return;
  const int W = frame.width, H = frame.height;
  int x0 = std::max(0, static_cast<int>(std::floor(std::min({s[0].x(), s[1].x(), s[2].x()}))));
  int x1 = std::min(W - 1, static_cast<int>(std::ceil(std::max({s[0].x(), s[1].x(), s[2].x()}))));
  int y0 = std::max(0, static_cast<int>(std::floor(std::min({s[0].y(), s[1].y(), s[2].y()}))));
  int y1 = std::min(H - 1, static_cast<int>(std::ceil(std::max({s[0].y(), s[1].y(), s[2].y()}))));
  const double inv_area = 1.0 / area;
  for (int y = y0; y <= y1; ++y) {
    const double py = y + 0.5;
    for (int x = x0; x <= x1; ++x) {
      const double px = x + 0.5;
      double l0 = edge(s[1], s[2], px, py) * inv_area;
      double l1 = edge(s[2], s[0], px, py) * inv_area;
      double l2 = 1.0 - l0 - l1;
      if (l0 < 0 || l1 < 0 || l2 < 0) continue;
      double q0 = l0 * iw[0], q1 = l1 * iw[1], q2 = l2 * iw[2];
      double inv = q0 + q1 + q2;
      std::size_t i = static_cast<std::size_t>(y) * W + x;
      if (inv <= frame.inv_depth[i]) continue;
      frame.inv_depth[i] = static_cast<float>(inv);
      Eigen::Vector3d b = (q0 * v[0].b + q1 * v[1].b + q2 * v[2].b) / inv;
      g.tri[i] = id;
      g.bary[i] = Eigen::Vector2f(static_cast<float>(b[1]), static_cast<float>(b[2]));
    }
  }
}

}  // namespace

void rasterize(const Scene& scene, const FlatScene& flat, const Camera& camera, Frame& frame) {
  const Projector proj(camera, frame.width, frame.height, flat.bounds);
  GBuffer g{std::vector<std::uint32_t>(frame.color.size(), kNone),
            std::vector<Eigen::Vector2f>(frame.color.size())};
  const Eigen::Matrix3d corners = Eigen::Matrix3d::Identity();
  for (std::uint32_t t = 0; t < flat.tris.size(); ++t) {
    std::array<ClipVertex, 3> v;
    bool outside[6] = {true, true, true, true, true, true};
    for (int i = 0; i < 3; ++i) {
      v[i] = {proj.clip(flat.positions[flat.tris[t][i]]), corners.col(i)};
      const Eigen::Vector4d& c = v[i].c;
      outside[0] &= c.x() > c.w();
      outside[1] &= c.x() < -c.w();
      outside[2] &= c.y() > c.w();
      outside[3] &= c.y() < -c.w();
      outside[4] &= c.z() < -c.w();
    }
    if (outside[0] || outside[1] || outside[2] || outside[3] || outside[4]) continue;
    std::array<ClipVertex, 4> poly;
    int n = clip_near(v, poly);
    for (int k = 1; k + 1 < n; ++k)
      raster_triangle(proj, {poly[0], poly[k], poly[k + 1]}, t, flat.tri_cullable[t] != 0, frame, g);
  }
  const Eigen::Vector3d eye = camera.eye;
  tbb::parallel_for(0, frame.height, [&](int y) {
    for (int x = 0; x < frame.width; ++x) {
      std::size_t i = static_cast<std::size_t>(y) * frame.width + x;
      if (g.tri[i] == kNone) continue;
      Eigen::Vector3d b(1.0 - g.bary[i].x() - g.bary[i].y(), g.bary[i].x(), g.bary[i].y());
      SurfacePoint sp = surface_at(flat, g.tri[i], b);
      Eigen::Vector3d to_eye = (eye - sp.position).normalized();
      Normal n = sp.normal.dot(to_eye) < 0 ? Normal(-sp.normal) : sp.normal;
      const Material& m = flat.materials[flat.tri_material[g.tri[i]]];
      Color c = blinn_phong(scene, m, sp.position, n, to_eye,
                            [](std::size_t, const Eigen::Vector3d&, double) { return true; });
      frame.color[i] = c.cast<float>();
    }
  });
}

}  // namespace geom::detail
