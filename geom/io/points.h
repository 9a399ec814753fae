#pragma once
/// \file
/// Point sets for computational geometry (Delaunay, hulls): plain text files of numeric
/// lines, or the vertex list of any mesh file geom reads.

#include <geom/io/io.h>

#include <Eigen/Core>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace geom {

struct PointSet {
  /// The points; 2D input has z = 0.
  std::vector<Eigen::Vector3d> points;
  /// 2 when every line held two numbers, 3 when every line held three (mesh files: 3).
  int dimension = 3;
};

/// Read points from a file ("-" is stdin). Mesh files (.ply, .obj, .off, .stl, .drc, or
/// content sniffed as one) give their vertices; anything else is read as text: one point
/// per line as `x y` or `x y z`, separated by blanks, tabs or commas, `#` starting a
/// comment, blank lines ignored.
/// Throws: ParseError naming the file and line for a non-numeric or non-finite value or a
/// line whose count differs from the first point's; Error when the file cannot be read.
/// Complexity: O(file size).
PointSet read_points(const std::filesystem::path& path);
/// The same from bytes in memory; `format` selects a mesh reader, nullopt sniffs the content
/// and falls back to the text form.
PointSet read_points(std::span<const std::byte> data, const std::string& name = "<memory>",
                     std::optional<FileFormat> format = std::nullopt);

}  // namespace geom
