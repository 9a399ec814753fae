// Bindings of geom/compgeom: Delaunay (constrained), Voronoi and convex hulls on numpy arrays.

#include "arrays.h"
#include "bindings.h"

#include <geom/compgeom/delaunay2.h>
#include <geom/compgeom/hull2.h>
#include <geom/compgeom/hull3.h>
#include <geom/compgeom/voronoi2.h>
#include <geom/core/errors.h>

#include <pybind11/stl.h>

#include <array>
#include <string>

namespace geom::python {

namespace {

template <int D>
std::vector<Eigen::Matrix<double, D, 1>> points_from(py::handle obj, const char* what) {
  auto arr = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!arr || arr.ndim() != 2 || arr.shape(1) != D)
    throw InvalidArgument(std::string(what) + ": expected an N×" + std::to_string(D) +
                          " array of numbers");
  std::vector<Eigen::Matrix<double, D, 1>> p(arr.shape(0));
  auto a = arr.template unchecked<2>();
  for (py::ssize_t i = 0; i < arr.shape(0); ++i)
    for (int k = 0; k < D; ++k) p[i][k] = a(i, k);
  return p;
}

template <class T, std::size_t K>
py::array_t<std::int64_t> index_array(const std::vector<std::array<T, K>>& v) {
  py::array_t<std::int64_t> out({static_cast<py::ssize_t>(v.size()), static_cast<py::ssize_t>(K)});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < v.size(); ++i)
    for (std::size_t k = 0; k < K; ++k) a(py::ssize_t(i), py::ssize_t(k)) = v[i][k];
  return out;
}

py::array_t<std::int64_t> index_vector(const std::vector<std::uint32_t>& v) {
  py::array_t<std::int64_t> out(static_cast<py::ssize_t>(v.size()));
  auto a = out.mutable_unchecked<1>();
  for (std::size_t i = 0; i < v.size(); ++i) a(py::ssize_t(i)) = v[i];
  return out;
}

py::array_t<double> polygon_array(const std::vector<Eigen::Vector2d>& p) {
  py::array_t<double> out({static_cast<py::ssize_t>(p.size()), py::ssize_t(2)});
  auto a = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < p.size(); ++i)
    a(py::ssize_t(i), 0) = p[i].x(), a(py::ssize_t(i), 1) = p[i].y();
  return out;
}

std::vector<Segment> segments_from(py::handle obj, std::size_t n) {
  std::vector<Segment> segs;
  if (obj.is_none()) return segs;
  auto arr = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!arr || arr.ndim() != 2 || arr.shape(1) != 2)
    throw InvalidArgument("segments: expected an M×2 array of point indices");
  auto a = arr.unchecked<2>();
  for (py::ssize_t i = 0; i < arr.shape(0); ++i) {
    for (int k = 0; k < 2; ++k)
      if (a(i, k) < 0 || a(i, k) >= static_cast<std::int64_t>(n))
        throw InvalidArgument("segments: row " + std::to_string(i) + " has index " +
                              std::to_string(a(i, k)) + " outside [0, " + std::to_string(n) + ")");
    segs.push_back({static_cast<std::uint32_t>(a(i, 0)), static_cast<std::uint32_t>(a(i, 1))});
  }
  return segs;
}

}  // namespace

void bind_compgeom(py::module_& m) {
  py::class_<DelaunayOptions>(m, "DelaunayOptions")
      .def(py::init<>())
      .def_readwrite("exact", &DelaunayOptions::exact);
  py::class_<ConstrainedDelaunayResult>(m, "DelaunayResult")
      .def_property_readonly(
          "triangles", [](const ConstrainedDelaunayResult& r) { return index_array(r.triangles); })
      .def_property_readonly(
          "vertex_of", [](const ConstrainedDelaunayResult& r) { return index_vector(r.vertex_of); })
      .def_property_readonly(
          "chain", [](const ConstrainedDelaunayResult& r) { return index_vector(r.chain); })
      .def_property_readonly("constrained_edges",
                             [](const ConstrainedDelaunayResult& r) {
                               std::vector<std::array<std::uint32_t, 2>> e;
                               for (const auto& s : r.constrained_edges) e.push_back({s.a, s.b});
                               return index_array(e);
                             })
      .def_readonly("vertices", &ConstrainedDelaunayResult::vertices)
      .def_readonly("duplicates", &ConstrainedDelaunayResult::duplicates)
      .def_readonly("collinear", &ConstrainedDelaunayResult::collinear)
      .def_readonly("cocircular", &ConstrainedDelaunayResult::cocircular)
      .def_readonly("split_segments", &ConstrainedDelaunayResult::split_segments)
      .def_property_readonly("exact_fallback_rate", [](const ConstrainedDelaunayResult& r) {
        return r.predicates.exact_rate();
      });
  m.def(
      "delaunay_2d",
      [](py::handle points, py::handle segments, const DelaunayOptions& options) {
        auto p = points_from<2>(points, "points");
        auto segs = segments_from(segments, p.size());
        py::gil_scoped_release release;
        return constrained_delaunay_2d(p, segs, options);
      },
      py::arg("points"), py::arg("segments") = py::none(), py::arg("options") = DelaunayOptions{});

  py::class_<VoronoiResult>(m, "VoronoiResult")
      .def_property_readonly("cells",
                             [](const VoronoiResult& r) {
                               py::list cells;
                               for (const auto& c : r.cells) cells.append(polygon_array(c));
                               return cells;
                             })
      .def_property_readonly("clip", [](const VoronoiResult& r) { return polygon_array(r.clip); })
      .def_property_readonly("vertex_of",
                             [](const VoronoiResult& r) { return index_vector(r.vertex_of); });
  m.def(
      "voronoi_2d",
      [](py::handle points, py::handle clip, double margin) {
        auto p = points_from<2>(points, "points");
        VoronoiOptions options;
        options.margin = margin;
        if (!clip.is_none()) options.clip = points_from<2>(clip, "clip");
        py::gil_scoped_release release;
        return voronoi_2d(p, options);
      },
      py::arg("points"), py::arg("clip") = py::none(), py::arg("margin") = 0.1);

  py::class_<Hull2Result>(m, "Hull2Result")
      .def_property_readonly("vertices",
                             [](const Hull2Result& r) { return index_vector(r.vertices); })
      .def_readonly("degenerate", &Hull2Result::degenerate);
  py::class_<Hull3Result>(m, "Hull3Result")
      .def_property_readonly("triangles",
                             [](const Hull3Result& r) { return index_array(r.triangles); })
      .def_property_readonly("vertices",
                             [](const Hull3Result& r) { return index_vector(r.vertices); })
      .def_property_readonly("polygon",
                             [](const Hull3Result& r) { return index_vector(r.polygon); })
      .def_readonly("dimension", &Hull3Result::dimension)
      .def_readonly("planar", &Hull3Result::planar)
      .def_property_readonly("exact_fallback_rate",
                             [](const Hull3Result& r) { return r.predicates.exact_rate(); });
  m.def(
      "convex_hull_2d",
      [](py::handle points) {
        auto p = points_from<2>(points, "points");
        py::gil_scoped_release release;
        return convex_hull_2d(p);
      },
      py::arg("points"));
  m.def(
      "convex_hull_3d",
      [](py::handle points) {
        auto p = points_from<3>(points, "points");
        py::gil_scoped_release release;
        return convex_hull_3d(p);
      },
      py::arg("points"));
}

}  // namespace geom::python
