// Marching cubes: geom (1 thread and TBB) against scikit-image's marching_cubes (a Python
// subprocess on the same .npy field, timing only the call) and OpenVDB's volumeToMesh (on a
// narrow-band grid built from the same field, build not timed), with the same topology checks
// applied to every output. Then the accuracy-versus-time table for geom: resolution 32…512
// against time, triangles, vertex distance to the analytic sphere/torus and the sampled
// symmetric Hausdorff distance to it. Then the signed distance to a mesh (--sdf) at 128…512:
// sampling time, exact samples, time of the extraction.
//
// usage: bench_isosurface [--sizes 256,512] [--repeats N] [--no-skimage] [--no-openvdb]
// CSV: isosurface.csv, isosurface_accuracy.csv, isosurface_sdf.csv in $GEOM_BENCH_OUT
// (default ./bench-out).
// PNG (what accuracy costs in time), one command:
//   bench/plot.py bench-out/isosurface_accuracy.csv --x ours_1t_ms --y hausdorff --group field
//       --logx --logy --title "marching cubes: Hausdorff distance against time (32..512)"
//       -o bench-out/isosurface_accuracy.png

#include "support/harness.h"

#include <geom/io/grid.h>
#include <geom/isosurface/implicit.h>
#include <geom/isosurface/marching_cubes.h>
#include <geom/isosurface/mesh_sdf.h>
#include <geom/spatial/bvh.h>

#ifdef GEOM_BENCH_HAVE_OPENVDB
#include <openvdb/openvdb.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <openvdb/tools/VolumeToMesh.h>
#endif

#include <tbb/global_control.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

using namespace geom;
using geom::bench::fmt;
using geom::bench::ratio;
using geom::bench::time_min;

namespace {

/// Topology of a triangle list, by edge counting (the same checks for every peer).
struct Quality {
  std::size_t triangles = 0, vertices = 0;
  std::size_t boundary_edges = 0;  ///< directed edges without a reverse: holes and cracks
  std::size_t repeated_edges = 0;  ///< directed edges used twice: >2 faces or flipped faces
  std::size_t degenerate = 0;      ///< zero-area triangles
  std::size_t duplicate_vertices = 0;  ///< distinct vertices at the same position
  long euler = 0;
  bool watertight() const { return boundary_edges == 0 && repeated_edges == 0; }
  std::string text() const {
    if (watertight() && degenerate == 0 && duplicate_vertices == 0) return "closed,manifold chi=" + std::to_string(euler);
    return "open=" + std::to_string(boundary_edges) + " rep=" + std::to_string(repeated_edges) +
           " degen=" + std::to_string(degenerate) + " dupv=" + std::to_string(duplicate_vertices);
  }
};

Quality check(const std::vector<std::array<double, 3>>& pos,
              const std::vector<std::array<std::uint32_t, 3>>& tris) {
  Quality q;
  q.triangles = tris.size();
  q.vertices = pos.size();
  std::vector<std::uint64_t> directed;
  directed.reserve(3 * tris.size());
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) directed.push_back(std::uint64_t(t[k]) << 32 | t[(k + 1) % 3]);
    const auto &a = pos[t[0]], &b = pos[t[1]], &c = pos[t[2]];
    double u[3], v[3];
    for (int k = 0; k < 3; ++k) u[k] = b[k] - a[k], v[k] = c[k] - a[k];
    double cx = u[1] * v[2] - u[2] * v[1], cy = u[2] * v[0] - u[0] * v[2], cz = u[0] * v[1] - u[1] * v[0];
    q.degenerate += (cx == 0 && cy == 0 && cz == 0) || t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
  }
  std::sort(directed.begin(), directed.end());
  std::size_t matched = 0;
  for (std::size_t i = 0; i < directed.size(); ++i) {
    if (i + 1 < directed.size() && directed[i] == directed[i + 1]) ++q.repeated_edges;
    std::uint64_t rev = directed[i] << 32 | directed[i] >> 32;
    if (std::binary_search(directed.begin(), directed.end(), rev))
      ++matched;
    else
      ++q.boundary_edges;
  }
  std::vector<std::array<double, 3>> sorted = pos;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i + 1 < sorted.size(); ++i) q.duplicate_vertices += sorted[i] == sorted[i + 1];
  q.euler = long(pos.size()) - long(matched / 2 + q.boundary_edges) + long(tris.size());
  return q;
}

