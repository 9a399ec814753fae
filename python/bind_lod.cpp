// Bindings of geom/lod (simplify, ProgressiveMesh with geomorphs and the .gpm stream) and of
// the sampled surface distance behind `geom compare`.

#include "arrays.h"
#include "bindings.h"

#include <geom/core/errors.h>
#include <geom/lod/progressive_mesh.h>
#include <geom/lod/simplify.h>
#include <geom/spatial/distance.h>

#include <pybind11/stl.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <type_traits>

namespace geom::python {

namespace {

py::array_t<double> points_array(std::span<const Point> p) {
  py::array_t<double> out({static_cast<py::ssize_t>(p.size()), py::ssize_t(3)});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int k = 0; k < 3; ++k) a(py::ssize_t(i), k) = p[i][k];
  return out;
}

py::array_t<std::int64_t> triangles_array(std::span<const std::array<std::uint32_t, 3>> t) {
  py::array_t<std::int64_t> out({static_cast<py::ssize_t>(t.size()), py::ssize_t(3)});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < t.size(); ++i)
    for (int k = 0; k < 3; ++k) a(py::ssize_t(i), k) = t[i][k];
  return out;
}

template <class T>
py::array_t<std::int64_t> index_array(const std::vector<T>& v) {
  py::array_t<std::int64_t> out(static_cast<py::ssize_t>(v.size()));
  auto a = out.mutable_unchecked<1>();
  for (std::size_t i = 0; i < v.size(); ++i) {
    if constexpr (std::is_same_v<T, Vertex>) a(py::ssize_t(i)) = v[i].idx();
    else a(py::ssize_t(i)) = v[i];
  }
  return out;
}

