// Bindings of geom/compress: the .gmc mesh codec (compress / decompress with the vertex and
// face permutations).

#include "arrays.h"
#include "bindings.h"

#include <geom/compress/container/codec.h>

#include <pybind11/stl.h>

#include <cstring>
#include <string>

namespace geom::python {

namespace {

py::array_t<std::int64_t> index_array(const std::vector<std::uint32_t>& v) {
  py::array_t<std::int64_t> out(static_cast<py::ssize_t>(v.size()));
  auto a = out.mutable_unchecked<1>();
  for (std::size_t i = 0; i < v.size(); ++i) a(py::ssize_t(i)) = v[i];
  return out;
}

py::bytes bytes_object(const std::vector<std::uint8_t>& b) {
  return py::bytes(reinterpret_cast<const char*>(b.data()), b.size());
}

/// The vector as an n×width numpy array that owns it (no copy: a decoded 1M-triangle mesh's
/// arrays are tens of megabytes); None when it is empty and `none_if_empty`.
template <class T, class A>
py::object owning_array(std::vector<T, A>&& v, py::ssize_t width, bool none_if_empty) {
  if (v.empty() && none_if_empty) return py::none();
  auto* owner = new std::vector<T, A>(std::move(v));
  py::capsule free_owner(owner, [](void* p) { delete static_cast<std::vector<T, A>*>(p); });
  const py::ssize_t rows = static_cast<py::ssize_t>(owner->size()) / width;
  return py::array_t<T>({rows, width}, {width * py::ssize_t(sizeof(T)), py::ssize_t(sizeof(T))},
                        owner->data(), free_owner);
}

}  // namespace

void bind_compress(py::module_& m) {
  py::class_<CompressOptions>(m, "CompressOptions")
      .def(py::init<>())
      .def_readwrite("bits", &CompressOptions::bits)
      .def_readwrite("precision", &CompressOptions::precision)
      .def_readwrite("level", &CompressOptions::level)
      .def_readwrite("preserve_order", &CompressOptions::preserve_order)
      .def_readwrite("normal_bits", &CompressOptions::normal_bits)
      .def_readwrite("texcoord_bits", &CompressOptions::texcoord_bits)
      .def_readwrite("attribute_bits", &CompressOptions::attribute_bits)
      .def_readwrite("chunk_triangles", &CompressOptions::chunk_triangles)
      .def_readwrite("vertex_origin", &CompressOptions::vertex_origin)
      .def_readwrite("keep_corner_order", &CompressOptions::keep_corner_order)
      .def_readwrite("keep_triangle_corners", &CompressOptions::keep_triangle_corners)
      .def_readwrite("loose_faces", &CompressOptions::loose_faces)
      .def_readwrite("loose_face_positions", &CompressOptions::loose_face_positions);
  py::class_<AttributeStats>(m, "AttributeStats")
      .def_readonly("name", &AttributeStats::name)
      .def_readonly("bytes", &AttributeStats::bytes)
      .def_readonly("max_error", &AttributeStats::max_error)
      .def("__repr__", [](const AttributeStats& a) {
        return "AttributeStats(name='" + a.name + "', bytes=" + std::to_string(a.bytes) +
               ", max_error=" + std::to_string(a.max_error) + ")";
      });
  py::class_<CompressStats>(m, "CompressStats")
      .def_readonly("header_bytes", &CompressStats::header_bytes)
      .def_readonly("connectivity_bytes", &CompressStats::connectivity_bytes)
      .def_readonly("geometry_bytes", &CompressStats::geometry_bytes)
      .def_readonly("order_bytes", &CompressStats::order_bytes)
      .def_readonly("normal_bytes", &CompressStats::normal_bytes)
      .def_readonly("texcoord_bytes", &CompressStats::texcoord_bytes)
      .def_readonly("texcoord_max_error", &CompressStats::texcoord_max_error)
      .def_readonly("bits", &CompressStats::bits)
      .def_readonly("step", &CompressStats::step)
      .def_readonly("max_error", &CompressStats::max_error)
      .def_readonly("predictor", &CompressStats::predictor)
      .def_readonly("traversal", &CompressStats::traversal)
      .def_readonly("chunks", &CompressStats::chunks)
      .def_readonly("rotation_bytes", &CompressStats::rotation_bytes)
      .def_readonly("loose_face_bytes", &CompressStats::loose_face_bytes)
      .def_readonly("attributes", &CompressStats::attributes)
      .def_readonly("dropped_properties", &CompressStats::dropped_properties);
  py::class_<CompressResult>(m, "CompressResult")
      .def_property_readonly("data", [](const CompressResult& r) { return bytes_object(r.bytes); })
      .def_property_readonly("vertex_permutation",
                             [](const CompressResult& r) { return index_array(r.vertex_permutation); })
      .def_property_readonly("face_permutation",
                             [](const CompressResult& r) { return index_array(r.face_permutation); })
      .def_readonly("stats", &CompressResult::stats);
  py::class_<DecompressResult>(m, "DecompressResult")
      .def_readonly("mesh", &DecompressResult::mesh)
      .def_property_readonly("vertex_permutation",
                             [](const DecompressResult& r) { return index_array(r.vertex_permutation); })
      .def_property_readonly("face_permutation",
                             [](const DecompressResult& r) { return index_array(r.face_permutation); })
      .def_readonly("order_preserved", &DecompressResult::order_preserved)
      .def_readonly("max_error", &DecompressResult::max_error)
      .def_readonly("texcoord_max_error", &DecompressResult::texcoord_max_error)
      .def_readonly("attributes", &DecompressResult::attributes)
      .def_property_readonly("vertex_representative", [](const DecompressResult& r) {
        return index_array(r.vertex_representative);
      })
      .def_readonly("loose_faces", &DecompressResult::loose_faces)
      .def_readonly("loose_face_positions", &DecompressResult::loose_face_positions);
  m.def(
      "compress",
      [](const SurfaceMesh& mesh, const CompressOptions& options) {
        py::gil_scoped_release release;
        return compress(mesh, options);
      },
      py::arg("mesh"), py::arg("options") = CompressOptions{});
  m.def(
      "decompress",
      [](const py::bytes& data) {
        const std::string s = data;  // a copy: the GIL is released while decoding
        py::gil_scoped_release release;
        return decompress(std::span<const std::uint8_t>(
            reinterpret_cast<const std::uint8_t*>(s.data()), s.size()));
      },
      py::arg("data"));
  m.def(
      "decompress_flat",
      [](const py::bytes& data) {
        const std::string s = data;  // a copy: the GIL is released while decoding
        codec::FlatDecode f;
        {
          py::gil_scoped_release release;
          f = codec::decompress_flat(std::span<const std::uint8_t>(
              reinterpret_cast<const std::uint8_t*>(s.data()), s.size()));
        }
        return py::make_tuple(owning_array(std::move(f.positions), 3, false),
                              owning_array(std::move(f.triangles), 3, false),
                              owning_array(std::move(f.normals), 3, true),
                              owning_array(std::move(f.texcoords), 2, true),
                              owning_array(std::move(f.corner_normals), 3, true),
                              owning_array(std::move(f.corner_texcoords), 2, true));
      },
      py::arg("data"));
}

}  // namespace geom::python
