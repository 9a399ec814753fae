#pragma once
/// \file
/// numpy ↔ mesh conversions and OS-error checks shared by the binding files. All of these
/// need the GIL.

#include <geom/core/soup.h>
#include <geom/core/surface_mesh.h>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>

namespace geom::python {

namespace py = pybind11;

/// Live vertex positions, densely renumbered in index order, as a V×3 float64 array (a copy:
/// the mesh may reallocate or compact later, which a view would not survive).
py::array_t<double> vertices_array(const SurfaceMesh& mesh);

/// Faces with the same dense vertex numbering: an F×k int64 array when every face has k
/// corners (F×3 when there are none), otherwise a list of lists.
py::object faces_object(const SurfaceMesh& mesh);

/// A soup from `vertices` (V×3, convertible to float64, finite) and `faces` (an F×k integer
/// array or a sequence of integer sequences, each with ≥ 3 indices in [0, V)).
/// Throws: InvalidArgument saying which argument, face or index is wrong.
PolygonSoup soup_from_arrays(py::handle vertices, py::handle faces);

/// Sets each keyword on `options` (an instance of a bound options struct), so Python keyword
/// arguments carry the C++ field names. Throws TypeError (via pybind11) on an unknown name.
void apply_kwargs(py::object options, const py::kwargs& kwargs);

/// Raise OSError (FileNotFoundError, PermissionError, IsADirectoryError, …) when `path` cannot
/// be opened for reading, or `path`'s folder does not accept a new file.
void check_readable(const std::string& path);
void check_writable(const std::string& path);

}  // namespace geom::python