Quality check(const IsoSurface& s) {
  std::vector<std::array<double, 3>> pos(s.positions.size());
  for (std::size_t i = 0; i < pos.size(); ++i) pos[i] = {s.positions[i].x(), s.positions[i].y(), s.positions[i].z()};
  return check(pos, s.triangles);
}

/// Smooth value noise (trilinear on a random 12³ lattice, smoothstep weights), closed off by
/// a positive shell near the box so every peer's surface should be closed.
struct Noise {
  std::vector<double> lattice;
  static constexpr int kG = 12;
  Noise() {
    std::mt19937 rng(2024);
    std::uniform_real_distribution<double> u(-1, 1);
    lattice.resize(kG * kG * kG);
    for (double& v : lattice) v = u(rng);
  }
  double operator()(const Eigen::Vector3d& p) const {
    double c[3];
    int i[3];
    for (int k = 0; k < 3; ++k) {
      double s = (p[k] + 1.0) * 0.5 * (kG - 1);
      s = std::clamp(s, 0.0, kG - 1.000001);
      i[k] = int(s);
      double f = s - i[k];
      c[k] = f * f * (3 - 2 * f);
    }
    double v = 0;
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          double w = (dx ? c[0] : 1 - c[0]) * (dy ? c[1] : 1 - c[1]) * (dz ? c[2] : 1 - c[2]);
          v += w * lattice[(i[0] + dx) + kG * ((i[1] + dy) + kG * (i[2] + dz))];
        }
    return std::max(v, 4.0 * (p.cwiseAbs().maxCoeff() - 0.9));
  }
};

struct PeerResult {
  bool ran = false;
  double seconds = 0, seconds_1t = 0;
  Quality quality;
  std::string note;
};

PeerResult run_skimage(const ScalarGrid& g, double level, int repeats) {
  PeerResult r;
  auto dir = geom::bench::out_dir();
  std::filesystem::create_directories(dir);
  auto npy = dir / "isosurface_field.npy";
  write_npy(npy, g.dims().nx, g.dims().ny, g.dims().nz, g.floats());
  auto prefix = (dir / "isosurface_skimage").string();
  std::string cmd = std::string("/usr/bin/python3 ") + GEOM_ISO_SKIMAGE_SCRIPT + " " + npy.string() + " " +
                    fmt(level, 17) + " " + std::to_string(repeats) + " " + prefix;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) {
    r.note = "popen failed";
    return r;
  }
  std::string out;
  char buf[512];
  while (fgets(buf, sizeof buf, p)) out += buf;
  if (pclose(p) != 0 || out.find("seconds") == std::string::npos) {
    r.note = "skimage failed: " + out;
    return r;
  }
  auto number = [&](const std::string& key) {
    auto k = out.find("\"" + key + "\": ");
    return std::stod(out.substr(k + key.size() + 4));
  };
  r.ran = true;
  r.seconds = r.seconds_1t = number("seconds");
  auto read = [](const std::string& path, auto& vec) {
    std::ifstream f(path, std::ios::binary);
    f.seekg(0, std::ios::end);
    std::size_t bytes = std::size_t(f.tellg());
    f.seekg(0);
    vec.resize(bytes / sizeof(vec[0]));
    f.read(reinterpret_cast<char*>(vec.data()), std::streamsize(bytes));
  };
  std::vector<std::array<double, 3>> verts;
  std::vector<std::array<std::int32_t, 3>> faces;
  read(prefix + ".verts", verts);
  read(prefix + ".faces", faces);
  std::vector<std::array<std::uint32_t, 3>> tris(faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (int k = 0; k < 3; ++k) tris[i][k] = std::uint32_t(faces[i][k]);
  r.quality = check(verts, tris);
  std::filesystem::remove(prefix + ".verts");
  std::filesystem::remove(prefix + ".faces");
  std::filesystem::remove(npy);
  return r;
}

