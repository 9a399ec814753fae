#pragma once
// Internal: the linear-light frame both render paths draw into, its projection, and the
// passes they share (wireframe overlay, resolve to 8-bit).

#include <geom/render/flatten.h>
#include <geom/render/image.h>

#include <Eigen/Core>

#include <limits>
#include <vector>

namespace geom::detail {

/// Linear colour plus inverse view depth (1/w, larger is nearer; 0 = nothing) per pixel.
struct Frame {
  int width = 0, height = 0;
  std::vector<Eigen::Vector3f> color;
  std::vector<float> inv_depth;
  Frame(int w, int h, const Color& background)
      : width(w), height(h), color(static_cast<std::size_t>(w) * h, background.cast<float>()),
        inv_depth(static_cast<std::size_t>(w) * h, 0.0f) {}
};

/// World → clip → pixel for a frame of the given size.
struct Projector {
  Eigen::Matrix4d view_projection;
  int width, height;
  Projector(const Camera& camera, int w, int h, const Eigen::AlignedBox3d& bounds);
  Eigen::Vector4d clip(const Point& p) const {
    return view_projection * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0);
  }
  /// Pixel coordinates (x right, y down; pixel centres at +0.5) of a clip point with w > 0.
  Eigen::Vector2d screen(const Eigen::Vector4d& c) const {
    return {(c.x() / c.w() * 0.5 + 0.5) * width, (0.5 - c.y() / c.w() * 0.5) * height};
  }
};

/// Draw polygon edges over the frame, hidden where a surface is nearer, `thickness` pixels
/// wide. Returns the number of edges drawn.
std::size_t draw_wireframe(const FlatScene& flat, const Projector& proj, int thickness, Frame& frame);

/// Average scale×scale blocks and convert to 8-bit.
Image resolve(const Frame& frame, int scale);

}  // namespace geom::detail
