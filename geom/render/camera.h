#pragma once
/// \file
/// A pinhole camera: look-at placement, perspective projection, automatic framing.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace geom {

struct Camera {
  Eigen::Vector3d eye{0, 0, 5};
  Eigen::Vector3d at{0, 0, 0};
  Eigen::Vector3d up{0, 1, 0};
  double fov_y_degrees = 35;

  /// World → camera: the camera looks down −z, y up.
  Eigen::Matrix4d view() const;
  /// Camera → clip (OpenGL conventions: depth in [−w, w]).
  Eigen::Matrix4d projection(double aspect, double near, double far) const;
  /// Direction of the primary ray through normalised image coordinates (sx, sy) in
  /// [−1, 1]², y up; not normalised.
  Eigen::Vector3d ray_direction(double sx, double sy, double aspect) const;
};

/// A camera that shows the whole box, looking along `direction` (from the eye towards the
/// box), with a margin. Pre: the box is not empty.
Camera frame_box(const Eigen::AlignedBox3d& box, double aspect,
                 const Eigen::Vector3d& direction = Eigen::Vector3d(-0.55, -0.45, -1.0),
                 double fov_y_degrees = 35, double margin = 1.08);

}  // namespace geom
