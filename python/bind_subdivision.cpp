// Bindings of geom/subdivision: subdivide() with creases given as arrays, limit_positions().

#include "arrays.h"
#include "bindings.h"

#include <geom/core/errors.h>
#include <geom/subdivision/subdivision.h>

#include <pybind11/stl.h>

#include <string>

namespace geom::python {

namespace {

const char* scheme_name(SubdivisionScheme s) {
  return s == SubdivisionScheme::kLoop ? "loop" : "catmull-clark";
}
SubdivisionScheme scheme_from(const std::string& s) {
  if (s == "catmull-clark") return SubdivisionScheme::kCatmullClark;
  if (s == "loop") return SubdivisionScheme::kLoop;
  throw InvalidArgument("scheme: expected 'catmull-clark' or 'loop', got '" + s + "'");
}
const char* boundary_name(BoundaryInterpolation b) {
  return b == BoundaryInterpolation::kNone    ? "none"
         : b == BoundaryInterpolation::kEdges ? "edges"
                                              : "corners";
}
BoundaryInterpolation boundary_from(const std::string& s) {
  if (s == "none") return BoundaryInterpolation::kNone;
  if (s == "edges") return BoundaryInterpolation::kEdges;
  if (s == "corners") return BoundaryInterpolation::kEdgesAndCorners;
  throw InvalidArgument("boundary: expected 'none', 'edges' or 'corners', got '" + s + "'");
}

py::array_t<double> rows3(const std::vector<Eigen::Vector3d>& p) {
  py::array_t<double> out({static_cast<py::ssize_t>(p.size()), py::ssize_t(3)});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < p.size(); ++i)
    for (int k = 0; k < 3; ++k) a(py::ssize_t(i), k) = p[i][k];
  return out;
}

/// Rows of `n` doubles from an array-like (None: no rows).
py::array_t<double> table(py::handle obj, py::ssize_t n, const char* what) {
  auto arr = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!arr || arr.ndim() != 2 || arr.shape(1) != n)
    throw InvalidArgument(std::string(what) + ": expected an N×" + std::to_string(n) + " array");
  return arr;
}

std::uint32_t vertex_index(double x, std::size_t nv, const char* what) {
  if (!(x >= 0.0 && x < static_cast<double>(nv) && x == static_cast<double>(static_cast<std::uint64_t>(x))))
    throw InvalidArgument(std::string(what) + ": vertex index " + std::to_string(x) +
                          " is not an integer in [0, " + std::to_string(nv) + ")");
  return static_cast<std::uint32_t>(x);
}

/// A copy of `mesh` (compacted) with "e:sharpness" from (a, b, s) rows and "v:sharpness"
/// from (v, s) rows.
SurfaceMesh with_creases(const SurfaceMesh& mesh, py::handle creases, py::handle corners) {
  SurfaceMesh m = mesh;
  if (m.has_garbage()) m.compact();
  if (!creases.is_none()) {
    auto t = table(creases, 3, "creases");
    auto r = t.unchecked<2>();
    auto sharp = m.get_or_add_property<Edge, double>(prop::kEdgeSharpness, 0.0);
    for (py::ssize_t i = 0; i < r.shape(0); ++i) {
      const Vertex a(vertex_index(r(i, 0), m.n_vertices(), "creases"));
      const Vertex b(vertex_index(r(i, 1), m.n_vertices(), "creases"));
      const Edge e = m.find_edge(a, b);
      if (!e.is_valid())
        throw InvalidArgument("creases: row " + std::to_string(i) + " names vertices " +
                              std::to_string(a.idx()) + " and " + std::to_string(b.idx()) +
                              ", which share no edge");
      sharp[e] = r(i, 2);
    }
  }
  if (!corners.is_none()) {
    auto t = table(corners, 2, "corners");
    auto r = t.unchecked<2>();
    auto sharp = m.get_or_add_property<Vertex, double>(prop::kVertexSharpness, 0.0);
    for (py::ssize_t i = 0; i < r.shape(0); ++i)
      sharp[Vertex(vertex_index(r(i, 0), m.n_vertices(), "corners"))] = r(i, 1);
  }
  return m;
}

