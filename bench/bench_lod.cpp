// bench_lod: our quadric simplifier against meshoptimizer, OpenMesh and CGAL on the same
// inputs and targets; error measured by geom's sampled Hausdorff/RMS tool for everyone.
//
//   bench_lod [--faces N] [--peers ours,ours_plain,ours_refit,meshopt,openmesh,cgal,ours_attr,meshopt_attr]
//             [--slow-max-faces N] [--attr-faces N] [--attribute-weight W] [--only NAME]
//             [--peers-from CSV]
//
// --only keeps the inputs whose name contains NAME (the torus is "torus-1000k"): one mesh's
// rows in seconds rather than the whole matrix in minutes.
//
// --peers-from takes OpenMesh's and CGAL's rows from an earlier bench-out/lod.csv instead of
// running them (their results are deterministic; only their times drift): a change to ours
// is judged against the whole error matrix in seconds rather than minutes. Rows it lacks run.
// bench/reference/lod_peers.csv holds them from a full run (their times are that machine's).
//
// After the table, a summary gives each target's error ratios of ours (the default) to the
// best peer and counts the losses: the goal is every ratio below 1 within 1.5x
// meshoptimizer's wall time. Only the peers this run has rows for (run, or read with
// --peers-from) count; the summary's header names them.
//
// Times are process CPU seconds (std::clock), min of 2 runs for the fast methods: CPU time
// stays meaningful on a loaded shared machine where wall time does not. Every method is
// single-threaded except ours, whose setup (a fifth of its time at 1M triangles), collapses
// (from 50k triangles, region by region) and refit run on all cores: its CPU time counts
// every thread, so the fast methods also get their wall time (min of the same runs;
// meaningful only on an otherwise idle machine).
//
// ours is simplify()'s default, which refits the result to the input (refit.h) at targets of
// about a quarter or less, where that is cheap; ours_plain never refits (refit_iterations =
// 0) and ours_refit always does (1 round): their times include the refit, so the tradeoff
// chart shows what that accuracy costs.
//
// --faces sets the generated torus size (default 1,000,000 triangles); slow peers
// (OpenMesh, CGAL) run on inputs up to --slow-max-faces (default: all).
//
// The attribute table (bench_lod_attributes.cpp) simplifies a UV-textured torus of
// --attr-faces triangles (default: --faces) with texture coordinates steering the collapses,
// ours against meshopt_simplifyWithAttributes (or, with meshoptimizer < 0.21, meshopt_simplify
// on the seam-split buffer), and adds the UV error; it goes to bench-out/lod_attributes.csv:
//
//   bench/plot.py bench-out/lod_attributes.csv --x seconds --y uv_rms --group method
//       --logx --logy --scatter --title "LOD with UVs: UV error against time" -o bench-out/lod_attributes.png
//
// Writes bench-out/lod.csv (every input) and bench-out/lod_tradeoff.csv (the torus: what
// accuracy costs in time: one point per method and target). The chart:
//
//   bench/plot.py bench-out/lod_tradeoff.csv --x seconds --y hausdorff_rel --group method
//       --logx --logy --scatter --title "LOD: error against time" -o bench-out/lod_tradeoff.png
// (one command line; after bench_lod has run from the repository root)

#include <geom/lod/simplify.h>
#include <geom/spatial/distance.h>
#ifdef GEOM_BENCH_HAVE_IO
#include <geom/io/io.h>
#endif

#include "lod_peers.h"
#include "support/harness.h"

#include <meshoptimizer.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <ctime>
#include <numbers>
#include <random>
#include <set>

using namespace geom;
using namespace geom::bench;

