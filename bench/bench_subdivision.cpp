// Subdivision: geom against OpenSubdiv Far (TopologyRefiner + PrimvarRefinerReal<double>), single
// thread, same inputs, same levels; topology and positions of every level are computed by
// both (geom also builds its SurfaceMesh of the last level). Then "what accuracy costs in
// time": per scheme and level, the time, the mesh size and how far the mesh is from the
// limit surface, for plain level k and for level k pushed to the limit.
//
// The limit rows: "CC level 4 + limit positions" is the whole job on both sides (OpenSubdiv
// then also builds full topology of level 4, which Limit() needs); "limit pass alone" is
// the figure: OpenSubdiv's Limit() call by itself, against the time geom's
// subdivide() adds when asked for the limit (the difference of the two geom rows).
//
// Times: single-thread runs are measured in process CPU time (min of runs), because the
// shared build machines are loaded and wall time there says more about the neighbours
// than about the code; the TBB column is wall time.
//
// Usage: bench_subdivision [--quick]   (CSV: $GEOM_BENCH_OUT/subdivision*.csv)
//
// The accuracy table is also written one row per (scheme, plain or pushed to the limit,
// level) to subdivision_tradeoff.csv; its chart, error against time, is one command:
//   bench/plot.py bench-out/subdivision_tradeoff.csv --x "cpu s" --y "max error"
//       --group method --logx --logy -o bench-out/subdivision_tradeoff.png

#include "support/harness.h"

#include <geom/subdivision/subdivision.h>

#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>

#include <tbb/global_control.h>

#include <cmath>
#include <cstring>
#include <ctime>
#include <limits>
#include <map>
#include <memory>
#include <utility>

using namespace geom;
using geom::bench::fmt;

namespace {

SurfaceMesh mesh_from(const std::vector<Point>& pts, const std::vector<std::vector<int>>& faces) {
  SurfaceMesh m;
  for (const Point& p : pts) m.add_vertex(p);
  for (const auto& f : faces) {
    std::vector<Vertex> vs;
    for (int i : f) vs.push_back(Vertex(static_cast<std::uint32_t>(i)));
    m.add_face(vs);
  }
  return m;
}

/// A cube with n × n quads per side projected onto the unit sphere (6n² quads).
SurfaceMesh quad_sphere(int n) {
  std::vector<Point> pts;
  std::map<std::tuple<long, long, long>, int> ids;
  auto vertex = [&](Eigen::Vector3d p) {
    auto key = std::make_tuple(std::lround(p.x() * 4 * n), std::lround(p.y() * 4 * n),
                               std::lround(p.z() * 4 * n));
    auto [it, fresh] = ids.emplace(key, static_cast<int>(pts.size()));
    if (fresh) pts.push_back(p.normalized());
    return it->second;
  };
  std::vector<std::vector<int>> faces;
  for (int axis = 0; axis < 3; ++axis)
    for (int sign : {-1, 1}) {
      Eigen::Vector3d normal = Eigen::Vector3d::Zero(), u = Eigen::Vector3d::Zero(),
                      v = Eigen::Vector3d::Zero();
      normal[axis] = sign;
      u[(axis + 1) % 3] = 1;
      v[(axis + 2) % 3] = 1;
      if (sign < 0) std::swap(u, v);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          auto at = [&](int a, int b) {
            return vertex(normal + (2.0 * a / n - 1.0) * u + (2.0 * b / n - 1.0) * v);
          };
          faces.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)});
        }
    }
  return mesh_from(pts, faces);
}

/// The icosahedron split `levels` times at edge midpoints, projected to the unit sphere.
SurfaceMesh icosphere(int levels) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Point> pts = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                            {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : pts) p.normalize();
  std::vector<std::array<int, 3>> tris = {
      {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
      {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      auto key = std::minmax(a, b);
      auto [it, fresh] = mid.emplace(key, static_cast<int>(pts.size()));
      if (fresh) pts.push_back((pts[a] + pts[b]).normalized());
      return it->second;
    };
    std::vector<std::array<int, 3>> next;
    for (auto [a, b, c] : tris) {
      int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      next.push_back({a, ab, ca});
      next.push_back({ab, b, bc});
      next.push_back({ca, bc, c});
      next.push_back({ab, bc, ca});
    }
    tris.swap(next);
  }
  std::vector<std::vector<int>> faces;
  for (auto [a, b, c] : tris) faces.push_back({a, b, c});
  return mesh_from(pts, faces);
}

struct Vec3 {
  double p[3];
  void Clear(void* = nullptr) { p[0] = p[1] = p[2] = 0.0; }
  void AddWithWeight(const Vec3& s, double w) {
    p[0] += w * s.p[0];
    p[1] += w * s.p[1];
    p[2] += w * s.p[2];
  }
};