void bind_simplify(py::module_& m) {
  py::class_<SimplifyOptions>(m, "SimplifyOptions")
      .def(py::init<>())
      .def_readwrite("target_faces", &SimplifyOptions::target_faces)
      .def_readwrite("ratio", &SimplifyOptions::ratio)
      .def_readwrite("max_error", &SimplifyOptions::max_error)
      .def_readwrite("boundary_weight", &SimplifyOptions::boundary_weight)
      .def_readwrite("lock_boundary", &SimplifyOptions::lock_boundary)
      .def_property(
          "locked",
          [](const SimplifyOptions& o) {
            std::vector<std::uint32_t> ids;
            for (Vertex v : o.locked) ids.push_back(v.idx());
            return ids;
          },
          [](SimplifyOptions& o, const std::vector<std::uint32_t>& ids) {
            o.locked.clear();
            for (std::uint32_t i : ids) o.locked.emplace_back(i);
          })
      .def_readwrite("min_triangle_quality", &SimplifyOptions::min_triangle_quality)
      .def_readwrite("refit_iterations", &SimplifyOptions::refit_iterations)
      .def_readwrite("keep_attributes", &SimplifyOptions::keep_attributes)
      // {"normals" | "uv" | "color": weight} for the enabled attributes (the CLI's names).
      .def_property(
          "attributes",
          [](const SimplifyOptions& o) {
            py::dict d;
            auto put = [&](const char* name, const SimplifyAttribute& a) {
              if (a.enabled) d[name] = a.weight;
            };
            put("normals", o.attributes.normals);
            put("uv", o.attributes.texcoords);
            put("color", o.attributes.colors);
            return d;
          },
          [](SimplifyOptions& o, const std::map<std::string, double>& weights) {
            o.attributes = {};
            for (const auto& [name, w] : weights) {
              SimplifyAttribute* a = name == "normals" ? &o.attributes.normals
                                     : name == "uv"    ? &o.attributes.texcoords
                                     : name == "color" ? &o.attributes.colors
                                                       : nullptr;
              if (!a) throw InvalidArgument("simplify: unknown attribute '" + name + "' (expected normals, uv or color)");
              *a = {.enabled = true, .weight = w};
            }
          });
  py::class_<SimplifyResult>(m, "SimplifyResult")
      .def_readonly("mesh", &SimplifyResult::mesh)
      .def_readonly("faces_before", &SimplifyResult::faces_before)
      .def_readonly("faces_after", &SimplifyResult::faces_after)
      .def_readonly("collapses", &SimplifyResult::collapses)
      .def_readonly("max_quadric_error", &SimplifyResult::max_quadric_error)
      .def_readonly("refit_rounds", &SimplifyResult::refit_rounds)
      .def_property_readonly("stop", [](const SimplifyResult& r) { return std::string(to_string(r.stop)); })
      .def_property_readonly("vertex_origin",
                             [](const SimplifyResult& r) { return index_array(r.vertex_origin); })
      .def_readonly("dropped_properties", &SimplifyResult::dropped_properties);
  // The CLI's names of the attributes simplify would carry by default.
  m.def("present_attributes", [](const SurfaceMesh& mesh) { return present_attributes(mesh).names(); });
  m.def("missing_properties", &missing_properties, py::arg("source"), py::arg("result"));
  m.def(
      "simplify",
      [](const SurfaceMesh& mesh, const SimplifyOptions& options) {
        py::gil_scoped_release release;
        return simplify(mesh, options);
      },
      py::arg("mesh"), py::arg("options") = SimplifyOptions{});

  py::class_<OneSidedDistance>(m, "OneSidedDistance")
      .def_readonly("max", &OneSidedDistance::max)
      .def_readonly("mean", &OneSidedDistance::mean)
      .def_readonly("rms", &OneSidedDistance::rms)
      .def_readonly("samples", &OneSidedDistance::samples);
  py::class_<MeshDistance>(m, "MeshDistance")
      .def_readonly("a_to_b", &MeshDistance::a_to_b)
      .def_readonly("b_to_a", &MeshDistance::b_to_a)
      .def_readonly("hausdorff", &MeshDistance::hausdorff)
      .def_readonly("rms", &MeshDistance::rms)
      .def_readonly("diagonal", &MeshDistance::diagonal)
      .def_property_readonly("relative_hausdorff", &MeshDistance::relative_hausdorff)
      .def_property_readonly("relative_rms", &MeshDistance::relative_rms);
  m.def(
      "compare",
      [](const SurfaceMesh& a, const SurfaceMesh& b, std::size_t samples, std::uint64_t seed) {
        py::gil_scoped_release release;
        return mesh_distance(a, b, {.samples = samples, .seed = seed});
      },
      py::arg("a"), py::arg("b"), py::arg("samples") = 200000, py::arg("seed") = 1);
}

std::vector<std::byte> read_bytes(const std::string& path) {
  check_readable(path);
  std::ifstream f(path, std::ios::binary);
  std::vector<char> chars{std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
  std::vector<std::byte> out(chars.size());
  if (!chars.empty()) std::memcpy(out.data(), chars.data(), chars.size());
  return out;
}

void write_bytes(const std::string& path, const std::vector<std::byte>& data) {
  check_writable(path);
  std::ofstream f(path, std::ios::binary);
  f.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size()));
  if (!f) {
    PyErr_SetString(PyExc_OSError, ("cannot write " + path).c_str());
    throw py::error_already_set();
  }
}

std::vector<std::byte> bytes_of(const py::bytes& b) {
  const std::string s = b;
  std::vector<std::byte> out(s.size());
  if (!s.empty()) std::memcpy(out.data(), s.data(), s.size());
  return out;
}

void check_level(const ProgressiveMesh& pm, std::size_t vertices, const char* what) {
  if (vertices < pm.base_vertices() || vertices > pm.max_vertices())
    throw InvalidArgument(std::string(what) + ": vertex count " + std::to_string(vertices) +
                          " is outside [" + std::to_string(pm.base_vertices()) + ", " +
                          std::to_string(pm.max_vertices()) + "]");
}