namespace {

// A torus sampled on a jittered parameter grid with radial noise: irregular triangle
// shapes and sizes, like a scan, but watertight.
TriangleArrays noisy_torus(std::size_t faces) {
  const int nv = std::max(3, static_cast<int>(std::sqrt(faces / 4.0)));
  const int nu = std::max(3, static_cast<int>(faces / (2.0 * nv)));
  TriangleArrays m;
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double a = 2 * std::numbers::pi * (i + 0.3 * uni(rng)) / nu;
      const double b = 2 * std::numbers::pi * (j + 0.3 * uni(rng)) / nv;
      const double r = 0.35 * (1 + 0.01 * uni(rng)) + 0.02 * std::sin(7 * a) * std::cos(5 * b);
      m.positions.emplace_back((1 + r * std::cos(b)) * std::cos(a), (1 + r * std::cos(b)) * std::sin(a),
                               r * std::sin(b));
    }
  auto at = [&](int i, int j) { return static_cast<std::uint32_t>((i % nu) * nv + (j % nv)); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

SurfaceMesh to_mesh(const TriangleArrays& t) {
  SurfaceMesh m;
  for (const auto& p : t.positions) m.add_vertex(p);
  for (const auto& f : t.triangles) m.add_triangle(Vertex(f[0]), Vertex(f[1]), Vertex(f[2]));
  return m;
}

TriangleArrays to_arrays(const SurfaceMesh& m) {
  TriangleArrays t;
  std::vector<std::uint32_t> index(m.vertices_size(), 0);
  for (Vertex v : m.vertices()) {
    index[v.idx()] = static_cast<std::uint32_t>(t.positions.size());
    t.positions.push_back(m.position(v));
  }
  for (Face f : m.faces()) {
    std::vector<std::uint32_t> c;
    for (Vertex v : m.vertices(f)) c.push_back(index[v.idx()]);
    for (std::size_t k = 1; k + 1 < c.size(); ++k) t.triangles.push_back({c[0], c[k], c[k + 1]});
  }
  return t;
}

PeerRun simplify_meshopt(const TriangleArrays& in, std::size_t target_faces) {
  std::vector<float> pos;
  pos.reserve(in.positions.size() * 3);
  for (const auto& p : in.positions) pos.insert(pos.end(), {float(p.x()), float(p.y()), float(p.z())});
  std::vector<unsigned> idx;
  idx.reserve(in.triangles.size() * 3);
  for (const auto& t : in.triangles) idx.insert(idx.end(), t.begin(), t.end());
  std::vector<unsigned> out(idx.size());
  PeerRun run;
  std::size_t n = 0;
  const CpuWall t = cpu_wall_min([&] {
    float err = 0;
    n = meshopt_simplify(out.data(), idx.data(), idx.size(), pos.data(), in.positions.size(),
                         3 * sizeof(float), target_faces * 3, 1.0f, 0, &err);
  }, 2);
  run.seconds = t.cpu, run.wall = t.wall;
  run.mesh.positions = in.positions;
  for (std::size_t i = 0; i + 2 < n; i += 3) run.mesh.triangles.push_back({out[i], out[i + 1], out[i + 2]});
  return run;
}

PeerRun simplify_ours(const SurfaceMesh& in, std::size_t target_faces, int refit = -1) {
  PeerRun run;
  SimplifyResult r;
  const SimplifyOptions o{.target_faces = target_faces, .keep_attributes = false, .refit_iterations = refit};
  const CpuWall t = cpu_wall_min([&] { r = simplify(in, o); }, 2);
  run.seconds = t.cpu, run.wall = t.wall;
  run.mesh = to_arrays(r.mesh);
  return run;
}

struct Input {
  std::string name;
  TriangleArrays arrays;
  SurfaceMesh mesh;
};

// Rows of a lod.csv written by this program (no field holds a comma).
std::vector<std::vector<std::string>> read_csv(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("bench_lod: cannot read " + path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(f, line);) {
    std::vector<std::string> row;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) row.push_back(cell);
    if (row.size() == 11 && row[0] != "input") rows.push_back(std::move(row));
  }
  return rows;
}

const std::vector<std::string>* find_row(const std::vector<std::vector<std::string>>& rows,
                                         const std::string& input, std::size_t target,
                                         const std::string& method) {
  for (const auto& r : rows)
    if (r[0] == input && r[2] == std::to_string(target) && r[3] == method) return &r;
  return nullptr;
}

// Per input and target: ours' Hausdorff and RMS over the best peer's (meshopt, openmesh,
// cgal) and its wall time over meshoptimizer's; then the losses and the geometric means.
void print_summary(const std::vector<std::vector<std::string>>& rows) {
  Table summary({"input", "target", "H/best_peer", "RMS/best_peer", "wall_vs_meshopt"});
  int losses = 0, slow = 0, cells = 0;
  double log_h = 0, log_rms = 0;
  // Which peers the rows hold: a run with --peers ours,meshopt counts its losses against
  // meshoptimizer alone, and the header says so.
  std::set<std::string> compared;
  for (const auto& ours : rows) {
    if (ours[3] != "ours") continue;
    double h = std::numeric_limits<double>::infinity(), rms = h;
    for (const auto& r : rows)
      if (r[0] == ours[0] && r[2] == ours[2] && (r[3] == "meshopt" || r[3] == "openmesh" || r[3] == "cgal")) {
        h = std::min(h, std::stod(r[9]));
        rms = std::min(rms, std::stod(r[10]));
        compared.insert(r[3]);
      }
    if (!std::isfinite(h)) continue;
    const double rh = std::stod(ours[9]) / h, rr = std::stod(ours[10]) / rms;
    losses += (rh >= 1) + (rr >= 1);
    cells += 2;
    log_h += std::log(rh), log_rms += std::log(rr);
    const std::string wall = ours[7];
    if (wall != "n/a" && std::stod(wall) > 1.5) ++slow;
    summary.add({ours[0], ours[2], fmt(rh, 4), fmt(rr, 4), wall});
  }
  if (cells == 0) return;
  std::string names;
  for (const std::string& c : compared) names += (names.empty() ? "" : ", ") + c;
  std::cout << "\nours against the best peer of " << names << " (below 1: ours is better)\n";
  summary.print();
  std::cout << "error losses: " << losses << " of " << cells << "; geomean H " << fmt(std::exp(2 * log_h / cells), 4)
            << ", RMS " << fmt(std::exp(2 * log_rms / cells), 4) << "; targets above 1.5x meshopt's wall time: " << slow
            << " of " << cells / 2 << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t torus_faces = 1000000, slow_max = std::numeric_limits<std::size_t>::max();
  std::set<std::string> peers{"ours", "ours_plain", "ours_refit", "meshopt", "openmesh", "cgal", "ours_attr", "meshopt_attr"};
  std::size_t attr_faces = 0;
  double attr_weight = 1.0;
  std::string only;
  std::string peers_from;
  const char* const usage =
      "usage: bench_lod [--faces N] [--peers LIST] [--slow-max-faces N] [--attr-faces N]\n"
      "                 [--attribute-weight W] [--only NAME] [--peers-from CSV]\n"
      "peers: ours,ours_plain,ours_refit,meshopt,openmesh,cgal,ours_attr,meshopt_attr\n"
      "(see the comment at the top of bench/bench_lod.cpp)";
  if (wants_help(argc, argv, usage)) return 0;
  for (int i = 1; i < argc; i += 2) {
    const std::string arg = argv[i];
    if (i + 1 >= argc) {
      std::cerr << "bench_lod: " << arg << " needs a value\n";
      return 2;
    }
    const std::string val = argv[i + 1];
    if (arg == "--faces") torus_faces = std::stoul(val);
    else if (arg == "--slow-max-faces") slow_max = std::stoul(val);
    else if (arg == "--attr-faces") attr_faces = std::stoul(val);
    else if (arg == "--attribute-weight") attr_weight = std::stod(val);
    else if (arg == "--only") only = val;
    else if (arg == "--peers-from") peers_from = val;
    else if (arg == "--peers") {
      peers.clear();
      std::size_t s = 0;
      while (s <= val.size()) {
        const std::size_t e = std::min(val.find(',', s), val.size());
        peers.insert(val.substr(s, e - s));
        s = e + 1;
      }
    } else {
      std::cerr << "bench_lod: unknown option " << arg << "\n" << usage << "\n";
      return 2;
    }
  }
  const std::vector<std::vector<std::string>> earlier = peers_from.empty() ? std::vector<std::vector<std::string>>{} : read_csv(peers_from);

  std::vector<Input> inputs;
  const auto wanted = [&](const std::string& name) { return name.find(only) != std::string::npos; };
  if (const std::string name = "torus-" + std::to_string(torus_faces / 1000) + "k"; wanted(name)) {
    Input in{name, noisy_torus(torus_faces), {}};
    in.mesh = to_mesh(in.arrays);
    inputs.push_back(std::move(in));
  }
#ifdef GEOM_BENCH_HAVE_IO
  if (auto dir = data_dir())
    for (const char* name : {"bunny_closed.off", "armadillo.obj", "nefertiti.obj", "amo.ply", "fandisk.off"}) {
      if (!wanted(name)) continue;
      try {
        Input in{name, {}, load_mesh(*dir / name).mesh};
        in.arrays = to_arrays(in.mesh);
        inputs.push_back(std::move(in));
      } catch (const std::exception& e) {
        std::cerr << "skipping " << name << ": " << e.what() << "\n";
      }
    }
#endif

  Table table({"input", "faces", "target", "method", "seconds", "ratio_vs_meshopt", "wall_seconds",
               "wall_ratio", "achieved", "hausdorff_rel", "rms_rel"});
  Table tradeoff({"method", "target", "seconds", "hausdorff_rel", "rms_rel"});
  for (const Input& in : inputs) {
    const TriangleBvh original(in.arrays.positions, in.arrays.triangles);
    const std::size_t f0 = in.arrays.triangles.size();
    for (double ratio : {0.5, 0.1, 0.01}) {
      const auto target = static_cast<std::size_t>(std::llround(ratio * f0));
      double meshopt_seconds = 0, meshopt_wall = 0;
      auto report = [&](const std::string& method, const PeerRun& run) {
        const TriangleBvh simplified(run.mesh.positions, run.mesh.triangles);
        const MeshDistance d = mesh_distance(original, simplified, {.samples = 500000});
        if (method == "meshopt") meshopt_seconds = run.seconds, meshopt_wall = run.wall;
        table.add({in.name, std::to_string(f0), std::to_string(target), method, fmt(run.seconds, 4),
                   method == "meshopt" ? std::string("1x") : geom::bench::ratio(run.seconds, meshopt_seconds),
                   run.wall > 0 ? fmt(run.wall, 4) : "n/a",
                   run.wall > 0 ? geom::bench::ratio(run.wall, meshopt_wall) : "n/a",
                   std::to_string(run.mesh.triangles.size()), fmt(d.relative_hausdorff(), 3),
                   fmt(d.relative_rms(), 3)});
        if (in.name.rfind("torus-", 0) == 0)  // the tradeoff chart is the torus's
          tradeoff.add({method, std::to_string(target), fmt(run.seconds, 4), fmt(d.relative_hausdorff(), 3),
                        fmt(d.relative_rms(), 3)});
        std::cerr << in.name << " " << target << " " << method << " " << run.seconds << " s\n";
      };
      if (peers.count("meshopt")) report("meshopt", simplify_meshopt(in.arrays, target));
      if (peers.count("ours")) report("ours", simplify_ours(in.mesh, target));
      if (peers.count("ours_plain")) report("ours_plain", simplify_ours(in.mesh, target, 0));
      if (peers.count("ours_refit")) report("ours_refit", simplify_ours(in.mesh, target, 1));
      if (f0 <= slow_max) {
        for (const auto& [method, run] :
             {std::pair{"openmesh", &simplify_openmesh}, std::pair{"cgal", &simplify_cgal}}) {
          if (!peers.count(method)) continue;
          if (const auto* row = find_row(earlier, in.name, target, method)) {
            table.add(*row);
            if (in.name.rfind("torus-", 0) == 0)
              tradeoff.add({method, std::to_string(target), (*row)[4], (*row)[9], (*row)[10]});
          } else {
            report(method, run(in.arrays, target));
          }
        }
      }
    }
  }
  table.print();
  table.write_csv(out_dir() / "lod.csv");
  print_summary(table.rows());
  if (peers.count("ours_attr") || peers.count("meshopt_attr")) {
    Table attributes({"input", "faces", "target", "method", "seconds", "ratio_vs_meshopt", "wall_seconds",
                      "wall_ratio", "achieved",
                      "hausdorff_rel", "rms_rel", "uv_max", "uv_rms"});
    run_attribute_bench(attr_faces ? attr_faces : torus_faces, attr_weight, peers, attributes);
    attributes.print();
    attributes.write_csv(out_dir() / "lod_attributes.csv");
    std::cout << "wrote " << (out_dir() / "lod_attributes.csv").string() << "\n";
  }
  tradeoff.write_csv(out_dir() / "lod_tradeoff.csv");
  std::cout << "wrote " << (out_dir() / "lod.csv").string() << " and lod_tradeoff.csv\n";
  return 0;
}