/// The soup of (vertices, faces) with crease and corner tags from the same rows.
PolygonSoup tagged_soup(py::handle vertices, py::handle faces, py::handle creases,
                        py::handle corners) {
  PolygonSoup soup = soup_from_arrays(vertices, faces);
  const std::size_t nv = soup.positions.size();
  if (!creases.is_none()) {
    auto r = table(creases, 3, "creases").unchecked<2>();
    for (py::ssize_t i = 0; i < r.shape(0); ++i)
      soup.creases.push_back({vertex_index(r(i, 0), nv, "creases"),
                              vertex_index(r(i, 1), nv, "creases"), r(i, 2)});
  }
  if (!corners.is_none()) {
    auto r = table(corners, 2, "corners").unchecked<2>();
    for (py::ssize_t i = 0; i < r.shape(0); ++i)
      soup.corners.push_back({vertex_index(r(i, 0), nv, "corners"), r(i, 1)});
  }
  return soup;
}

/// Faces of a soup: an F×k array when all have k corners, else a list of lists.
py::object soup_faces(const PolygonSoup& soup) {
  const std::size_t nf = soup.n_faces();
  const std::size_t k = nf ? soup.face(0).size() : 3;
  bool uniform = true;
  for (std::size_t f = 0; f < nf && uniform; ++f) uniform = soup.face(f).size() == k;
  if (uniform) {
    py::array_t<std::int64_t> out({static_cast<py::ssize_t>(nf), static_cast<py::ssize_t>(k)});
    auto a = out.mutable_unchecked<2>();
    for (std::size_t f = 0; f < nf; ++f)
      for (std::size_t j = 0; j < k; ++j) a(py::ssize_t(f), py::ssize_t(j)) = soup.face(f)[j];
    return out;
  }
  py::list out;
  for (std::size_t f = 0; f < nf; ++f) {
    py::list corners;
    for (std::uint32_t v : soup.face(f)) corners.append(v);
    out.append(corners);
  }
  return out;
}

}  // namespace

