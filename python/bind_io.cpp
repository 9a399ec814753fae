// Bindings of geom/io: load and save mesh files.

#include "arrays.h"
#include "bindings.h"

#include <geom/core/build.h>
#include <geom/core/errors.h>
#include <geom/io/io.h>

#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <optional>
#include <string>

namespace geom::python {

namespace {

std::optional<FileFormat> format_from_name(const std::optional<std::string>& name) {
  if (!name) return std::nullopt;
  for (FileFormat f : {FileFormat::kObj, FileFormat::kPly, FileFormat::kOff, FileFormat::kStl,
                       FileFormat::kDrc, FileFormat::kGltf, FileFormat::kGlb})
    if (*name == format_name(f)) return f;
  throw InvalidArgument("format: expected one of obj, ply, off, stl, drc, gltf, glb; got '" + *name + "'");
}

std::optional<std::string> name_of(const std::optional<FileFormat>& f) {
  if (!f) return std::nullopt;
  return std::string(format_name(*f));
}

}  // namespace

void bind_io(py::module_& m) {
  py::class_<WriteOptions>(m, "WriteOptions", "Options of geom::save_mesh (see geom/io/io.h).")
      .def(py::init<>())
      .def_property(
          "format", [](const WriteOptions& o) { return name_of(o.format); },
          [](WriteOptions& o, const std::optional<std::string>& s) { o.format = format_from_name(s); },
          "None (from the file name) or one of 'obj', 'ply', 'off', 'stl', 'drc'")
      .def_readwrite("binary", &WriteOptions::binary)
      .def_readwrite("drc_position_bits", &WriteOptions::drc_position_bits)
      .def_readwrite("drc_level", &WriteOptions::drc_level)
      .def_readwrite("attributes", &WriteOptions::attributes)
      .def_readwrite("material_libraries", &WriteOptions::material_libraries,
                     "OBJ: material files (mtllib) to name when the mesh names materials");

  py::class_<LoadResult>(m, "LoadResult")
      .def_readonly("mesh", &LoadResult::mesh)
      .def_readonly("report", &LoadResult::report)
      .def_readonly("warnings", &LoadResult::warnings,
                    "What the reader skipped or could not keep, one line each")
      .def_readonly("material_libraries", &LoadResult::material_libraries,
                    "The OBJ's material files (mtllib), which geom.save writes again");

  m.def(
      "load_mesh",
      [](const std::string& path, const std::optional<std::string>& format,
         const BuildOptions& build) {
        check_readable(path);
        ReadOptions read;
        read.format = format_from_name(format);
        py::gil_scoped_release release;
        return load_mesh(path, read, build);
      },
      py::arg("path"), py::arg("format") = py::none(), py::arg("build") = BuildOptions{});

  m.def(
      "load_mesh_bytes",
      [](const py::bytes& data, const std::string& format, const BuildOptions& build,
         const std::string& name) {
        const FileFormat f = *format_from_name(format);
        const std::string_view view = data;
        py::gil_scoped_release release;
        const PolygonSoup soup =
            read_soup(std::as_bytes(std::span<const char>(view.data(), view.size())), f, name);
        BuildResult built = geom::build(soup, build);
        return LoadResult{std::move(built.mesh), std::move(built.report), soup.warnings,
                          soup.material_libraries};
      },
      py::arg("data"), py::arg("format"), py::arg("build") = BuildOptions{},
      py::arg("name") = "<bytes>");

  m.def(
      "save_mesh",
      [](const SurfaceMesh& mesh, const std::string& path, const WriteOptions& options) {
        check_writable(path);
        py::gil_scoped_release release;
        PolygonSoup soup = to_soup(mesh);
        if (!soup.face_materials.empty() && soup.material_libraries.empty())
          soup.material_libraries = options.material_libraries;
        write_soup(soup, path, options);
        const FileFormat format = options.format ? *options.format : format_from_path(path);
        std::vector<std::string> lines = unstored(soup, format, options);
        if (format == FileFormat::kObj && !soup.face_materials.empty() && soup.material_libraries.empty())
          lines.push_back("faces name materials (usemtl) but no material file is known: pass "
                          "material_libraries=[...] (geom.load remembers a file's mtllib)");
        return lines;
      },
      py::arg("mesh"), py::arg("path"), py::arg("options") = WriteOptions{});

  m.def(
      "format_from_path",
      [](const std::string& path) { return std::string(format_name(format_from_path(path))); },
      py::arg("path"));
}

}  // namespace geom::python