#ifdef GEOM_BENCH_HAVE_OPENVDB
/// OpenVDB on a narrow band: voxels within one voxel of a sign change (6-neighbours) are
/// active, the rest are filled with ±background by signedFloodFill, as a level set would be.
PeerResult run_openvdb(const ScalarGrid& g, double level, int repeats) {
  PeerResult r;
  openvdb::initialize();
  const auto d = g.dims();
  auto vals = g.floats();
  const float lv = float(level);
  std::vector<std::uint8_t> band(d.size(), 0);
  auto idx = [&](std::size_t x, std::size_t y, std::size_t z) { return x + d.nx * (y + d.ny * z); };
  for (std::size_t z = 0; z < d.nz; ++z)
    for (std::size_t y = 0; y < d.ny; ++y)
      for (std::size_t x = 0; x < d.nx; ++x) {
        bool s = vals[idx(x, y, z)] >= lv;
        bool cross = (x + 1 < d.nx && (vals[idx(x + 1, y, z)] >= lv) != s) ||
                     (y + 1 < d.ny && (vals[idx(x, y + 1, z)] >= lv) != s) ||
                     (z + 1 < d.nz && (vals[idx(x, y, z + 1)] >= lv) != s);
        if (cross) {
          for (int dz = -1; dz <= 2; ++dz)
            for (int dy = -1; dy <= 2; ++dy)
              for (int dx = -1; dx <= 2; ++dx) {
                long X = long(x) + dx, Y = long(y) + dy, Z = long(z) + dz;
                if (X >= 0 && Y >= 0 && Z >= 0 && X < long(d.nx) && Y < long(d.ny) && Z < long(d.nz))
                  band[idx(X, Y, Z)] = 1;
              }
        }
      }
  float maxabs = 0;
  for (float v : vals) maxabs = std::max(maxabs, std::abs(v - lv));
  auto grid = openvdb::FloatGrid::create(maxabs + 1.0f);
  auto acc = grid->getAccessor();
  for (std::size_t z = 0; z < d.nz; ++z)
    for (std::size_t y = 0; y < d.ny; ++y)
      for (std::size_t x = 0; x < d.nx; ++x)
        if (band[idx(x, y, z)])
          acc.setValue(openvdb::Coord(int(x), int(y), int(z)), vals[idx(x, y, z)] - lv);
  openvdb::tools::signedFloodFill(grid->tree());
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec3I> triangles;
  std::vector<openvdb::Vec4I> quads;
  auto once = [&] {
    points.clear();
    triangles.clear();
    quads.clear();
    openvdb::tools::volumeToMesh(*grid, points, triangles, quads, 0.0, 0.0);
  };
  r.seconds = time_min(once, repeats);
  {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    r.seconds_1t = time_min(once, repeats);
  }
  r.ran = true;
  std::vector<std::array<double, 3>> pos(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) pos[i] = {points[i][0], points[i][1], points[i][2]};
  std::vector<std::array<std::uint32_t, 3>> tris;
  tris.reserve(triangles.size() + 2 * quads.size());
  for (const auto& t : triangles) tris.push_back({t[0], t[1], t[2]});
  for (const auto& q : quads) {
    tris.push_back({q[0], q[1], q[2]});
    tris.push_back({q[0], q[2], q[3]});
  }
  r.quality = check(pos, tris);
  return r;
}
#endif

double ms(double s) { return 1000.0 * s; }

/// Sampled symmetric Hausdorff distance between an extracted surface and the analytic one
/// (f an exact signed distance): surface → analytic exactly by |f| at every vertex and at
/// `samples` area-weighted random points on the triangles; analytic → surface by
/// closest-point queries on a BVH of the output (geom/spatial, as `geom compare`) from
/// `samples` points spread uniformly by area over the analytic surface.
double hausdorff(const IsoSurface& s, const ScalarFunction& f,
                 const std::function<Point(std::mt19937_64&)>& on_surface, std::size_t samples) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst = 0;
  for (const Point& p : s.positions) worst = std::max(worst, std::abs(f(p)));
  std::vector<double> cumulative(s.triangles.size());
  double total = 0;
  for (std::size_t i = 0; i < s.triangles.size(); ++i) {
    const auto& t = s.triangles[i];
    total += (s.positions[t[1]] - s.positions[t[0]]).cross(s.positions[t[2]] - s.positions[t[0]]).norm();
    cumulative[i] = total;
  }
  for (std::size_t k = 0; k < samples && total > 0; ++k) {
    auto it = std::lower_bound(cumulative.begin(), cumulative.end(), u(rng) * total);
    const auto& t = s.triangles[std::min<std::size_t>(it - cumulative.begin(), s.triangles.size() - 1)];
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    Point p = s.positions[t[0]] + a * (s.positions[t[1]] - s.positions[t[0]]) +
              b * (s.positions[t[2]] - s.positions[t[0]]);
    worst = std::max(worst, std::abs(f(p)));
  }
  TriangleBvh bvh(s.positions, s.triangles);
  for (std::size_t k = 0; k < samples; ++k)
    worst = std::max(worst, std::sqrt(bvh.distance_squared(on_surface(rng))));
  return worst;
}