void bind_subdivision(py::module_& m) {
  py::class_<SubdivideOptions>(m, "SubdivideOptions")
      .def(py::init<>())
      .def_property(
          "scheme", [](const SubdivideOptions& o) { return scheme_name(o.scheme); },
          [](SubdivideOptions& o, const std::string& s) { o.scheme = scheme_from(s); })
      .def_readwrite("levels", &SubdivideOptions::levels)
      .def_property(
          "boundary", [](const SubdivideOptions& o) { return boundary_name(o.boundary); },
          [](SubdivideOptions& o, const std::string& s) { o.boundary = boundary_from(s); })
      .def_property(
          "crease_method",
          [](const SubdivideOptions& o) {
            return o.crease_method == CreaseMethod::kChaikin ? "chaikin" : "uniform";
          },
          [](SubdivideOptions& o, const std::string& s) {
            if (s != "uniform" && s != "chaikin")
              throw InvalidArgument("crease_method: expected 'uniform' or 'chaikin', got '" + s + "'");
            o.crease_method = s == "chaikin" ? CreaseMethod::kChaikin : CreaseMethod::kUniform;
          })
      .def_property(
          "face_varying",
          [](const SubdivideOptions& o) {
            return o.face_varying == FaceVaryingInterpolation::kLinearBoundaries ? "smooth"
                                                                                 : "linear";
          },
          [](SubdivideOptions& o, const std::string& s) {
            if (s != "linear" && s != "smooth")
              throw InvalidArgument("face_varying: expected 'linear' or 'smooth', got '" + s + "'");
            o.face_varying = s == "smooth" ? FaceVaryingInterpolation::kLinearBoundaries
                                           : FaceVaryingInterpolation::kLinearAll;
          })
      .def_readwrite("limit", &SubdivideOptions::limit)
      .def_readwrite("crease_angle", &SubdivideOptions::crease_angle)
      .def_readwrite("parallel", &SubdivideOptions::parallel);
  py::class_<LevelCounts>(m, "LevelCounts")
      .def_readonly("vertices", &LevelCounts::vertices)
      .def_readonly("edges", &LevelCounts::edges)
      .def_readonly("faces", &LevelCounts::faces);
  py::class_<SubdivideResult>(m, "SubdivideResult")
      .def_readonly("mesh", &SubdivideResult::mesh)
      .def_readonly("levels", &SubdivideResult::levels)
      .def_readonly("per_level", &SubdivideResult::per_level)
      .def_readonly("angle_creased_edges", &SubdivideResult::angle_creased_edges)
      .def_readonly("limit_max_distance", &SubdivideResult::limit_max_distance)
      .def_readonly("limit_rms_distance", &SubdivideResult::limit_rms_distance);
  m.def(
      "subdivide",
      [](const SurfaceMesh& mesh, const SubdivideOptions& options, py::object creases,
         py::object corners) {
        if (creases.is_none() && corners.is_none()) {
          py::gil_scoped_release release;
          return subdivide(mesh, options);
        }
        SurfaceMesh creased = with_creases(mesh, creases, corners);
        py::gil_scoped_release release;
        return subdivide(creased, options);
      },
      py::arg("mesh"), py::arg("options") = SubdivideOptions{}, py::arg("creases") = py::none(),
      py::arg("corners") = py::none());

  py::class_<SoupSubdivideResult>(m, "SoupSubdivideResult")
      .def_property_readonly("vertices",
                             [](const SoupSubdivideResult& r) { return rows3(r.soup.positions); })
      .def_property_readonly("faces", [](const SoupSubdivideResult& r) { return soup_faces(r.soup); })
      .def_readonly("levels", &SoupSubdivideResult::levels)
      .def_readonly("per_level", &SoupSubdivideResult::per_level)
      .def_readonly("angle_creased_edges", &SoupSubdivideResult::angle_creased_edges)
      .def_readonly("limit_max_distance", &SoupSubdivideResult::limit_max_distance)
      .def_readonly("limit_rms_distance", &SoupSubdivideResult::limit_rms_distance)
      .def_readonly("nonmanifold_edges", &SoupSubdivideResult::nonmanifold_edges)
      .def_readonly("nonmanifold_vertices", &SoupSubdivideResult::nonmanifold_vertices)
      .def_readonly("degenerate_edges", &SoupSubdivideResult::degenerate_edges)
      .def_readonly("split_vertices", &SoupSubdivideResult::split_vertices)
      .def_readonly("opened_edges", &SoupSubdivideResult::opened_edges);
  m.def(
      "subdivide_soup",
      [](py::handle vertices, py::handle faces, const SubdivideOptions& options,
         py::handle creases, py::handle corners) {
        PolygonSoup soup = tagged_soup(vertices, faces, creases, corners);
        py::gil_scoped_release release;
        return subdivide(soup, options);
      },
      py::arg("vertices"), py::arg("faces"), py::arg("options") = SubdivideOptions{},
      py::arg("creases") = py::none(), py::arg("corners") = py::none());

  py::class_<LimitOptions>(m, "LimitOptions")
      .def(py::init<>())
      .def_property(
          "scheme", [](const LimitOptions& o) { return scheme_name(o.scheme); },
          [](LimitOptions& o, const std::string& s) { o.scheme = scheme_from(s); })
      .def_property(
          "boundary", [](const LimitOptions& o) { return boundary_name(o.boundary); },
          [](LimitOptions& o, const std::string& s) { o.boundary = boundary_from(s); })
      .def_readwrite("normals", &LimitOptions::normals);
  py::class_<LimitResult>(m, "LimitResult")
      .def_property_readonly("positions", [](const LimitResult& r) { return rows3(r.positions); })
      .def_property_readonly("normals",
                             [](const LimitResult& r) -> py::object {
                               if (r.normals.empty()) return py::none();
                               return rows3(r.normals);
                             })
      .def_readonly("max_distance", &LimitResult::max_distance)
      .def_readonly("rms_distance", &LimitResult::rms_distance);
  m.def(
      "limit_positions",
      [](const SurfaceMesh& mesh, const LimitOptions& options) {
        py::gil_scoped_release release;
        return limit_positions(mesh, options);
      },
      py::arg("mesh"), py::arg("options") = LimitOptions{});
}

}  // namespace geom::python
