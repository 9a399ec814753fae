#pragma once
/// \file
/// Implicit functions and sampling them on a grid. Every built-in is negative inside and
/// positive outside with the surface at level 0, so marching_cubes' default orientation
/// (normals toward increasing values) makes it face outward. Sphere and torus are exact
/// signed distances (used by the accuracy tests); the others are smooth fields whose zero set
/// is the named surface.

#include <geom/isosurface/grid.h>

#include <Eigen/Core>

#include <cstddef>
#include <functional>
#include <vector>

namespace geom {

/// Any C++ callable p ↦ value.
using ScalarFunction = std::function<double(const Eigen::Vector3d&)>;

/// Where to sample: an axis-aligned box and a sample count per axis (≥ 2 each).
struct SamplingBox {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(-1.0);
  Eigen::Vector3d max = Eigen::Vector3d::Constant(1.0);
  GridDims dims{64, 64, 64};
  bool use_double = false;  ///< store float64 samples instead of float32
};

/// Sample f at every grid point of the box (corners included), in parallel over z.
/// Throws: InvalidArgument when a dimension is < 2 or the box is empty or not finite.
/// Complexity: one call of f per sample.
ScalarGrid sample(const ScalarFunction& f, const SamplingBox& box);

/// A cube box [-half, half]³ with n samples per axis.
SamplingBox cube_box(double half, std::size_t n, bool use_double = false);

namespace implicit {

/// Signed distance to a sphere.
struct Sphere {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 1.0;
  double operator()(const Eigen::Vector3d& p) const { return (p - center).norm() - radius; }
};

/// Signed distance to a torus around the z axis through `center`.
struct Torus {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double major_radius = 0.6;
  double minor_radius = 0.25;
  double operator()(const Eigen::Vector3d& p) const;
};

/// sin x cos y + sin y cos z + sin z cos x with x = 2π·p/period; optionally clipped to the
/// box |p_i| ≤ clip (a closed solid: max with the box's signed distance) when clip > 0.
struct Gyroid {
  double period = 1.0;
  double clip = 0.0;
  double operator()(const Eigen::Vector3d& p) const;
};

/// Blinn-style metaballs: threshold − Σ r_i² / |p − c_i|² (negative inside).
struct Metaballs {
  struct Ball {
    Eigen::Vector3d center;
    double radius;
  };
  std::vector<Ball> balls;
  double threshold = 1.0;
  double operator()(const Eigen::Vector3d& p) const;
};

/// A genus-3 surface: three tori in a row along x whose tubes overlap the next one's (the
/// rings themselves do not cross, so each hole stays open), joined by a smooth minimum
/// (polynomial smin with blend radius `blend`). Extent: |x| ≤ spacing + major + minor.
struct Genus3 {
  double major_radius = 0.3;
  double minor_radius = 0.11;
  double spacing = 0.7;  ///< centre distance; 2·major < spacing < 2·(major + minor)
  double blend = 0.02;
  double operator()(const Eigen::Vector3d& p) const;
};

}  // namespace implicit
}  // namespace geom
