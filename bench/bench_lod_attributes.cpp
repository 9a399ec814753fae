// bench_lod's attribute section: simplification with texture coordinates steering it, ours
// (SimplifyOptions::attributes) against meshoptimizer, on a textured noisy torus whose UV
// chart is cut along two seams. The peer is meshopt_simplifyWithAttributes where the
// installed meshoptimizer has it (0.21+), else meshopt_simplify on the seam-split vertex
// buffer (meshoptimizer keeps seams but has no attribute metric before 0.20).
//
// Error: geometric Hausdorff/RMS as in the main table, and the UV error: at area-weighted
// samples of the simplified surface, the distance between its interpolated UV and the
// original's UV at the closest original point (periodic, since the torus chart wraps).

#include <geom/core/soup.h>
#include <geom/lod/simplify.h>
#include <geom/spatial/bvh.h>
#include <geom/spatial/distance.h>

#include "lod_peers.h"
#include "support/harness.h"

#include <meshoptimizer.h>

#include <Eigen/Geometry>

#include <cmath>
#include <map>
#include <numbers>
#include <random>

namespace geom::bench {

namespace {

// Triangles with a UV per corner.
struct Textured {
  TriangleArrays mesh;
  std::vector<std::array<TexCoord, 3>> uv;
};

Textured textured_torus(std::size_t faces) {
  const int nv = std::max(3, static_cast<int>(std::sqrt(faces / 4.0)));
  const int nu = std::max(3, static_cast<int>(faces / (2.0 * nv)));
  Textured t;
  std::mt19937 rng(2025);
  std::uniform_real_distribution<double> uni(-1.0, 1.0);
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double a = 2 * std::numbers::pi * (i + 0.3 * uni(rng)) / nu;
      const double b = 2 * std::numbers::pi * (j + 0.3 * uni(rng)) / nv;
      const double r = 0.35 + 0.02 * std::sin(7 * a) * std::cos(5 * b);
      t.mesh.positions.emplace_back((1 + r * std::cos(b)) * std::cos(a), (1 + r * std::cos(b)) * std::sin(a),
                                    r * std::sin(b));
    }
  // UV (i / nu, j / nv) of the grid point before wrapping: the last row and column meet the
  // first at u = 1 and v = 1, which makes the two seams.
  auto at = [&](int i, int j) { return static_cast<std::uint32_t>((i % nu) * nv + (j % nv)); };
  auto uv = [&](int i, int j) { return TexCoord(double(i) / nu, double(j) / nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      t.mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      t.uv.push_back({uv(i, j), uv(i + 1, j), uv(i + 1, j + 1)});
      t.mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      t.uv.push_back({uv(i, j), uv(i + 1, j + 1), uv(i, j + 1)});
    }
  return t;
}

SurfaceMesh to_surface_mesh(const Textured& t) {
  SurfaceMesh m;
  for (const auto& p : t.mesh.positions) m.add_vertex(p);
  auto uv = m.add_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  for (std::size_t f = 0; f < t.mesh.triangles.size(); ++f) {
    const auto& tri = t.mesh.triangles[f];
    const Face face = m.add_triangle(Vertex(tri[0]), Vertex(tri[1]), Vertex(tri[2]));
    for (Halfedge h : m.halfedges(face))
      for (int k = 0; k < 3; ++k)
        if (m.to_vertex(h).idx() == tri[k]) uv[h] = t.uv[f][k];
  }
  return m;
}

Textured from_surface_mesh(const SurfaceMesh& m) {
  Textured t;
  for (Vertex v : m.vertices()) t.mesh.positions.push_back(m.position(v));  // compact: dense indices
  const auto uv = m.get_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  for (Face f : m.faces()) {
    std::array<std::uint32_t, 3> tri{};
    std::array<TexCoord, 3> c;
    int k = 0;
    for (Halfedge h : m.halfedges(f)) tri[k] = m.to_vertex(h).idx(), c[k++] = uv[h];
    t.mesh.triangles.push_back(tri);
    t.uv.push_back(c);
  }
  return t;
}

// The seam-split vertex buffer meshoptimizer works on: one vertex per (position, UV).
struct Split {
  std::vector<float> vertices;  // x y z u v
  std::vector<unsigned> indices;
  std::vector<Point> positions;
};

Split split(const Textured& t) {
  Split s;
  std::map<std::tuple<std::uint32_t, double, double>, unsigned> index;
  for (std::size_t f = 0; f < t.mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t v = t.mesh.triangles[f][k];
      const TexCoord& c = t.uv[f][k];
      auto [it, fresh] = index.try_emplace({v, c.x(), c.y()}, static_cast<unsigned>(s.positions.size()));
      if (fresh) {
        const Point& p = t.mesh.positions[v];
        s.positions.push_back(p);
        s.vertices.insert(s.vertices.end(), {float(p.x()), float(p.y()), float(p.z()), float(c.x()), float(c.y())});
      }
      s.indices.push_back(it->second);
    }
  return s;
}

Textured from_split(const Split& s, const std::vector<unsigned>& out, std::size_t n) {
  Textured t;
  t.mesh.positions = s.positions;
  for (std::size_t i = 0; i + 2 < n; i += 3) {
    t.mesh.triangles.push_back({out[i], out[i + 1], out[i + 2]});
    std::array<TexCoord, 3> c;
    for (int k = 0; k < 3; ++k) c[k] = TexCoord(s.vertices[5 * out[i + k] + 3], s.vertices[5 * out[i + k] + 4]);
    t.uv.push_back(c);
  }
  return t;
}

struct UvError {
  double max = 0, rms = 0;
};

double wrap(double d) {
  d = std::abs(d - std::round(d));
  return d;
}

// Samples of `simplified` against the closest point of the original; both UVs are periodic.
UvError uv_error(const TriangleBvh& original, const Textured& in, const Textured& simplified, std::size_t samples) {
  std::vector<double> cumulative;
  double total = 0;
  for (const auto& tri : simplified.mesh.triangles) {
    const auto& p = simplified.mesh.positions;
    total += 0.5 * (p[tri[1]] - p[tri[0]]).cross(p[tri[2]] - p[tri[0]]).norm();
    cumulative.push_back(total);
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  UvError e;
  double sum = 0;
  for (std::size_t s = 0; s < samples; ++s) {
    const std::size_t f = std::lower_bound(cumulative.begin(), cumulative.end(), uni(rng) * total) - cumulative.begin();
    double a = uni(rng), b = uni(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    const auto& tri = simplified.mesh.triangles[std::min(f, cumulative.size() - 1)];
    const auto& c = simplified.uv[std::min(f, cumulative.size() - 1)];
    const auto& p = simplified.mesh.positions;
    const Point x = (1 - a - b) * p[tri[0]] + a * p[tri[1]] + b * p[tri[2]];
    const TexCoord got = (1 - a - b) * c[0] + a * c[1] + b * c[2];
    const ClosestPoint cp = original.closest_point(x);
    const auto [q0, q1, q2] = original.triangle(cp.triangle);
    // Barycentrics of the closest point in its original triangle.
    const Eigen::Vector3d n = (q1 - q0).cross(q2 - q0);
    const double nn = n.squaredNorm();
    const double w1 = (cp.point - q0).cross(q2 - q0).dot(n) / nn, w2 = (q1 - q0).cross(cp.point - q0).dot(n) / nn;
    const auto& oc = in.uv[cp.triangle];
    const TexCoord want = (1 - w1 - w2) * oc[0] + w1 * oc[1] + w2 * oc[2];
    const double d = std::hypot(wrap(got.x() - want.x()), wrap(got.y() - want.y()));
    e.max = std::max(e.max, d);
    sum += d * d;
  }
  e.rms = std::sqrt(sum / static_cast<double>(samples));
  return e;
}

}  // namespace

void run_attribute_bench(std::size_t faces, double weight, const std::set<std::string>& peers, Table& table) {
  const Textured in = textured_torus(faces);
  const SurfaceMesh mesh = to_surface_mesh(in);
  const Split sp = split(in);
  const TriangleBvh original(in.mesh.positions, in.mesh.triangles);
  const std::string name = "uv-torus-" + std::to_string(faces / 1000) + "k";
  const std::size_t f0 = in.mesh.triangles.size();
  for (double fraction : {0.5, 0.1, 0.01}) {
    const auto target = static_cast<std::size_t>(std::llround(fraction * f0));
    CpuWall peer{};
    auto report = [&](const std::string& method, const Textured& out, CpuWall t) {
      const TriangleBvh simplified(out.mesh.positions, out.mesh.triangles);
      const MeshDistance d = mesh_distance(original, simplified, {.samples = 500000});
      const UvError uv = uv_error(original, in, out, 200000);
      const bool ours = method == "ours_attr";
      if (!ours) peer = t;
      table.add({name, std::to_string(f0), std::to_string(target), method, fmt(t.cpu, 4),
                 ours ? ratio(t.cpu, peer.cpu) : std::string("1x"), fmt(t.wall, 4),
                 ours ? ratio(t.wall, peer.wall) : std::string("1x"), std::to_string(out.mesh.triangles.size()), fmt(d.relative_hausdorff(), 3), fmt(d.relative_rms(), 3),
                 fmt(uv.max, 3), fmt(uv.rms, 3)});
      std::cerr << name << " " << target << " " << method << " " << t.cpu << " s\n";
    };
    if (peers.count("meshopt_attr")) {
      std::vector<unsigned> out(sp.indices.size());
      std::size_t n = 0;
#if MESHOPTIMIZER_VERSION >= 210
      const float weights[2] = {float(weight), float(weight)};
      const CpuWall seconds = cpu_wall_min([&] {
        float err = 0;
        n = meshopt_simplifyWithAttributes(out.data(), sp.indices.data(), sp.indices.size(), sp.vertices.data(),
                                           sp.positions.size(), 5 * sizeof(float), sp.vertices.data() + 3,
                                           5 * sizeof(float), weights, 2, nullptr, target * 3, 1.0f, 0, &err);
      }, 2);
      report("meshopt_attr", from_split(sp, out, n), seconds);
#else
      const CpuWall seconds = cpu_wall_min([&] {
        float err = 0;
        n = meshopt_simplify(out.data(), sp.indices.data(), sp.indices.size(), sp.vertices.data(),
                             sp.positions.size(), 5 * sizeof(float), target * 3, 1.0f, 0, &err);
      }, 2);
      report("meshopt_seams", from_split(sp, out, n), seconds);
#endif
    }
    if (peers.count("ours_attr")) {
      SimplifyOptions o{.target_faces = target, .keep_attributes = false};
      o.attributes.texcoords = {.enabled = true, .weight = weight};
      SimplifyResult r;
      const CpuWall seconds = cpu_wall_min([&] { r = simplify(mesh, o); }, 2);
      report("ours_attr", from_surface_mesh(r.mesh), seconds);
    }
  }
}

}  // namespace geom::bench
