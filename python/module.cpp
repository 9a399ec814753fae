// The compiled half of the Python package `geom` (the public API is python/geom/*.py).
//
// HOW TO ADD A CAPABILITY'S BINDING (the pattern every capability follows):
//
//  1. Write python/bind_<capability>.cpp defining `void bind_<capability>(pybind11::module_& m)`
//     in namespace geom::python. Bind the options struct with a default constructor and one
//     def_readwrite per field (same names as in C++), the result struct with one def_readonly
//     per field, and the function itself taking (mesh, options), releasing the GIL:
//
//        void bind_lod(py::module_& m) {
//          py::class_<SimplifyOptions>(m, "SimplifyOptions")
//              .def(py::init<>())
//              .def_readwrite("target_faces", &SimplifyOptions::target_faces)
//              .def_readwrite("max_error", &SimplifyOptions::max_error);
//          py::class_<SimplifyResult>(m, "SimplifyResult")
//              .def_readonly("mesh", &SimplifyResult::mesh)
//              .def_readonly("collapses", &SimplifyResult::collapses);
//          m.def("simplify", &simplify, py::arg("mesh"), py::arg("options") = SimplifyOptions{},
//                py::call_guard<py::gil_scoped_release>());
//        }
//
//     Meshes go in and out as the bound `Mesh` (geom::SurfaceMesh); numpy arrays in and out
//     through the helpers in arrays.h. Do not validate input here: the library throws
//     geom::Error and its subclasses, which bind_core turns into ValueError once for all.
//  2. Declare it in python/bindings.h and add one line to kBindings below.
//  3. Write python/geom/<capability>.py with the public function(s): keyword arguments named
//     like the options' fields, a docstring, and a call through _options.make():
//
//        def simplify(mesh, **options):
//            """Reduce the face count by quadric-error edge collapses. ... Returns a
//            SimplifyResult with .mesh, .collapses, ..."""
//            return _geom.simplify(mesh, make(_geom.SimplifyOptions, options))
//
//     (listing its public names in __all__) and add "<capability>" to _SUBMODULES in
//     python/geom/__init__.py.
//  4. In python/CMakeLists.txt add bind_<capability>.cpp to GEOM_PY_SOURCES,
//     geom::<capability> to GEOM_PY_LIBS and geom/<capability>.py to GEOM_PY_FILES.
//  5. Test in tests/python/test_<capability>.py (pytest; the error paths too).

#include "bindings.h"

namespace {

using Bind = void (*)(pybind11::module_&);

// One line per capability; core first (it registers Mesh and the exception translation).
constexpr Bind kBindings[] = {
    geom::python::bind_core,
    geom::python::bind_io,
    geom::python::bind_isosurface,
    geom::python::bind_render,
    geom::python::bind_compgeom,
    geom::python::bind_subdivision,
    geom::python::bind_lod,
    geom::python::bind_compress,
    geom::python::bind_batch,
};

}  // namespace

PYBIND11_MODULE(_geom, m) {
  m.doc() = "geom's compiled core; use the `geom` package, not this module.";
  for (Bind bind : kBindings) bind(m);
}
