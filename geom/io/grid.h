#pragma once
/// \file
/// Scalar grids from files: NumPy .npy (format versions 1-3) and raw binary samples. The
/// result is plain arrays; geom/isosurface's ScalarGrid takes them without a copy
/// (`ScalarGrid({g.nx, g.ny, g.nz}, std::move(g.floats))`).
///
/// Axis rule: a 3-D array a[i, j, k] is sample (x = k, y = j, z = i), x fastest in memory,
/// whatever the file's memory order: a C-order file is used as is and a Fortran-order file
/// is transposed while reading. A 2-D array a[j, k] is one layer (nz = 1), a 1-D array one
/// row.
///
/// Ref: NumPy Enhancement Proposal 1, "A simple file format for NumPy arrays".

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

namespace geom {

/// Samples of a grid, x fastest. Exactly one of floats/doubles holds nx·ny·nz values:
/// float32 files and integers of ≤ 16 bits, bool and float16 become floats (exactly);
/// float64 and wider integers become doubles.
struct GridData {
  std::size_t nx = 0, ny = 0, nz = 0;
  std::vector<float> floats;
  std::vector<double> doubles;
  bool is_double = false;
  std::string dtype;  ///< the file's type, NumPy notation ("<f4", ">i2", "|u1", …)
};

/// Read a .npy file. Throws: ParseError naming the file and byte offset for a bad magic,
/// version, header, unsupported dtype (complex, object, strings), more than 3 dimensions, or
/// data shorter than the shape needs; Error when the file cannot be opened.
GridData read_npy(const std::filesystem::path& path);
/// Read .npy bytes from memory; `name` is used in messages. Throws: as above.
GridData read_npy(std::span<const std::byte> data, const std::string& name = "<memory>");

/// Write a 3-D C-order little-endian .npy of shape (nz, ny, nx) ('<f4' or '<f8').
/// Throws: InvalidArgument when values.size() != nx·ny·nz; Error when the file cannot be
/// written.
void write_npy(const std::filesystem::path& path, std::size_t nx, std::size_t ny, std::size_t nz,
               std::span<const float> values);
void write_npy(const std::filesystem::path& path, std::size_t nx, std::size_t ny, std::size_t nz,
               std::span<const double> values);

struct RawGridOptions {
  std::size_t nx = 0, ny = 0, nz = 0;
  /// NumPy notation for the sample type: "f4", "<f8", ">u2", "i1", … (no prefix =
  /// little-endian).
  std::string dtype = "<f4";
  /// true: the file holds x slowest (z fastest) and is transposed while reading.
  bool z_fastest = false;
  /// Bytes to skip before the samples (a fixed header).
  std::size_t offset = 0;
};

/// Read raw binary samples. Throws: InvalidArgument for a zero dimension or unknown dtype;
/// ParseError when the file is shorter than offset + nx·ny·nz samples; Error when it cannot
/// be opened.
GridData read_raw(const std::filesystem::path& path, const RawGridOptions& options);

}  // namespace geom
