#pragma once
/// \file
/// Scalar grids for iso-surface extraction: an owning ScalarGrid (float32 or float64 samples)
/// and a non-owning GridView over samples someone else holds (a NumPy array, a file buffer).
///
/// Layout (the one rule every grid in geom/isosurface follows): sample (x, y, z) is at
/// position origin + (x·sx, y·sy, z·sz) and at flat index x + nx·(y + ny·z), x fastest.
/// That is the memory of a C-contiguous NumPy array of shape (nz, ny, nx) indexed
/// a[z, y, x], so such an array is used without a copy.

#include <geom/core/errors.h>

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <span>
#include <variant>
#include <vector>

namespace geom {

/// Sample counts along x, y, z.
struct GridDims {
  std::size_t nx = 0, ny = 0, nz = 0;
  std::size_t size() const { return nx * ny * nz; }
  std::size_t index(std::size_t x, std::size_t y, std::size_t z) const {
    return x + nx * (y + ny * z);
  }
  friend bool operator==(const GridDims&, const GridDims&) = default;
};

/// Where the samples sit in space.
struct GridGeometry {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Vector3d spacing = Eigen::Vector3d::Ones();
};

/// A read-only view of grid samples (float or double) with dims and geometry.
struct GridView {
  GridDims dims;
  GridGeometry geometry;
  std::variant<std::span<const float>, std::span<const double>> values;

  bool is_double() const { return values.index() == 1; }
  /// Sample as double. Pre: indices in range.
  double at(std::size_t x, std::size_t y, std::size_t z) const {
    std::size_t i = dims.index(x, y, z);
    return values.index() == 0 ? static_cast<double>(std::get<0>(values)[i])
                               : std::get<1>(values)[i];
  }
  Eigen::Vector3d position(std::size_t x, std::size_t y, std::size_t z) const {
    return geometry.origin + Eigen::Vector3d(double(x), double(y), double(z))
                                 .cwiseProduct(geometry.spacing);
  }
  /// Throws: InvalidArgument when the value count differs from nx·ny·nz, a spacing is not
  /// positive and finite, or the origin is not finite.
  void check() const;
};

/// A grid that owns its samples, stored as float32 or float64.
class ScalarGrid {
 public:
  ScalarGrid() = default;
  /// Zero-filled grid. Throws: InvalidArgument when a dimension is 0 or the sample count
  /// overflows.
  ScalarGrid(GridDims dims, GridGeometry geometry = {}, bool use_double = false);
  /// Take ownership of samples (x fastest). Throws: InvalidArgument on a size mismatch.
  ScalarGrid(GridDims dims, std::vector<float> values, GridGeometry geometry = {});
  ScalarGrid(GridDims dims, std::vector<double> values, GridGeometry geometry = {});

  const GridDims& dims() const { return dims_; }
  const GridGeometry& geometry() const { return geometry_; }
  GridGeometry& geometry() { return geometry_; }
  bool is_double() const { return values_.index() == 1; }

  double at(std::size_t x, std::size_t y, std::size_t z) const { return view().at(x, y, z); }
  void set(std::size_t x, std::size_t y, std::size_t z, double v);

  /// The samples; floats() throws InvalidArgument on a float64 grid and doubles() on a
  /// float32 grid.
  std::span<float> floats();
  std::span<double> doubles();
  std::span<const float> floats() const;
  std::span<const double> doubles() const;

  GridView view() const;

 private:
  GridDims dims_;
  GridGeometry geometry_;
  std::variant<std::vector<float>, std::vector<double>> values_;
};

}  // namespace geom
