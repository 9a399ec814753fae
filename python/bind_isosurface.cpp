// Bindings of geom/isosurface: marching cubes on a numpy volume, without copying it.

#include "arrays.h"
#include "bindings.h"

#include <geom/core/errors.h>
#include <geom/isosurface/marching_cubes.h>
#include <geom/isosurface/mesh_sdf.h>

#include <pybind11/stl.h>

#include <array>
#include <string>

namespace geom::python {

namespace {

const char* direction_name(NormalDirection d) {
  return d == NormalDirection::kDecreasing ? "decreasing" : "increasing";
}

NormalDirection direction_from(const std::string& s) {
  if (s == "increasing") return NormalDirection::kIncreasing;
  if (s == "decreasing") return NormalDirection::kDecreasing;
  throw InvalidArgument("normals_toward: expected 'increasing' or 'decreasing', got '" + s + "'");
}

py::array_t<double> points_array(const std::vector<Point>& p) {
  py::array_t<double> out({static_cast<py::ssize_t>(p.size()), py::ssize_t(3)});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int k = 0; k < 3; ++k) a(py::ssize_t(i), k) = p[i][k];
  return out;
}

/// Run marching cubes on `volume` (3-D float32/float64; volume[i, j, k] sits at
/// origin + (i, j, k)·spacing). A Fortran-contiguous array is geom's layout (i fastest) as is;
/// a C-contiguous one is read as the transposed grid (k fastest) and the result's x and z are
/// swapped back (with the winding reversed, since swapping two axes mirrors). Other arrays are
/// copied to C order first.
template <class T>
IsoSurface extract(py::array volume_in, const std::array<double, 3>& spacing,
                   const std::array<double, 3>& origin, const MarchingCubesOptions& options) {
  // Contiguous arrays of the right type are used in place; anything else is copied once.
  py::array arr;
  bool fortran = false;
  const bool right_type = py::isinstance<py::array_t<T>>(volume_in);
  if (right_type && (volume_in.flags() & py::array::c_style)) {
    arr = volume_in;
  } else if (right_type && (volume_in.flags() & py::array::f_style)) {
    arr = volume_in;
    fortran = true;
  } else {
    arr = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(volume_in);
    if (!arr) throw InvalidArgument("volume: expected a numeric 3-D array");
  }
  if (arr.ndim() != 3)
    throw InvalidArgument("volume: expected a 3-D array, got " + std::to_string(arr.ndim()) + " dimensions");
  const std::size_t n0 = arr.shape(0), n1 = arr.shape(1), n2 = arr.shape(2);
  GridView view;
  const T* data = static_cast<const T*>(arr.data());
  if (fortran) {
    view.dims = {n0, n1, n2};
    view.geometry.spacing = Eigen::Vector3d(spacing[0], spacing[1], spacing[2]);
    view.geometry.origin = Eigen::Vector3d(origin[0], origin[1], origin[2]);
  } else {
    view.dims = {n2, n1, n0};
    view.geometry.spacing = Eigen::Vector3d(spacing[2], spacing[1], spacing[0]);
    view.geometry.origin = Eigen::Vector3d(origin[2], origin[1], origin[0]);
  }
  view.values = std::span<const T>(data, n0 * n1 * n2);
  IsoSurface s;
  {
    py::gil_scoped_release release;
    s = marching_cubes_arrays(view, options);
    if (!fortran) {
      for (Point& p : s.positions) std::swap(p.x(), p.z());
      for (Normal& n : s.normals) std::swap(n.x(), n.z());
      for (auto& t : s.triangles) std::swap(t[1], t[2]);
    }
  }
  return s;
}

}  // namespace