void bind_progressive(py::module_& m) {
  py::class_<ProgressiveMesh>(m, "ProgressiveMesh")
      .def(py::init([](const SurfaceMesh& mesh, const SimplifyOptions& options) {
             py::gil_scoped_release release;
             return ProgressiveMesh::build(mesh, {.simplify = options});
           }),
           py::arg("mesh"), py::arg("options"))
      .def_property_readonly("base_vertices", &ProgressiveMesh::base_vertices)
      .def_property_readonly("base_faces", &ProgressiveMesh::base_faces)
      .def_property_readonly("max_vertices", &ProgressiveMesh::max_vertices)
      .def_property_readonly("max_faces", &ProgressiveMesh::max_faces)
      .def_property_readonly("n_vertices", &ProgressiveMesh::n_vertices)
      .def_property_readonly("n_faces", &ProgressiveMesh::n_faces)
      .def("faces_at",
           [](const ProgressiveMesh& pm, std::size_t v) {
             check_level(pm, v, "faces_at");
             return pm.faces_at(v);
           })
      .def("vertices_for_faces", &ProgressiveMesh::vertices_for_faces)
      .def(
          "refine_to",
          [](ProgressiveMesh& pm, std::size_t v) {
            check_level(pm, v, "refine_to");
            if (v < pm.n_vertices())
              throw InvalidArgument("refine_to: " + std::to_string(v) + " vertices is below the current " +
                                    std::to_string(pm.n_vertices()) + " (use coarsen_to)");
            pm.refine_to(v);
          },
          py::arg("vertices"))
      .def(
          "coarsen_to",
          [](ProgressiveMesh& pm, std::size_t v) {
            check_level(pm, v, "coarsen_to");
            if (v > pm.n_vertices())
              throw InvalidArgument("coarsen_to: " + std::to_string(v) + " vertices is above the current " +
                                    std::to_string(pm.n_vertices()) + " (use refine_to)");
            pm.coarsen_to(v);
          },
          py::arg("vertices"))
      .def(
          "set_level",
          [](ProgressiveMesh& pm, std::size_t v) {
            check_level(pm, v, "set_level");
            pm.set_level(v);
          },
          py::arg("vertices"))
      .def_property_readonly("positions",
                             [](const ProgressiveMesh& pm) { return points_array(pm.positions()); })
      .def_property_readonly("faces",
                             [](const ProgressiveMesh& pm) { return triangles_array(pm.faces()); })
      .def("mesh", &ProgressiveMesh::mesh)
      .def(
          "geomorph",
          [](ProgressiveMesh& pm, std::size_t coarse, std::size_t fine, double t) {
            if (!(t >= 0.0 && t <= 1.0))
              throw InvalidArgument("geomorph: t must be in [0, 1], got " + std::to_string(t));
            const Geomorph g = pm.geomorph(coarse, fine);
            const std::vector<Point> p = g.at(t);
            return py::make_tuple(points_array(p), triangles_array(g.faces));
          },
          py::arg("coarse"), py::arg("fine"), py::arg("t"))
      .def_property_readonly("vertex_origin",
                             [](const ProgressiveMesh& pm) { return index_array(pm.vertex_origin()); })
      .def_property_readonly("face_origin",
                             [](const ProgressiveMesh& pm) { return index_array(pm.face_origin()); })
      .def("encode",
           [](const ProgressiveMesh& pm) {
             const std::vector<std::byte> data = pm.encode();
             return py::bytes(reinterpret_cast<const char*>(data.data()), data.size());
           })
      .def_static(
          "decode",
          [](const py::bytes& data, bool allow_partial) {
            return ProgressiveMesh::decode(bytes_of(data), allow_partial);
          },
          py::arg("data"), py::arg("allow_partial") = false)
      .def("save", [](const ProgressiveMesh& pm, const std::string& path) { write_bytes(path, pm.encode()); },
           py::arg("path"))
      .def_static(
          "load",
          [](const std::string& path, bool allow_partial) {
            return ProgressiveMesh::decode(read_bytes(path), allow_partial);
          },
          py::arg("path"), py::arg("allow_partial") = false);
}

}  // namespace

void bind_lod(py::module_& m) {
  bind_simplify(m);
  bind_progressive(m);
}

}  // namespace geom::python
