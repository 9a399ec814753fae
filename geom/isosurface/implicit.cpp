#include <geom/isosurface/implicit.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

namespace geom {

ScalarGrid sample(const ScalarFunction& f, const SamplingBox& box) {
  const GridDims d = box.dims;
  if (d.nx < 2 || d.ny < 2 || d.nz < 2)
    throw InvalidArgument("sampling needs at least 2 samples per axis, got " +
                          std::to_string(d.nx) + "×" + std::to_string(d.ny) + "×" +
                          std::to_string(d.nz));
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(box.min[k]) || !std::isfinite(box.max[k]) || !(box.max[k] > box.min[k]))
      throw InvalidArgument(std::string("sampling box is empty or not finite on axis ") + "xyz"[k]);
  if (!f) throw InvalidArgument("sampling needs a function, got an empty one");
  GridGeometry g;
  g.origin = box.min;
  g.spacing = (box.max - box.min).cwiseQuotient(
      Eigen::Vector3d(double(d.nx - 1), double(d.ny - 1), double(d.nz - 1)));
  ScalarGrid grid(d, g, box.use_double);
  auto fill = [&](auto* values) {
    tbb::parallel_for(std::size_t(0), d.nz, [&](std::size_t z) {
      for (std::size_t y = 0; y < d.ny; ++y)
        for (std::size_t x = 0; x < d.nx; ++x) {
          Eigen::Vector3d p = g.origin + Eigen::Vector3d(double(x), double(y), double(z))
                                             .cwiseProduct(g.spacing);
          values[d.index(x, y, z)] = static_cast<std::remove_pointer_t<decltype(values)>>(f(p));
        }
    });
  };
  if (box.use_double)
    fill(grid.doubles().data());
  else
    fill(grid.floats().data());
  return grid;
}

SamplingBox cube_box(double half, std::size_t n, bool use_double) {
  SamplingBox b;
  b.min = Eigen::Vector3d::Constant(-half);
  b.max = Eigen::Vector3d::Constant(half);
  b.dims = {n, n, n};
  b.use_double = use_double;
  return b;
}

namespace implicit {

double Torus::operator()(const Eigen::Vector3d& p) const {
  Eigen::Vector3d q = p - center;
  double ring = std::hypot(q.x(), q.y()) - major_radius;
  return std::hypot(ring, q.z()) - minor_radius;
}

double Gyroid::operator()(const Eigen::Vector3d& p) const {
  const double s = 2.0 * std::numbers::pi / period;
  const double x = s * p.x(), y = s * p.y(), z = s * p.z();
  double g = std::sin(x) * std::cos(y) + std::sin(y) * std::cos(z) + std::sin(z) * std::cos(x);
  if (clip > 0) {
    double box = p.cwiseAbs().maxCoeff() - clip;
    g = std::max(g, box);
  }
  return g;
}

double Metaballs::operator()(const Eigen::Vector3d& p) const {
  double sum = 0;
  for (const Ball& b : balls) sum += b.radius * b.radius / (p - b.center).squaredNorm();
  return threshold - sum;
}

double Genus3::operator()(const Eigen::Vector3d& p) const {
  // Polynomial smooth minimum (Quílez): blends within `blend` of the crossing.
  auto smin = [&](double a, double b) {
    double h = std::clamp(0.5 + 0.5 * (b - a) / blend, 0.0, 1.0);
    return b + (a - b) * h - blend * h * (1.0 - h);
  };
  double d = 0;
  for (int i = -1; i <= 1; ++i) {
    Torus t{Eigen::Vector3d(i * spacing, 0, 0), major_radius, minor_radius};
    double ti = t(p);
    d = i == -1 ? ti : smin(d, ti);
  }
  return d;
}

}  // namespace implicit
}  // namespace geom