void bind_isosurface(py::module_& m) {
  py::class_<MarchingCubesOptions>(m, "MarchingCubesOptions",
                                   "Options of geom::marching_cubes (geom/isosurface/marching_cubes.h).")
      .def(py::init<>())
      .def_readwrite("level", &MarchingCubesOptions::level)
      .def_property(
          "normals_toward", [](const MarchingCubesOptions& o) { return direction_name(o.normals_toward); },
          [](MarchingCubesOptions& o, const std::string& s) { o.normals_toward = direction_from(s); },
          "'increasing' (default) or 'decreasing': the side the triangles face")
      .def_readwrite("compute_normals", &MarchingCubesOptions::compute_normals)
      .def_readwrite("parallel", &MarchingCubesOptions::parallel);

  py::class_<MarchingCubesStats>(m, "MarchingCubesStats")
      .def_readonly("vertices", &MarchingCubesStats::vertices)
      .def_readonly("triangles", &MarchingCubesStats::triangles)
      .def_readonly("edge_vertices", &MarchingCubesStats::edge_vertices)
      .def_readonly("centroid_vertices", &MarchingCubesStats::centroid_vertices)
      .def_readonly("active_cells", &MarchingCubesStats::active_cells)
      .def_readonly("ambiguous_faces", &MarchingCubesStats::ambiguous_faces)
      .def_readonly("tunnels", &MarchingCubesStats::tunnels)
      .def_readonly("cells", &MarchingCubesStats::cells)
      .def_readonly("closed", &MarchingCubesStats::closed);

  py::class_<IsoSurface>(m, "IsoSurface")
      .def_property_readonly("vertices", [](const IsoSurface& s) { return points_array(s.positions); })
      .def_property_readonly("faces",
                             [](const IsoSurface& s) {
                               py::array_t<std::int64_t> out(
                                   {static_cast<py::ssize_t>(s.triangles.size()), py::ssize_t(3)});
                               auto a = out.mutable_unchecked<2>();
                               for (std::size_t i = 0; i < s.triangles.size(); ++i)
                                 for (int k = 0; k < 3; ++k) a(py::ssize_t(i), k) = s.triangles[i][k];
                               return out;
                             })
      .def_property_readonly("normals",
                             [](const IsoSurface& s) -> py::object {
                               if (s.normals.empty() && !s.positions.empty()) return py::none();
                               return points_array(s.normals);
                             })
      .def_readonly("stats", &IsoSurface::stats)
      .def(
          "to_mesh", [](const IsoSurface& s) { return mesh_from_triangles(s.positions, s.triangles); },
          py::call_guard<py::gil_scoped_release>());

  m.def(
      "marching_cubes",
      [](py::array volume, const std::array<double, 3>& spacing, const std::array<double, 3>& origin,
         const MarchingCubesOptions& options) {
        // float32 stays float32; every other dtype is read as float64.
        if (py::isinstance<py::array_t<float>>(volume)) return extract<float>(volume, spacing, origin, options);
        return extract<double>(volume, spacing, origin, options);
      },
      py::arg("volume"), py::arg("spacing"), py::arg("origin"), py::arg("options"));

  // The grid as volume[i, j, k] at origin + (i, j, k)·spacing: a Fortran-ordered float32
  // array over geom's samples (x fastest), which marching_cubes then reads in place.
  m.def(
      "signed_distance_grid",
      [](const SurfaceMesh& mesh, std::size_t resolution, double level, bool exact_everywhere) {
        MeshSdf sdf;
        {
          py::gil_scoped_release release;
          sdf = signed_distance_grid(mesh, {.resolution = resolution,
                                            .level = level,
                                            .exact_everywhere = exact_everywhere});
        }
        const GridDims d = sdf.grid.dims();
        const GridGeometry g = sdf.grid.geometry();
        auto* owner = new std::vector<float>(sdf.grid.floats().begin(), sdf.grid.floats().end());
        py::capsule free_owner(owner, [](void* p) { delete static_cast<std::vector<float>*>(p); });
        const py::ssize_t f = sizeof(float);
        py::array_t<float> volume({py::ssize_t(d.nx), py::ssize_t(d.ny), py::ssize_t(d.nz)},
                                  {f, f * py::ssize_t(d.nx), f * py::ssize_t(d.nx * d.ny)},
                                  owner->data(), free_owner);
        py::dict stats;
        stats["samples"] = sdf.stats.samples;
        stats["exact_samples"] = sdf.stats.exact_samples;
        stats["blocks"] = sdf.stats.blocks;
        stats["near_blocks"] = sdf.stats.near_blocks;
        return py::make_tuple(volume, py::make_tuple(g.spacing.x(), g.spacing.y(), g.spacing.z()),
                              py::make_tuple(g.origin.x(), g.origin.y(), g.origin.z()), stats);
      },
      py::arg("mesh"), py::arg("resolution"), py::arg("level"), py::arg("exact_everywhere"));
}

}  // namespace geom::python