/// Uniform (by area) points on the sphere |p| = r.
Point on_sphere(std::mt19937_64& rng, double r) {
  std::normal_distribution<double> n(0.0, 1.0);
  Point p(n(rng), n(rng), n(rng));
  return r * p.normalized();
}

/// Uniform (by area) points on the torus around z: the tube angle is accepted with
/// probability proportional to the distance from the axis.
Point on_torus(std::mt19937_64& rng, double major, double minor) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double two_pi = 2 * std::acos(-1.0);
  for (;;) {
    double theta = two_pi * u(rng), phi = two_pi * u(rng);
    double ring = major + minor * std::cos(phi);
    if (u(rng) * (major + minor) > ring) continue;
    return Point(ring * std::cos(theta), ring * std::sin(theta), minor * std::sin(phi));
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (geom::bench::wants_help(argc, argv, "usage: bench_isosurface [--sizes 256,512] [--repeats N] [--no-skimage] [--no-openvdb]")) return 0;
  std::vector<std::size_t> sizes = {256, 512};
  int repeats = 5;
  bool skimage = true, openvdb = true;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--sizes" && i + 1 < argc) {
      sizes.clear();
      std::string s = argv[++i];
      for (std::size_t pos = 0; pos < s.size();) {
        std::size_t end = s.find(',', pos);
        sizes.push_back(std::stoul(s.substr(pos, end - pos)));
        pos = end == std::string::npos ? s.size() : end + 1;
      }
    } else if (a == "--repeats" && i + 1 < argc) {
      repeats = std::stoi(argv[++i]);
    } else if (a == "--no-skimage") {
      skimage = false;
    } else if (a == "--no-openvdb") {
      openvdb = false;
    }
  }
#ifndef GEOM_BENCH_HAVE_OPENVDB
  openvdb = false;
  std::cerr << "note: built without OpenVDB; its columns are n/a\n";
