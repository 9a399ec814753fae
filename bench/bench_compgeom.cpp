// compgeom benchmark: ours and CGAL (Epick) side by side in one process, plus the "what
// accuracy costs in time" table (exact-adaptive vs plain floating-point predicates).
#include <geom/compgeom/delaunay2.h>
#include <geom/compgeom/hull2.h>
#include <geom/compgeom/hull3.h>
#include <support/harness.h>

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/convex_hull_3.h>

#include <Eigen/Geometry>

#include <cmath>
#include <iostream>
#include <numbers>
#include <random>

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using V2 = Eigen::Vector2d;
using V3 = Eigen::Vector3d;
using geom::bench::fmt;
using geom::bench::ratio;
using geom::bench::time_min;

std::vector<V2> uniform2(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<V2> p(n);
  for (auto& q : p) q = {u(rng), u(rng)};
  return p;
}

std::vector<V2> grid2(int w) {
  std::vector<V2> p;
  for (int y = 0; y < w; ++y)
    for (int x = 0; x < w; ++x) p.push_back({double(x), double(y)});
  std::shuffle(p.begin(), p.end(), std::mt19937(1));
  return p;
}

std::vector<V3> ball3(std::size_t n, bool surface, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<V3> p;
  while (p.size() < n) {
    V3 q(u(rng), u(rng), u(rng));
    if (q.squaredNorm() > 1 || q.squaredNorm() < 1e-6) continue;
    p.push_back(surface ? q.normalized() : q);
  }
  return p;
}

std::vector<K::Point_2> to_cgal(const std::vector<V2>& p) {
  std::vector<K::Point_2> out;
  out.reserve(p.size());
  for (const V2& q : p) out.push_back({q.x(), q.y()});
  return out;
}

std::vector<K::Point_3> to_cgal(const std::vector<V3>& p) {
  std::vector<K::Point_3> out;
  out.reserve(p.size());
  for (const V3& q : p) out.push_back({q.x(), q.y(), q.z()});
  return out;
}

// Hard inputs for the accuracy table.
std::vector<std::pair<std::string, std::vector<V2>>> hard_cases() {
  std::vector<std::pair<std::string, std::vector<V2>>> c;
  c.push_back({"grid 60x60", grid2(60)});
  auto g = grid2(60);
  for (auto& q : g) q = q * 1e-12;
  c.push_back({"grid 1e-12", g});
  g = grid2(60);
  for (auto& q : g) q += V2(1e9, 1e9);
  c.push_back({"grid +1e9", g});
  std::vector<V2> poly;
  for (int i = 0; i < 1000; ++i)
    poly.push_back(
        {std::cos(2 * std::numbers::pi * i / 1000), std::sin(2 * std::numbers::pi * i / 1000)});
  c.push_back({"1000-gon", poly});
  poly.push_back({0, 0});
  c.push_back({"1000-gon + centre", poly});
  std::vector<V2> lat;
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 60; ++x)
      lat.push_back({std::cos(0.5) * x - std::sin(0.5) * y, std::sin(0.5) * x + std::cos(0.5) * y});
  c.push_back({"rotated lattice", lat});
  std::vector<V2> line;
  for (int i = 0; i < 1000; ++i) line.push_back({0.1 * i, 0.3 * i});
  line.push_back({50.05, 150.15 + 1e-9});
  c.push_back({"collinear + 1e-9", line});
  auto u = uniform2(10000, 3);
  for (auto& q : u) q += V2(1e9, 1e9);
  c.push_back({"uniform +1e9", u});
  std::vector<V2> near;  // points a few ulps off a circle
  std::mt19937_64 rng(9);
  for (int i = 0; i < 5000; ++i) {
    double t = std::uniform_real_distribution<double>(0, 6.283)(rng);
    near.push_back({1e3 + std::cos(t), 1e3 + std::sin(t)});
  }
  c.push_back({"near-cocircular +1e3", near});
  return c;
}

}  // namespace

