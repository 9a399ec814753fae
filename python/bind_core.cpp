// Bindings of geom/core: Mesh (SurfaceMesh), build, analyze, validate, and the translation of
// geom's exceptions into Python ones (once, here, for every binding file).

#include "arrays.h"
#include "bindings.h"

#include <geom/core/build.h>
#include <geom/core/errors.h>
#include <geom/core/topology.h>
#include <geom/core/validate.h>

#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <sstream>

namespace geom::python {

namespace {

const char* policy_name(RepairPolicy p) { return p == RepairPolicy::kStrict ? "strict" : "repair"; }

RepairPolicy policy_from(const std::string& s) {
  if (s == "repair") return RepairPolicy::kRepair;
  if (s == "strict") return RepairPolicy::kStrict;
  throw InvalidArgument("policy: expected 'repair' or 'strict', got '" + s + "'");
}

py::array_t<std::int64_t> indices(const std::vector<std::uint32_t>& v) {
  py::array_t<std::int64_t> out(static_cast<py::ssize_t>(v.size()));
  auto a = out.mutable_unchecked<1>();
  for (std::size_t i = 0; i < v.size(); ++i) a(static_cast<py::ssize_t>(i)) = v[i];
  return out;
}

// Handles become int64 with -1 for "invalid" (a dropped element).
py::array_t<std::int64_t> indices(const std::vector<Vertex>& v) {
  py::array_t<std::int64_t> out(static_cast<py::ssize_t>(v.size()));
  auto a = out.mutable_unchecked<1>();
  for (std::size_t i = 0; i < v.size(); ++i)
    a(static_cast<py::ssize_t>(i)) = v[i].is_valid() ? std::int64_t{v[i].idx()} : -1;
  return out;
}

py::object bounds(const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return py::none();
  return py::make_tuple(Eigen::Vector3d(box.min()), Eigen::Vector3d(box.max()));
}

BuildResult build_from_arrays(py::handle vertices, py::handle faces, const BuildOptions& options) {
  PolygonSoup soup = soup_from_arrays(vertices, faces);
  py::gil_scoped_release release;
  return build(soup, options);
}

std::string mesh_repr(const SurfaceMesh& m) {
  std::ostringstream s;
  s << "<geom.Mesh with " << m.n_vertices() << " vertices, " << m.n_edges() << " edges, "
    << m.n_faces() << " faces>";
  return s.str();
}

}  // namespace

void bind_core(py::module_& m) {
  // Every geom exception is a ValueError in Python (the C++ message unchanged); the subclasses
  // let callers tell them apart. Later registrations are tried first, so the base goes first.
  static py::exception<Error> error(m, "Error", PyExc_ValueError);
  static py::exception<ParseError> parse_error(m, "ParseError", error.ptr());
  static py::exception<TopologyError> topology_error(m, "TopologyError", error.ptr());
  static py::exception<InvalidArgument> invalid_argument(m, "InvalidArgument", error.ptr());
  static py::exception<DecodeError> decode_error(m, "DecodeError", error.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ParseError& e) {
      parse_error(e.what());
    } catch (const TopologyError& e) {
      topology_error(e.what());
    } catch (const InvalidArgument& e) {
      invalid_argument(e.what());
    } catch (const DecodeError& e) {
      decode_error(e.what());
    } catch (const Error& e) {
      error(e.what());
    }
  });

  py::class_<BuildOptions>(m, "BuildOptions", "Options of geom::build (see geom/core/build.h).")
      .def(py::init<>())
      .def_property(
          "policy", [](const BuildOptions& o) { return policy_name(o.policy); },
          [](BuildOptions& o, const std::string& s) { o.policy = policy_from(s); },
          "'repair' (keep what can be kept, report changes) or 'strict' (raise on the first "
          "offending face)")
      .def_readwrite("weld_tolerance", &BuildOptions::weld_tolerance)
      .def_readwrite("orient", &BuildOptions::orient)
      .def_readwrite("drop_unreferenced", &BuildOptions::drop_unreferenced);

  py::class_<BuildReport>(m, "BuildReport", "What building a mesh changed.")
      .def_readonly("welded_vertices", &BuildReport::welded_vertices)
      .def_readonly("unreferenced_vertices", &BuildReport::unreferenced_vertices)
      .def_readonly("dropped_out_of_range", &BuildReport::dropped_out_of_range)
      .def_readonly("dropped_degenerate", &BuildReport::dropped_degenerate)
      .def_readonly("dropped_duplicate", &BuildReport::dropped_duplicate)
      .def_readonly("split_nonmanifold_edges", &BuildReport::split_nonmanifold_edges)
      .def_readonly("split_nonmanifold_vertices", &BuildReport::split_nonmanifold_vertices)
      .def_readonly("flipped_faces", &BuildReport::flipped_faces)
      .def_readonly("collapsed_corners", &BuildReport::collapsed_corners)
      .def_readonly("cut_edges", &BuildReport::cut_edges)
      .def_readonly("detached_faces", &BuildReport::detached_faces)
      .def_readonly("dropped_unreferenced", &BuildReport::dropped_unreferenced)
      .def_readonly("orientable", &BuildReport::orientable)
      .def_readonly("messages", &BuildReport::messages)
      .def_property_readonly("face_origin", [](const BuildReport& r) { return indices(r.face_origin); })
      .def_property_readonly("vertex_map", [](const BuildReport& r) { return indices(r.vertex_map); })
      .def_property_readonly("vertex_origin",
                             [](const BuildReport& r) { return indices(r.vertex_origin); })
      .def("changed", &BuildReport::changed)
      .def("__repr__", [](const BuildReport& r) {
        std::string s = "<geom.BuildReport";
        if (!r.changed()) return s + ": no changes>";
        for (const auto& msg : r.messages) s += "\n  " + msg;
        return s + ">";
      });

  py::class_<SurfaceMesh> mesh(m, "Mesh");
  mesh.def(py::init<>())
      .def(py::init([](py::handle vertices, py::handle faces, const py::kwargs& kwargs) {
             BuildOptions options;
             apply_kwargs(py::cast(&options, py::return_value_policy::reference), kwargs);
             return build_from_arrays(vertices, faces, options).mesh;
           }),
           py::arg("vertices"), py::arg("faces"))
      .def_property_readonly("vertices", &vertices_array)
      .def_property_readonly("faces", &faces_object)
      .def_property_readonly("n_vertices", &SurfaceMesh::n_vertices)
      .def_property_readonly("n_halfedges", &SurfaceMesh::n_halfedges)
      .def_property_readonly("n_edges", &SurfaceMesh::n_edges)
      .def_property_readonly("n_faces", &SurfaceMesh::n_faces)
      .def_property_readonly("is_empty", &SurfaceMesh::is_empty)
      .def("is_triangle_mesh", &SurfaceMesh::is_triangle_mesh)
      .def("is_quad_mesh", &SurfaceMesh::is_quad_mesh)
      .def("analyze", py::overload_cast<const SurfaceMesh&>(&analyze),
           py::call_guard<py::gil_scoped_release>())
      .def("validate", &validate, py::arg("max_problems") = 100,
           py::call_guard<py::gil_scoped_release>())
      .def("copy", [](const SurfaceMesh& self) { return SurfaceMesh(self); })
      .def("__copy__", [](const SurfaceMesh& self) { return SurfaceMesh(self); })
      .def("__deepcopy__", [](const SurfaceMesh& self, py::dict) { return SurfaceMesh(self); })
      .def("__repr__", &mesh_repr);

  py::class_<BuildResult>(m, "BuildResult")
      .def_readonly("mesh", &BuildResult::mesh)
      .def_readonly("report", &BuildResult::report);

  m.def("build", &build_from_arrays, py::arg("vertices"), py::arg("faces"),
        py::arg("options") = BuildOptions{});

  py::class_<ComponentTopology>(m, "ComponentTopology")
      .def_readonly("vertices", &ComponentTopology::vertices)
      .def_readonly("edges", &ComponentTopology::edges)
      .def_readonly("faces", &ComponentTopology::faces)
      .def_readonly("boundary_loops", &ComponentTopology::boundary_loops)
      .def_readonly("euler_characteristic", &ComponentTopology::euler_characteristic)
      .def_readonly("orientable", &ComponentTopology::orientable)
      .def_readonly("genus", &ComponentTopology::genus);

  py::class_<TopologyReport>(m, "TopologyReport")
      .def_readonly("vertices", &TopologyReport::vertices)
      .def_readonly("edges", &TopologyReport::edges)
      .def_readonly("faces", &TopologyReport::faces)
      .def_readonly("isolated_vertices", &TopologyReport::isolated_vertices)
      .def_readonly("boundary_edges", &TopologyReport::boundary_edges)
      .def_readonly("boundary_loops", &TopologyReport::boundary_loops)
      .def_readonly("components", &TopologyReport::components)
      .def_readonly("euler_characteristic", &TopologyReport::euler_characteristic)
      .def_readonly("genus", &TopologyReport::genus)
      .def_readonly("closed", &TopologyReport::closed)
      .def_readonly("manifold", &TopologyReport::manifold)
      .def_readonly("orientable", &TopologyReport::orientable)
      .def_readonly("nonmanifold_vertices", &TopologyReport::nonmanifold_vertices)
      .def_readonly("nonmanifold_edges", &TopologyReport::nonmanifold_edges)
      .def_readonly("degenerate_faces", &TopologyReport::degenerate_faces)
      .def_readonly("face_sizes", &TopologyReport::face_sizes)
      .def_property_readonly("bounds", [](const TopologyReport& r) { return bounds(r.bounds); },
                             "(min, max) corners as float64 arrays, or None for an empty mesh")
      .def_readonly("per_component", &TopologyReport::per_component)
      .def("__repr__", [](const TopologyReport& r) {
        std::ostringstream s;
        s << "<geom.TopologyReport V=" << r.vertices << " E=" << r.edges << " F=" << r.faces
          << " H=" << r.boundary_loops << " C=" << r.components
          << " chi=" << r.euler_characteristic << " genus=";
        if (r.genus) s << *r.genus; else s << "None";
        s << (r.closed ? " closed" : " open") << (r.manifold ? " manifold" : " non-manifold")
          << (r.orientable ? " orientable" : " non-orientable") << '>';
        return s.str();
      });

  py::class_<ValidationReport>(m, "ValidationReport")
      .def_readonly("problems", &ValidationReport::problems)
      .def_property_readonly("ok", &ValidationReport::ok)
      .def("__bool__", &ValidationReport::ok)
      .def("__str__", &ValidationReport::to_string)
      .def("__repr__", [](const ValidationReport& r) {
        return r.ok() ? std::string("<geom.ValidationReport ok>")
                      : "<geom.ValidationReport " + std::to_string(r.problems.size()) +
                            " problem(s)>";
      });

  m.def("analyze", py::overload_cast<const SurfaceMesh&>(&analyze), py::arg("mesh"),
        py::call_guard<py::gil_scoped_release>());
  m.def(
      "analyze_arrays",
      [](py::handle vertices, py::handle faces) {
        const PolygonSoup soup = soup_from_arrays(vertices, faces);
        py::gil_scoped_release release;
        return analyze(soup);
      },
      py::arg("vertices"), py::arg("faces"));
  m.def("validate", &validate, py::arg("mesh"), py::arg("max_problems") = 100,
        py::call_guard<py::gil_scoped_release>());
}

}  // namespace geom::python
