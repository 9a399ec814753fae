#include <geom/render/camera.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace geom {
namespace {

double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

// Orthonormal camera frame; falls back to another up vector when up ∥ view direction.
void frame(const Camera& c, Eigen::Vector3d& right, Eigen::Vector3d& up, Eigen::Vector3d& back) {
  back = (c.eye - c.at).normalized();
  Eigen::Vector3d u = c.up;
  if (u.cross(back).squaredNorm() < 1e-12) u = std::abs(back.y()) < 0.9 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  right = u.cross(back).normalized();
  up = back.cross(right);
}

}  // namespace

Eigen::Matrix4d Camera::view() const {
  Eigen::Vector3d r, u, b;
  frame(*this, r, u, b);
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.block<1, 3>(0, 0) = r.transpose();
  m.block<1, 3>(1, 0) = u.transpose();
  m.block<1, 3>(2, 0) = b.transpose();
  m(0, 3) = -r.dot(eye);
  m(1, 3) = -u.dot(eye);
  m(2, 3) = -b.dot(eye);
  return m;
}

Eigen::Matrix4d Camera::projection(double aspect, double near, double far) const {
  const double f = 1.0 / std::tan(radians(fov_y_degrees) / 2);
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = f / aspect;
  p(1, 1) = f;
  p(2, 2) = (far + near) / (near - far);
  p(2, 3) = 2 * far * near / (near - far);
  p(3, 2) = -1;
  return p;
}

Eigen::Vector3d Camera::ray_direction(double sx, double sy, double aspect) const {
  Eigen::Vector3d r, u, b;
  frame(*this, r, u, b);
  const double t = std::tan(radians(fov_y_degrees) / 2);
  return r * (sx * t * aspect) + u * (sy * t) - b;
}

Camera frame_box(const Eigen::AlignedBox3d& box, double aspect, const Eigen::Vector3d& direction,
                 double fov_y_degrees, double margin) {
  Camera c;
  c.fov_y_degrees = fov_y_degrees;
  c.at = box.center();
  c.up = Eigen::Vector3d::UnitY();
  c.eye = c.at - direction.normalized();
  Eigen::Vector3d right, up, back;
  frame(c, right, up, back);
  // The nearest eye distance at which all eight corners fit in the frustum, with a margin.
  const double tan_y = std::tan(radians(fov_y_degrees) / 2) / margin, tan_x = tan_y * aspect;
  double distance = 1e-300;
  for (int i = 0; i < 8; ++i) {
    Eigen::Vector3d corner = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(i)) - c.at;
    double depth_offset = corner.dot(back);
    distance = std::max({distance, depth_offset + std::abs(corner.dot(right)) / tan_x,
                         depth_offset + std::abs(corner.dot(up)) / tan_y});
  }
  if (box.sizes().maxCoeff() == 0) distance = 1.0;
  c.eye = c.at + back * distance;
  return c;
}

}  // namespace geom