// Usage: bench_compgeom [ROW-SUBSTRING]; with an argument only the matching rows run.
int main(int argc, char** argv) {
  if (geom::bench::wants_help(argc, argv, "usage: bench_compgeom [ROW-SUBSTRING]   (only the rows whose name contains it)")) return 0;
  const std::string only = argc > 1 ? argv[1] : "";
  auto want = [&](const std::string& row) {
    return only.empty() || row.find(only) != std::string::npos;
  };
  geom::bench::Table table({"input", "ours_s", "cgal_s", "ratio", "accuracy"});
  if (want("delaunay 1M uniform")) {
    auto p = uniform2(1000000, 1);
    auto cp = to_cgal(p);
    geom::DelaunayResult r;
    double ours = time_min([&] { r = geom::delaunay_2d(p); });
    std::size_t faces = 0;
    double cgal = time_min([&] {
      CGAL::Delaunay_triangulation_2<K> dt;
      dt.insert(cp.begin(), cp.end());
      faces = dt.number_of_faces();
    });
    table.add({"delaunay 1M uniform", fmt(ours), fmt(cgal), ratio(ours, cgal),
               "triangles " + std::to_string(r.triangles.size()) + " vs " + std::to_string(faces) +
                   ", exact fallback " + fmt(100 * r.predicates.exact_rate(), 2) + "%"});
  }
  if (want("delaunay 1M grid")) {
    auto p = grid2(1000);
    auto cp = to_cgal(p);
    geom::DelaunayResult r;
    double ours = time_min([&] { r = geom::delaunay_2d(p); });
    std::size_t faces = 0;
    double cgal = time_min([&] {
      CGAL::Delaunay_triangulation_2<K> dt;
      dt.insert(cp.begin(), cp.end());
      faces = dt.number_of_faces();
    });
    table.add({"delaunay 1M grid", fmt(ours), fmt(cgal), ratio(ours, cgal),
               "triangles " + std::to_string(r.triangles.size()) + " vs " + std::to_string(faces) +
                   ", exact fallback " + fmt(100 * r.predicates.exact_rate(), 2) + "%"});
  }
  using Mesh = CGAL::Surface_mesh<K::Point_3>;
  for (auto [name, n, surface] : {std::tuple{"hull3 1M ball", 1000000, false},
                                  std::tuple{"hull3 100k sphere", 100000, true}}) {
    if (!want(name)) continue;
    auto p = ball3(n, surface, 2);
    auto cp = to_cgal(p);
    geom::Hull3Result r;
    double ours = time_min([&] { r = geom::convex_hull_3d(p); });
    std::size_t faces = 0, verts = 0;
    double cgal = time_min([&] {
      Mesh m;
      CGAL::convex_hull_3(cp.begin(), cp.end(), m);
      faces = m.number_of_faces();
      verts = m.number_of_vertices();
    });
    table.add({name, fmt(ours), fmt(cgal), ratio(ours, cgal),
               "vertices " + std::to_string(r.vertices.size()) + " vs " + std::to_string(verts) +
                   ", facets " + std::to_string(r.triangles.size()) + " vs " +
                   std::to_string(faces)});
  }
  for (auto [name, disk] :
       {std::pair{"hull2 1M square", false}, std::pair{"hull2 1M disk", true}}) {
    if (!want(name)) continue;
    auto p = uniform2(1000000, 4);
    if (disk)
      for (auto& q : p) {
        double r = std::sqrt(q.x()), t = 2 * std::numbers::pi * q.y();
        q = {r * std::cos(t), r * std::sin(t)};
      }
    auto cp = to_cgal(p);
    geom::Hull2Result r;
    double ours = time_min([&] { r = geom::convex_hull_2d(p); }, 5);
    std::size_t hv = 0;
    double cgal = time_min(
        [&] {
          std::vector<K::Point_2> out;
          CGAL::convex_hull_2(cp.begin(), cp.end(), std::back_inserter(out));
          hv = out.size();
        },
        5);
    table.add({name, fmt(ours), fmt(cgal), ratio(ours, cgal),
               "vertices " + std::to_string(r.vertices.size()) + " vs " + std::to_string(hv)});
  }
  table.print();
  table.write_csv(geom::bench::out_dir() / "compgeom.csv");
  if (!want("accuracy")) return 0;

  // What accuracy costs: the same Delaunay code with plain floating-point predicates.
  geom::bench::Table acc(
      {"predicates", "delaunay_1M_s", "time_ratio", "hard_cases_wrong", "failures"});
  auto p = uniform2(1000000, 1);
  double exact_t = time_min([&] { geom::delaunay_2d(p); });
  double float_t = time_min([&] {
    try {
      geom::delaunay_2d(p, {.exact = false});
    } catch (const geom::Error&) {
    }
  });
  auto cases = hard_cases();
  for (bool exact : {true, false}) {
    int wrong = 0;
    std::string failures;
    for (const auto& [name, pts] : cases) {
      std::string why;
      try {
        auto r = geom::delaunay_2d(pts, {.exact = exact});
        why = geom::check_delaunay_2d(pts, r.triangles);
      } catch (const geom::Error& e) {
        why = std::string("threw: ") + e.what();
      }
      if (!why.empty()) {
        ++wrong;
        failures += (failures.empty() ? "" : "; ") + name;
      }
    }
    double t = exact ? exact_t : float_t;
    acc.add({exact ? "exact-adaptive" : "plain double", fmt(t), ratio(t, exact_t),
             std::to_string(wrong) + "/" + std::to_string(cases.size()),
             failures.empty() ? "-" : failures});
  }
  std::cout << '\n';
  acc.print();
  acc.write_csv(geom::bench::out_dir() / "compgeom_accuracy.csv");
  return 0;
}
