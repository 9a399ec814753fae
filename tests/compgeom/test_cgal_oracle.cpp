// Oracle tests against CGAL (Epick kernel): the only file of the compgeom tests that includes
// CGAL, so its slow compile happens once.
#include <geom/compgeom/delaunay2.h>
#include <geom/compgeom/hull2.h>
#include <geom/compgeom/hull3.h>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <set>

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::uint32_t, K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb>;
using DT = CGAL::Delaunay_triangulation_2<K, Tds>;
using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;
using Tri = std::array<std::uint32_t, 3>;

Tri canonical(Tri t) {
  std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
  return t;
}

std::set<Tri> ours_set(const std::vector<Tri>& ts) {
  std::set<Tri> s;
  for (const Tri& t : ts) s.insert(canonical(t));
  return s;
}

DT cgal_dt(const std::vector<V2>& p) {
  std::vector<std::pair<K::Point_2, std::uint32_t>> in;
  for (std::uint32_t i = 0; i < p.size(); ++i) in.push_back({{p[i].x(), p[i].y()}, i});
  DT dt;
  dt.insert(in.begin(), in.end());
  return dt;
}

std::set<Tri> cgal_set(const DT& dt) {
  std::set<Tri> s;
  for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f)
    s.insert(canonical({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()}));
  return s;
}

std::vector<V2> uniform(std::size_t n, std::uint64_t seed, double scale = 1, double offset = 0) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<V2> p(n);
  for (auto& q : p) q = V2(offset + scale * u(rng), offset + scale * u(rng));
  return p;
}

TEST(CgalOracle, DelaunayTrianglesIdenticalOnRandomInput) {
  for (auto [scale, offset] : {std::pair{1.0, 0.0}, std::pair{1.0, 1e9}, std::pair{1e-12, 0.0}}) {
    auto p = uniform(20000, 11, scale, offset);
    auto ours = geom::delaunay_2d(p);
    DT dt = cgal_dt(p);
    EXPECT_EQ(ours_set(ours.triangles), cgal_set(dt)) << "scale " << scale << " offset " << offset;
  }
}

// Hard cases where the triangulation is not unique: ours must be Delaunay under exact
// predicates and have CGAL's triangle count.
std::vector<std::pair<std::string, std::vector<V2>>> hard_cases() {
  std::vector<std::pair<std::string, std::vector<V2>>> cases;
  std::vector<V2> grid;
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 60; ++x) grid.push_back({double(x), double(y)});
  cases.push_back({"grid 60x60", grid});
  std::vector<V2> grid_off = grid;
  for (auto& q : grid_off) q += V2(1e9, 1e9);
  cases.push_back({"grid offset 1e9", grid_off});
  std::vector<V2> grid_tiny = grid;
  for (auto& q : grid_tiny) q *= 1e-12;
  cases.push_back({"grid scaled 1e-12", grid_tiny});
  std::vector<V2> poly;
  for (int i = 0; i < 1000; ++i) {
    double t = 2 * std::numbers::pi * i / 1000;
    poly.push_back({std::cos(t), std::sin(t)});
  }
  cases.push_back({"1000-gon", poly});
  std::vector<V2> lat;
  const double c = std::cos(0.5), s = std::sin(0.5);
  for (int y = 0; y < 40; ++y)
    for (int x = 0; x < 40; ++x) lat.push_back({c * x - s * y, s * x + c * y});
  cases.push_back({"rotated lattice", lat});
  std::vector<V2> dup = uniform(2000, 5);
  for (int k = 0; k < 3; ++k) dup.insert(dup.end(), dup.begin(), dup.begin() + 700);
  for (int k = 0; k < 500; ++k) dup.push_back(dup[3]);
  cases.push_back({"duplicates", dup});
  std::vector<V2> circles;
  for (int r = 1; r <= 10; ++r)
    for (int i = 0; i < 8 * r; ++i) {
      double t = 2 * std::numbers::pi * i / (8 * r);
      circles.push_back({r * std::cos(t), r * std::sin(t)});
    }
  cases.push_back({"concentric circles", circles});
  std::vector<V2> line;
  for (int i = 0; i < 100; ++i) line.push_back({double(i), 2.0 * i});
  line.push_back({50.5, 101 + 1e-9});
  cases.push_back({"collinear + one off by 1e-9", line});
  std::vector<V2> integer_circle;  // the 12 lattice points with x^2 + y^2 = 25, and more
  for (int x = -25; x <= 25; ++x)
    for (int y = -25; y <= 25; ++y)
      if (x * x + y * y == 625 || x * x + y * y == 25)
        integer_circle.push_back({double(x), double(y)});
  cases.push_back({"integer circles", integer_circle});
  return cases;
}

TEST(CgalOracle, DelaunayHardCasesAreDelaunayWithCgalsTriangleCount) {
  for (const auto& [name, p] : hard_cases()) {
    auto ours = geom::delaunay_2d(p);
    EXPECT_EQ(geom::check_delaunay_2d(p, ours.triangles), "") << name;
    DT dt = cgal_dt(p);
    EXPECT_EQ(ours.triangles.size(), dt.number_of_faces()) << name;
    EXPECT_EQ(ours.vertices, dt.number_of_vertices()) << name;
  }
}

