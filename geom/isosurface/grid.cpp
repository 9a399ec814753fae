#include <geom/isosurface/grid.h>

#include <cmath>
#include <limits>
#include <string>

namespace geom {

namespace {

std::string dims_text(const GridDims& d) {
  return std::to_string(d.nx) + "×" + std::to_string(d.ny) + "×" + std::to_string(d.nz);
}

void check_dims(const GridDims& d) {
  if (d.nx == 0 || d.ny == 0 || d.nz == 0)
    throw InvalidArgument("grid dimensions must be positive, got " + dims_text(d));
  constexpr std::size_t kMax = std::size_t(1) << 40;  // 1 Ti samples: far beyond memory
  if (d.nx > kMax || d.ny > kMax || d.nz > kMax || d.nx * d.ny > kMax ||
      d.nx * d.ny > kMax / d.nz)
    throw InvalidArgument("grid dimensions " + dims_text(d) + " overflow the sample count");
}

}  // namespace

void GridView::check() const {
  std::size_t n = std::visit([](auto s) { return s.size(); }, values);
  if (n != dims.size())
    throw InvalidArgument("grid " + dims_text(dims) + " expects " + std::to_string(dims.size()) +
                          " values, found " + std::to_string(n));
  for (int k = 0; k < 3; ++k) {
    double s = geometry.spacing[k];
    if (!(s > 0) || !std::isfinite(s))
      throw InvalidArgument("grid spacing must be positive and finite, found " +
                            std::to_string(s) + " on axis " + "xyz"[k]);
    if (!std::isfinite(geometry.origin[k]))
      throw InvalidArgument(std::string("grid origin is not finite on axis ") + "xyz"[k]);
  }
}

ScalarGrid::ScalarGrid(GridDims dims, GridGeometry geometry, bool use_double)
    : dims_(dims), geometry_(geometry) {
  check_dims(dims);
  if (use_double)
    values_ = std::vector<double>(dims.size(), 0.0);
  else
    values_ = std::vector<float>(dims.size(), 0.0f);
}

ScalarGrid::ScalarGrid(GridDims dims, std::vector<float> values, GridGeometry geometry)
    : dims_(dims), geometry_(geometry) {
  check_dims(dims);
  if (values.size() != dims.size())
    throw InvalidArgument("grid " + dims_text(dims) + " expects " + std::to_string(dims.size()) +
                          " values, found " + std::to_string(values.size()));
  values_ = std::move(values);
}

ScalarGrid::ScalarGrid(GridDims dims, std::vector<double> values, GridGeometry geometry)
    : dims_(dims), geometry_(geometry) {
  check_dims(dims);
  if (values.size() != dims.size())
    throw InvalidArgument("grid " + dims_text(dims) + " expects " + std::to_string(dims.size()) +
                          " values, found " + std::to_string(values.size()));
  values_ = std::move(values);
}

void ScalarGrid::set(std::size_t x, std::size_t y, std::size_t z, double v) {
  std::size_t i = dims_.index(x, y, z);
  if (values_.index() == 0)
    std::get<0>(values_)[i] = static_cast<float>(v);
  else
    std::get<1>(values_)[i] = v;
}

std::span<float> ScalarGrid::floats() {
  if (values_.index() != 0) throw InvalidArgument("grid holds float64 samples, not float32");
  return std::get<0>(values_);
}
std::span<double> ScalarGrid::doubles() {
  if (values_.index() != 1) throw InvalidArgument("grid holds float32 samples, not float64");
  return std::get<1>(values_);
}
std::span<const float> ScalarGrid::floats() const {
  if (values_.index() != 0) throw InvalidArgument("grid holds float64 samples, not float32");
  return std::get<0>(values_);
}
std::span<const double> ScalarGrid::doubles() const {
  if (values_.index() != 1) throw InvalidArgument("grid holds float32 samples, not float64");
  return std::get<1>(values_);
}

GridView ScalarGrid::view() const {
  GridView v;
  v.dims = dims_;
  v.geometry = geometry_;
  if (values_.index() == 0)
    v.values = std::span<const float>(std::get<0>(values_));
  else
    v.values = std::span<const double>(std::get<1>(values_));
  return v;
}

}  // namespace geom