/// OpenSubdiv: build the refiner, refine uniformly, interpolate positions through every
/// level (and take the limit of the last when asked). Returns the last level's face count.
/// With `limit_seconds`, the limit pass alone is also timed (CPU, min of `repeats`).
std::size_t osd_refine(const PolygonSoup& soup, bool loop, int levels, bool limit,
                       std::vector<Vec3>* out = nullptr, double* limit_seconds = nullptr,
                       int repeats = 1) {
  using namespace OpenSubdiv;
  std::vector<int> counts, indices(soup.face_indices.begin(), soup.face_indices.end());
  for (std::size_t f = 0; f < soup.n_faces(); ++f)
    counts.push_back(static_cast<int>(soup.face(f).size()));
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(soup.positions.size());
  desc.numFaces = static_cast<int>(counts.size());
  desc.numVertsPerFace = counts.data();
  desc.vertIndicesPerFace = indices.data();
  Sdc::Options options;
  options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(Factory::Create(
      desc, Factory::Options(loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, options)));
  Far::TopologyRefiner::UniformOptions uniform(levels);
  uniform.orderVerticesFromFacesFirst = true;
  uniform.fullTopologyInLastLevel = limit;
  refiner->RefineUniform(uniform);
  std::vector<Vec3> cur;
  for (const Point& p : soup.positions) cur.push_back({{p.x(), p.y(), p.z()}});
  Far::PrimvarRefinerReal<double> primvar(*refiner);
  for (int l = 1; l <= levels; ++l) {
    std::vector<Vec3> next(refiner->GetLevel(l).GetNumVertices());
    primvar.Interpolate(l, cur, next);
    cur.swap(next);
  }
  if (limit) {
    std::vector<Vec3> lim(cur.size());
    if (limit_seconds)
      *limit_seconds = geom::bench::cpu_time_min([&] { primvar.Limit(cur, lim); }, repeats);
    else
      primvar.Limit(cur, lim);
    cur.swap(lim);
  }
  if (out) *out = std::move(cur);
  return static_cast<std::size_t>(refiner->GetLevel(levels).GetNumFaces());
}

std::size_t osd_refine(const SurfaceMesh& mesh, bool loop, int levels, bool limit,
                       std::vector<Vec3>* out = nullptr, double* limit_seconds = nullptr,
                       int repeats = 1) {
  return osd_refine(to_soup(mesh), loop, levels, limit, out, limit_seconds, repeats);
}

/// The quad sphere's soup with a fin quad standing on every `step`-th edge: each of those
/// edges then has three faces (OpenSubdiv refines them as infinitely sharp creases).
PolygonSoup with_fins(const SurfaceMesh& mesh, std::size_t step) {
  PolygonSoup s = to_soup(mesh);
  for (Edge e : mesh.edges()) {
    if (e.idx() % step != 0) continue;
    const std::uint32_t a = mesh.vertex(e, 0).idx(), b = mesh.vertex(e, 1).idx();
    const auto n = static_cast<std::uint32_t>(s.positions.size());
    s.positions.push_back(s.positions[b] * 1.2);
    s.positions.push_back(s.positions[a] * 1.2);
    s.add_face({a, b, n, n + 1});
  }
  return s;
}

/// Largest distance between a soup's vertices and OpenSubdiv's.
double soup_difference(const PolygonSoup& s, const std::vector<Vec3>& osd) {
  if (s.positions.size() != osd.size()) return std::numeric_limits<double>::infinity();
  double worst = 0.0;
  for (std::size_t i = 0; i < osd.size(); ++i)
    worst = std::max(worst, (s.positions[i] - Point(osd[i].p[0], osd[i].p[1], osd[i].p[2])).norm());
  return worst;
}

double max_difference(const SurfaceMesh& ours, const std::vector<Vec3>& osd) {
  double worst = 0.0;
  for (Vertex v : ours.vertices()) {
    const Vec3& o = osd[v.idx()];
    worst = std::max(worst, (ours.position(v) - Point(o.p[0], o.p[1], o.p[2])).norm());
  }
  return worst;
}

/// Approximate bytes of a SurfaceMesh with positions (the figures in surface_mesh.h).
double mesh_megabytes(const SurfaceMesh& m) {
  return (29.0 * m.n_vertices() + 33.0 * m.n_edges() + 5.0 * m.n_faces()) / 1e6;
}

struct Errors {
  double max = 0.0, rms = 0.0;
};

