#pragma once
/// \file
/// The binding functions module.cpp calls, one per capability (python/bind_<capability>.cpp),
/// and helpers they share. See the pattern at the top of module.cpp.

#include <pybind11/pybind11.h>

namespace geom::python {

void bind_core(pybind11::module_& m);
void bind_io(pybind11::module_& m);
void bind_isosurface(pybind11::module_& m);
void bind_render(pybind11::module_& m);
void bind_compgeom(pybind11::module_& m);
void bind_subdivision(pybind11::module_& m);
void bind_lod(pybind11::module_& m);
void bind_compress(pybind11::module_& m);
void bind_batch(pybind11::module_& m);

}  // namespace geom::python