TEST(CgalOracle, Hull2SameExtremePoints) {
  std::vector<std::vector<V2>> inputs = {uniform(20000, 7), uniform(5000, 8, 1, 1e9)};
  for (const auto& [name, p] : hard_cases()) inputs.push_back(p);
  for (const auto& p : inputs) {
    auto ours = geom::convex_hull_2d(p);
    std::vector<K::Point_2> in, out;
    for (const V2& q : p) in.push_back({q.x(), q.y()});
    CGAL::convex_hull_2(in.begin(), in.end(), std::back_inserter(out));
    std::set<std::pair<double, double>> a, b;
    for (auto i : ours.vertices) a.insert({p[i].x(), p[i].y()});
    for (const auto& q : out) b.insert({q.x(), q.y()});
    EXPECT_EQ(a, b);
    EXPECT_EQ(ours.vertices.size(), out.size());
  }
}

using Mesh = CGAL::Surface_mesh<K::Point_3>;

struct Hull3Summary {
  std::set<std::array<double, 3>> vertices;
  std::size_t faces = 0;
  double volume = 0;
};

Hull3Summary cgal_hull3(const std::vector<V3>& p) {
  std::vector<K::Point_3> in;
  for (const V3& q : p) in.push_back({q.x(), q.y(), q.z()});
  Mesh m;
  CGAL::convex_hull_3(in.begin(), in.end(), m);
  Hull3Summary s;
  for (auto v : m.vertices()) {
    const auto& q = m.point(v);
    s.vertices.insert({q.x(), q.y(), q.z()});
  }
  s.faces = m.number_of_faces();
  const auto& c = m.point(*m.vertices().begin());
  for (auto f : m.faces()) {
    std::vector<V3> t;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) {
      const auto& q = m.point(v);
      t.push_back(V3(q.x() - c.x(), q.y() - c.y(), q.z() - c.z()));
    }
    for (std::size_t k = 1; k + 1 < t.size(); ++k) s.volume += t[0].dot(t[k].cross(t[k + 1])) / 6;
  }
  return s;
}

Hull3Summary ours_hull3(const std::vector<V3>& p) {
  auto h = geom::convex_hull_3d(p);
  Hull3Summary s;
  for (auto i : h.vertices) s.vertices.insert({p[i].x(), p[i].y(), p[i].z()});
  s.faces = h.triangles.size();
  // Volume relative to the same corner CGAL uses is not known; use the first vertex.
  if (!h.vertices.empty()) {
    V3 c = p[h.vertices.front()];
    for (const auto& t : h.triangles)
      s.volume += (p[t[0]] - c).dot((p[t[1]] - c).cross(p[t[2]] - c)) / 6;
  }
  return s;
}

TEST(CgalOracle, Hull3GeneralPositionSameVerticesAndFacets) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> g;
  for (double offset : {0.0, 1e8}) {
    std::vector<V3> ball, sphere;
    for (int i = 0; i < 20000; ++i)
      ball.push_back(V3(g(rng), g(rng), g(rng)) + V3::Constant(offset));
    for (int i = 0; i < 3000; ++i)
      sphere.push_back(V3(g(rng), g(rng), g(rng)).normalized() + V3::Constant(offset));
    for (const auto& p : {ball, sphere}) {
      auto a = ours_hull3(p), b = cgal_hull3(p);
      EXPECT_EQ(a.vertices, b.vertices);
      EXPECT_EQ(a.faces, b.faces);
      EXPECT_NEAR(a.volume, b.volume, 1e-9 * std::fabs(b.volume) + (offset ? 1e-3 : 0));
    }
  }
}

TEST(CgalOracle, Hull3DegenerateSameVerticesAndVolume) {
  std::vector<std::vector<V3>> cases;
  std::vector<V3> cube;
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x) cube.push_back({double(x), double(y), double(z)});
  cases.push_back(cube);
  std::vector<V3> cube_off = cube;
  for (auto& q : cube_off) q += V3::Constant(1e8);
  cases.push_back(cube_off);
  std::vector<V3> dup = cube;
  dup.insert(dup.end(), cube.begin(), cube.end());
  cases.push_back(dup);
  std::vector<V3> prism;  // regular 100-gon prism: many coplanar cap points
  for (int i = 0; i < 100; ++i) {
    double t = 2 * std::numbers::pi * i / 100;
    prism.push_back({std::cos(t), std::sin(t), 0});
    prism.push_back({std::cos(t), std::sin(t), 1});
  }
  cases.push_back(prism);
  for (const auto& p : cases) {
    auto a = ours_hull3(p), b = cgal_hull3(p);
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_NEAR(a.volume, b.volume, 1e-9 * std::fabs(b.volume));
  }
}

}  // namespace