#endif

  struct Field {
    std::string name;
    ScalarFunction f;
  };
  std::vector<Field> fields = {
      {"sphere", implicit::Sphere{Eigen::Vector3d::Zero(), 0.8}},
      {"torus", implicit::Torus{Eigen::Vector3d::Zero(), 0.6, 0.25}},
      {"noise", Noise{}},
  };

  geom::bench::Table table({"field", "n", "ours_1t_ms", "ours_tbb_ms", "ours_mesh_1t_ms", "tris",
                            "skimage_ms", "sk_tris", "ours/sk", "vdb_1t_ms", "vdb_tbb_ms", "vdb_tris",
                            "ours1t/vdb1t", "ours", "skimage", "openvdb"});
  for (std::size_t n : sizes)
    for (const Field& field : fields) {
      ScalarGrid g = sample(field.f, cube_box(1.0, n));
      const int reps = n >= 512 ? std::max(1, repeats / 2) : repeats;
      IsoSurface s;
      double t1 = time_min([&] { s = marching_cubes_arrays(g.view(), {.parallel = false}); }, reps);
      double tp = time_min([&] { s = marching_cubes_arrays(g.view(), {.parallel = true}); }, reps);
      double tm = time_min([&] { auto m = marching_cubes(g.view(), {.parallel = false}); }, std::max(1, reps / 2));
      Quality ours = check(s);
      PeerResult sk, vdb;
      if (skimage) sk = run_skimage(g, 0.0, std::max(1, reps / 2));
#ifdef GEOM_BENCH_HAVE_OPENVDB
      if (openvdb) vdb = run_openvdb(g, 0.0, reps);
#endif
      if (!sk.note.empty()) std::cerr << sk.note << '\n';
      table.add({field.name, std::to_string(n), fmt(ms(t1)), fmt(ms(tp)), fmt(ms(tm)),
                 std::to_string(s.triangles.size()), sk.ran ? fmt(ms(sk.seconds)) : "n/a",
                 sk.ran ? std::to_string(sk.quality.triangles) : "n/a", ratio(t1, sk.ran ? sk.seconds : 0),
                 vdb.ran ? fmt(ms(vdb.seconds_1t)) : "n/a", vdb.ran ? fmt(ms(vdb.seconds)) : "n/a",
                 vdb.ran ? std::to_string(vdb.quality.triangles) : "n/a",
                 ratio(t1, vdb.ran ? vdb.seconds_1t : 0), ours.text(), sk.ran ? sk.quality.text() : "n/a",
                 vdb.ran ? vdb.quality.text() : "n/a"});
      std::cerr << "done " << field.name << " " << n << "\n";
    }
  table.print();
  table.write_csv(geom::bench::out_dir() / "isosurface.csv");

  // What accuracy costs in time: vertex distance to the analytic surface (in units of the
  // box half-width 1, and of the grid step h).
  geom::bench::Table acc({"field", "n", "h", "ours_1t_ms", "tris", "max_dist", "mean_dist", "max_dist/h",
                          "hausdorff", "hausdorff/h"});
  std::vector<std::size_t> res = {32, 64, 128, 256, 512};
  for (const char* name : {"sphere", "torus"}) {
    ScalarFunction f = std::string(name) == "sphere" ? ScalarFunction(implicit::Sphere{Eigen::Vector3d::Zero(), 0.8})
                                                     : ScalarFunction(implicit::Torus{Eigen::Vector3d::Zero(), 0.6, 0.25});
    for (std::size_t n : res) {
      if (n > *std::max_element(sizes.begin(), sizes.end())) continue;
      ScalarGrid g = sample(f, cube_box(1.0, n));
      IsoSurface s;
      double t = time_min([&] { s = marching_cubes_arrays(g.view(), {.parallel = false}); }, repeats);
      double mx = 0, mean = 0;
      for (const Point& p : s.positions) {
        double dd = std::abs(f(p));
        mx = std::max(mx, dd);
        mean += dd;
      }
      mean /= double(std::max<std::size_t>(1, s.positions.size()));
      double h = 2.0 / double(n - 1);
      const bool sphere = std::string(name) == "sphere";
      double hd = hausdorff(
          s, f,
          [&](std::mt19937_64& rng) { return sphere ? on_sphere(rng, 0.8) : on_torus(rng, 0.6, 0.25); },
          200000);
      acc.add({name, std::to_string(n), fmt(h, 4), fmt(ms(t)), std::to_string(s.triangles.size()), fmt(mx, 4),
               fmt(mean, 4), fmt(mx / h, 4), fmt(hd, 4), fmt(hd / h, 4)});
    }
  }
  acc.print();
  acc.write_csv(geom::bench::out_dir() / "isosurface_accuracy.csv");

  // Signed distance to a mesh: a 0.8-sphere extracted at 256³ (~0.5 M triangles) resampled
  // at 128…512 (sampling time, how many samples needed their own query, extraction time,
  // and the vertex distance of the result to the analytic sphere).
  {
    SurfaceMesh input = marching_cubes(sample(implicit::Sphere{Eigen::Vector3d::Zero(), 0.8}, cube_box(1.0, 256)).view()).mesh;
    MeshSignedDistance distance(input);
    geom::bench::Table sdf({"input_tris", "n", "sdf_ms", "samples", "exact_samples", "exact_%", "mc_1t_ms",
                            "tris", "max_dist"});
    for (std::size_t n : {128, 256, 512}) {
      if (n > *std::max_element(sizes.begin(), sizes.end())) continue;
      MeshSdf grid;
      double ts = time_min([&] { grid = signed_distance_grid(distance, {.resolution = n}); }, std::max(1, repeats / 2));
      IsoSurface s;
      double tm = time_min([&] { s = marching_cubes_arrays(grid.grid.view(), {.parallel = false}); }, repeats);
      double mx = 0;
      for (const Point& p : s.positions) mx = std::max(mx, std::abs(p.norm() - 0.8));
      sdf.add({std::to_string(input.n_faces()), std::to_string(n), fmt(ms(ts)), std::to_string(grid.stats.samples),
               std::to_string(grid.stats.exact_samples),
               fmt(100.0 * double(grid.stats.exact_samples) / double(grid.stats.samples), 3), fmt(ms(tm)),
               std::to_string(s.triangles.size()), fmt(mx, 4)});
    }
    sdf.print();
    sdf.write_csv(geom::bench::out_dir() / "isosurface_sdf.csv");
  }
  return 0;
}