/// Distance from a level-k mesh (positions `pos`) to the limit surface, sampled at its
/// vertices, edge midpoints and (Catmull-Clark) face centres, whose exact limit points are
/// the limit positions of level k + 1's vertex-, edge- and face-points.
Errors distance_to_limit(const SurfaceMesh& level, const std::vector<Point>& pos,
                         const SurfaceMesh& finer_limit, bool catmark) {
  const std::size_t F = catmark ? level.n_faces() : 0, E = level.n_edges();
  double sum = 0.0, mx = 0.0;
  std::size_t n = 0;
  auto add = [&](const Point& a, std::size_t child) {
    const double d = (a - finer_limit.position(Vertex(static_cast<std::uint32_t>(child)))).norm();
    mx = std::max(mx, d);
    sum += d * d;
    ++n;
  };
  for (Vertex v : level.vertices()) add(pos[v.idx()], F + E + v.idx());
  for (Edge e : level.edges())
    add(0.5 * (pos[level.vertex(e, 0).idx()] + pos[level.vertex(e, 1).idx()]), F + e.idx());
  if (catmark)
    for (Face f : level.faces()) {
      Point c = Point::Zero();
      double k = 0;
      for (Vertex v : level.vertices(f)) {
        c += pos[v.idx()];
        ++k;
      }
      add(c / k, f.idx());
    }
  return {mx, n ? std::sqrt(sum / n) : 0.0};
}

