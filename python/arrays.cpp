#include "arrays.h"

#include <geom/core/errors.h>

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <limits>

namespace geom::python {

namespace {

// Dense index of each live vertex; identity when the mesh has no deleted elements.
std::vector<std::uint32_t> dense_vertex_ids(const SurfaceMesh& mesh) {
  std::vector<std::uint32_t> ids(mesh.vertices_size(), std::numeric_limits<std::uint32_t>::max());
  std::uint32_t next = 0;
  for (Vertex v : mesh.vertices()) ids[v.idx()] = next++;
  return ids;
}

[[noreturn]] void raise_os_error(int error, const std::string& path) {
  errno = error;
  PyErr_SetFromErrnoWithFilename(PyExc_OSError, path.c_str());
  throw py::error_already_set();
}

std::string type_name(py::handle h) { return py::str(py::type::of(h).attr("__name__")); }

}  // namespace

py::array_t<double> vertices_array(const SurfaceMesh& mesh) {
  py::array_t<double> out({static_cast<py::ssize_t>(mesh.n_vertices()), py::ssize_t{3}});
  auto a = out.mutable_unchecked<2>();
  py::ssize_t i = 0;
  for (Vertex v : mesh.vertices()) {
    const Point& p = mesh.position(v);
    a(i, 0) = p.x();
    a(i, 1) = p.y();
    a(i, 2) = p.z();
    ++i;
  }
  return out;
}

py::object faces_object(const SurfaceMesh& mesh) {
  const auto ids = dense_vertex_ids(mesh);
  std::size_t k = 0;
  bool uniform = true;
  for (Face f : mesh.faces()) {
    const std::size_t n = mesh.valence(f);
    if (k == 0) k = n;
    if (n != k) {
      uniform = false;
      break;
    }
  }
  if (uniform) {
    if (k == 0) k = 3;
    py::array_t<std::int64_t> out(
        {static_cast<py::ssize_t>(mesh.n_faces()), static_cast<py::ssize_t>(k)});
    auto a = out.mutable_unchecked<2>();
    py::ssize_t i = 0;
    for (Face f : mesh.faces()) {
      py::ssize_t j = 0;
      for (Vertex v : mesh.vertices(f)) a(i, j++) = ids[v.idx()];
      ++i;
    }
    return out;
  }
  py::list out(mesh.n_faces());
  py::ssize_t i = 0;
  for (Face f : mesh.faces()) {
    py::list corners;
    for (Vertex v : mesh.vertices(f)) corners.append(ids[v.idx()]);
    out[i++] = corners;
  }
  return out;
}

PolygonSoup soup_from_arrays(py::handle vertices, py::handle faces) {
  PolygonSoup soup;
  py::array_t<double, py::array::c_style | py::array::forcecast> v;
  try {
    v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(vertices);
  } catch (const py::error_already_set&) {
  }
  if (!v) throw InvalidArgument("vertices: expected a V×3 array of numbers, got " + type_name(vertices));
  if (v.ndim() == 1 && v.shape(0) == 0) {
    // An empty list: no vertices.
  } else if (v.ndim() != 2 || v.shape(1) != 3) {
    std::string shape;
    for (py::ssize_t d = 0; d < v.ndim(); ++d) shape += (d ? "×" : "") + std::to_string(v.shape(d));
    throw InvalidArgument("vertices: expected shape V×3, got " + (shape.empty() ? "a scalar" : shape));
  }
  const std::size_t n_vertices = v.ndim() == 2 ? static_cast<std::size_t>(v.shape(0)) : 0;
  if (n_vertices >= std::numeric_limits<std::uint32_t>::max())
    throw InvalidArgument("vertices: more than 2^32 - 2 vertices");
  soup.positions.reserve(n_vertices);
  const double* p = v.data();
  for (std::size_t i = 0; i < n_vertices; ++i, p += 3) {
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw InvalidArgument("vertices: vertex " + std::to_string(i) + " has a non-finite coordinate");
    soup.positions.emplace_back(p[0], p[1], p[2]);
  }

  auto check_index = [n_vertices](std::size_t face, long long index) {
    if (index < 0 || static_cast<unsigned long long>(index) >= n_vertices)
      throw InvalidArgument("faces: face " + std::to_string(face) + " has index " +
                            std::to_string(index) + ", outside [0, " + std::to_string(n_vertices) +
                            ")");
    return static_cast<std::uint32_t>(index);
  };
  auto check_size = [](std::size_t face, std::size_t corners) {
    if (corners < 3)
      throw InvalidArgument("faces: face " + std::to_string(face) + " has " +
                            std::to_string(corners) + " corners, expected at least 3");
  };

  std::vector<std::uint32_t> corners;
  if (py::isinstance<py::array>(faces)) {
    auto arr = py::reinterpret_borrow<py::array>(faces);
    const char kind = arr.dtype().kind();
    if (arr.size() > 0 && kind != 'i' && kind != 'u')
      throw InvalidArgument("faces: expected an integer array, got dtype " +
                            std::string(py::str(arr.dtype())));
    if (arr.ndim() == 1 && arr.size() == 0) return soup;
    if (arr.ndim() != 2)
      throw InvalidArgument("faces: expected an F×k array or a list of index lists, got " +
                            std::to_string(arr.ndim()) + " dimensions");
    auto f = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(arr);
    const auto rows = static_cast<std::size_t>(f.shape(0));
    const auto k = static_cast<std::size_t>(f.shape(1));
    if (rows == 0) return soup;
    check_size(0, k);
    const long long* d = f.data();
    soup.face_offsets.reserve(rows + 1);
    soup.face_indices.reserve(rows * k);
    for (std::size_t r = 0; r < rows; ++r) {
      corners.clear();
      for (std::size_t c = 0; c < k; ++c) corners.push_back(check_index(r, d[r * k + c]));
      soup.add_face(corners);
    }
    return soup;
  }
  if (!py::isinstance<py::sequence>(faces) || py::isinstance<py::str>(faces))
    throw InvalidArgument("faces: expected an F×k integer array or a list of index lists, got " +
                          type_name(faces));
  auto seq = py::reinterpret_borrow<py::sequence>(faces);
  std::size_t face = 0;
  for (py::handle item : seq) {
    if (!py::isinstance<py::sequence>(item) && !py::isinstance<py::array>(item))
      throw InvalidArgument("faces: face " + std::to_string(face) +
                            " is not a sequence of indices (got " + type_name(item) + ")");
    corners.clear();
    for (py::handle index : item) {
      long long value = 0;
      try {
        value = py::cast<long long>(index);
      } catch (const py::cast_error&) {
        throw InvalidArgument("faces: face " + std::to_string(face) +
                              " has a non-integer index (" + type_name(index) + ")");
      }
      corners.push_back(check_index(face, value));
    }
    check_size(face, corners.size());
    soup.add_face(corners);
    ++face;
  }
  return soup;
}

void apply_kwargs(py::object options, const py::kwargs& kwargs) {
  for (auto [key, value] : kwargs) {
    const std::string name = py::str(key);
    if (name.empty() || name[0] == '_' || !py::hasattr(options, key)) {
      std::string known;
      for (py::handle attr : py::module_::import("builtins").attr("dir")(options)) {
        const std::string a = py::str(attr);
        if (a.empty() || a[0] == '_') continue;
        known += (known.empty() ? "" : ", ") + a;
      }
      throw py::type_error("unknown option '" + name + "' (expected one of: " + known + ")");
    }
    py::setattr(options, key, value);
  }
}

void check_readable(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) raise_os_error(EISDIR, path);
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) raise_os_error(errno, path);
  std::fclose(f);
}

void check_writable(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) raise_os_error(EISDIR, path);
  fs::path folder = fs::path(path).parent_path();
  if (folder.empty()) folder = ".";
  if (!fs::is_directory(folder, ec)) raise_os_error(ENOENT, folder.string());
  if (::access(folder.c_str(), W_OK) != 0) raise_os_error(errno, folder.string());
  if (fs::exists(path, ec) && ::access(path.c_str(), W_OK) != 0) raise_os_error(errno, path);
}

}  // namespace geom::python