std::vector<Point> positions_of(const SurfaceMesh& m) {
  std::vector<Point> p;
  for (Vertex v : m.vertices()) p.push_back(m.position(v));
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  if (geom::bench::wants_help(argc, argv, "usage: bench_subdivision [--quick]")) return 0;
  const bool quick = argc > 1 && std::strcmp(argv[1], "--quick") == 0;
  const int repeats = quick ? 1 : 3;
  const SurfaceMesh sphere = quad_sphere(64);  // 24 576 quads
  const SurfaceMesh ico = icosphere(quick ? 3 : 5);     // 20 480 triangles
  std::cout << "inputs: quad sphere " << sphere.n_faces() << " quads, icosphere " << ico.n_faces()
            << " triangles; " << (quick ? "quick run" : "min of 3 runs") << "\n\n";

  geom::bench::Table speed({"case", "faces out", "geom 1T cpu s", "OpenSubdiv cpu s", "ratio",
                            "geom Mfaces/s", "OSD Mfaces/s", "geom TBB wall s",
                            "max |Δ| vs OSD"});
  struct Case {
    const char* name;
    const SurfaceMesh* mesh;
    bool loop, limit;
    int levels;
  };
  const Case cases[] = {{"Catmull-Clark level 4, quad sphere", &sphere, false, false, 4},
                        {"Loop level 4, icosphere", &ico, true, false, 4},
                        {"CC level 4 + limit positions", &sphere, false, true, 4}};
  double plain_1t = 0.0, plain_mt = 0.0;  // Catmull-Clark level 4 without the limit
  for (const Case& c : cases) {
    SubdivideOptions o;
    o.scheme = c.loop ? SubdivisionScheme::kLoop : SubdivisionScheme::kCatmullClark;
    o.levels = c.levels;
    o.limit = c.limit;
    SubdivideResult result;
    double ours_1t;
    {
      tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
      o.parallel = false;
      ours_1t = geom::bench::cpu_time_min([&] { result = subdivide(*c.mesh, o); }, repeats);
    }
    o.parallel = true;
    const double ours_mt = geom::bench::time_min([&] { result = subdivide(*c.mesh, o); }, repeats);
    std::size_t faces = 0;
    const double peer =
        geom::bench::cpu_time_min([&] { faces = osd_refine(*c.mesh, c.loop, c.levels, c.limit); }, repeats);
    std::vector<Vec3> osd;
    osd_refine(*c.mesh, c.loop, c.levels, c.limit, &osd);
    const std::string diff = fmt(max_difference(result.mesh, osd), 3);
    speed.add({c.name, std::to_string(faces), fmt(ours_1t), fmt(peer),
               geom::bench::ratio(ours_1t, peer), fmt(faces / ours_1t / 1e6),
               fmt(faces / peer / 1e6), fmt(ours_mt), diff});
    if (!c.loop && !c.limit) {
      plain_1t = ours_1t;
      plain_mt = ours_mt;
    }
    if (c.limit) {
      // The "limit positions at CC level 4": the limit pass alone. OpenSubdiv's is
      // Limit() on its refined level 4; geom's is what asking for the limit adds to the
      // same subdivide() call (the two rows above, same run).
      double peer_limit = 0.0;
      osd_refine(*c.mesh, c.loop, c.levels, true, nullptr, &peer_limit, repeats);
      const double ours_limit = ours_1t - plain_1t;
      speed.add({"limit pass alone, CC level 4", std::to_string(faces), fmt(ours_limit),
                 fmt(peer_limit), geom::bench::ratio(ours_limit, peer_limit),
                 fmt(faces / ours_limit / 1e6), fmt(faces / peer_limit / 1e6),
                 fmt(ours_mt - plain_mt), diff});
    }
  }
  speed.print();
  speed.write_csv(geom::bench::out_dir() / "subdivision.csv");

  // As given: a soup through subdivide(soup). Manifold input takes the mesh path after
  // checking OpenSubdiv's topology; non-manifold input is split, refined level by level and
  // joined again.
  std::cout << "\nas given (subdivide(soup), Catmull-Clark level 3, single thread)\n";
  geom::bench::Table given({"case", "faces in", "faces out", "geom cpu s", "OpenSubdiv cpu s",
                            "ratio", "max |Δ| vs OSD"});
  const PolygonSoup manifold = to_soup(sphere), fins = with_fins(sphere, 64);
  for (const auto& [name, soup] : {std::pair{"quad sphere soup (manifold)", &manifold},
                                   std::pair{"quad sphere + fins (non-manifold)", &fins}}) {
    tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
    SubdivideOptions o;
    o.levels = 3;
    o.parallel = false;
    SoupSubdivideResult r;
    const double ours = geom::bench::cpu_time_min([&] { r = subdivide(*soup, o); }, repeats);
    std::size_t faces = 0;
    const double peer = geom::bench::cpu_time_min([&] { faces = osd_refine(*soup, false, 3, false); }, repeats);
    std::vector<Vec3> osd;
    osd_refine(*soup, false, 3, false, &osd);
    given.add({name, std::to_string(soup->n_faces()), std::to_string(faces), fmt(ours), fmt(peer),
               geom::bench::ratio(ours, peer), fmt(soup_difference(r.soup, osd), 3)});
  }
  given.print();
  given.write_csv(geom::bench::out_dir() / "subdivision_as_given.csv");

  std::cout << "\nwhat accuracy costs in time (unit sphere inputs; distance to the limit surface "
               "sampled at vertices, edge midpoints and face centres)\n";
  geom::bench::Table acc({"scheme", "level", "faces", "mesh MB", "plain cpu s", "plain max",
                          "plain rms", "limit cpu s", "pushed max", "pushed rms"});
  geom::bench::Table tradeoff({"method", "level", "faces", "cpu s", "max error", "rms error"});
  for (bool loop : {false, true}) {
    const SurfaceMesh& input = loop ? ico : sphere;
    const std::size_t max_faces = quick ? 400000 : 6000000;
    for (int k = 1; k <= 5; ++k) {
      const double growth = std::pow(4.0, k);
      if (input.n_faces() * growth > max_faces) break;
      SubdivideOptions o;
      o.scheme = loop ? SubdivisionScheme::kLoop : SubdivisionScheme::kCatmullClark;
      o.levels = k;
      o.parallel = false;
      SubdivideResult plain, pushed;
      const double t_plain = geom::bench::cpu_time_min([&] { plain = subdivide(input, o); }, repeats);
      o.limit = true;
      const double t_limit = geom::bench::cpu_time_min([&] { pushed = subdivide(input, o); }, repeats);
      // The limit points of level k + 1 sample the limit surface inside level k's faces.
      o.levels = k + 1;
      const SubdivideResult finer = subdivide(input, o);
      const Errors e_plain = distance_to_limit(plain.mesh, positions_of(plain.mesh), finer.mesh, !loop);
      const Errors e_pushed = distance_to_limit(plain.mesh, positions_of(pushed.mesh), finer.mesh, !loop);
      acc.add({loop ? "loop" : "catmull-clark", std::to_string(k), std::to_string(plain.mesh.n_faces()),
               fmt(mesh_megabytes(plain.mesh)), fmt(t_plain), fmt(e_plain.max), fmt(e_plain.rms),
               fmt(t_limit), fmt(e_pushed.max), fmt(e_pushed.rms)});
      const std::string scheme = loop ? "loop" : "catmull-clark";
      tradeoff.add({scheme + " level k", std::to_string(k), std::to_string(plain.mesh.n_faces()),
                    fmt(t_plain), fmt(e_plain.max), fmt(e_plain.rms)});
      tradeoff.add({scheme + " level k + limit", std::to_string(k),
                    std::to_string(plain.mesh.n_faces()), fmt(t_limit), fmt(e_pushed.max),
                    fmt(e_pushed.rms)});
    }
  }
  acc.print();
  acc.write_csv(geom::bench::out_dir() / "subdivision_accuracy.csv");
  tradeoff.write_csv(geom::bench::out_dir() / "subdivision_tradeoff.csv");
  return 0;
}
