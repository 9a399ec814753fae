// Render benchmark: (1) what each effect costs on a ~1M-triangle mesh at 1024×1024 — the
// raster preview, + shadows, + reflections — so the cost is seen to grow only with what the
// scene asks for; (2) ray casting throughput of geom's BVH against Embree on the same
// triangles and the same rays, side by side.

#include <geom/render/render.h>
#include <geom/spatial/bvh.h>

#include "support/harness.h"

#include <embree3/rtcore.h>

#include <cmath>
#include <iostream>
#include <numbers>
#include <random>

namespace {

using namespace geom;

// A bumpy torus of about 2·n·m triangles: irregular enough that the BVH has work to do.
std::shared_ptr<SurfaceMesh> bumpy_torus(int n, int m) {
  auto mesh = std::make_shared<SurfaceMesh>();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      double u = 2 * std::numbers::pi * i / n, v = 2 * std::numbers::pi * j / m;
      double r = 0.35 + 0.02 * std::sin(13 * u) * std::cos(11 * v);
      mesh->add_vertex({(1 + r * std::cos(v)) * std::cos(u), r * std::sin(v), (1 + r * std::cos(v)) * std::sin(u)});
    }
  mesh->reserve(n * m, 3 * n * m, 2 * n * m);
  auto at = [&](int i, int j) { return Vertex(static_cast<std::uint32_t>(((i + n) % n) * m + (j + m) % m)); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      mesh->add_triangle(at(i, j), at(i, j + 1), at(i + 1, j + 1));
      mesh->add_triangle(at(i, j), at(i + 1, j + 1), at(i + 1, j));
    }
  return mesh;
}

void effects_table(const std::shared_ptr<SurfaceMesh>& mesh) {
  bench::Table t({"scene", "path", "bvh", "primary", "shadow", "reflection", "seconds", "vs raster"});
  double raster = 0;
  for (int variant = 0; variant < 3; ++variant) {
    Scene s = scene_for_mesh(mesh);
    s.width = s.height = 1024;
    s.samples = 1;
    s.ground = true;
    if (variant >= 1) s.lights.front().shadows = true;
    if (variant >= 2) s.materials[0].reflectance = 0.3;
    RenderStats st;
    double secs = bench::time_min([&] { st = render(s).stats; }, 1);
    if (variant == 0) raster = secs;
    const char* name[] = {"raster preview", "+ shadows", "+ reflections"};
    t.add({name[variant], st.path, st.bvh_built ? "yes" : "no", std::to_string(st.primary_rays),
           std::to_string(st.shadow_rays), std::to_string(st.reflection_rays), bench::fmt(secs),
           bench::fmt(secs / raster, 3) + "x"});
  }
  std::cout << "\nEffects on " << mesh->n_faces() << " triangles at 1024x1024, 1 sample/pixel:\n";
  t.print();
  t.write_csv(bench::out_dir() / "render_effects.csv");
}

void throughput_table(const SurfaceMesh& mesh) {
  std::vector<Point> pos;
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (Vertex v : mesh.vertices()) pos.push_back(mesh.position(v));
  for (Face f : mesh.faces()) {
    std::array<std::uint32_t, 3> t{};
    int k = 0;
    for (Vertex v : mesh.vertices(f)) t[k++] = v.idx();
    tris.push_back(t);
  }
  // Rays from a sphere around the mesh toward random points inside its box.
  const int n_rays = 1 << 20;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Point> org(n_rays), dir(n_rays);
  for (int i = 0; i < n_rays; ++i) {
    Point o(u(rng), u(rng), u(rng));
    org[i] = 4 * o.normalized();
    dir[i] = (Point(u(rng), 0.3 * u(rng), u(rng)) - org[i]).normalized();
  }

  TriangleBvh bvh;
  double build_ours = bench::time_min([&] { bvh = TriangleBvh(pos, tris); }, 1);
  std::size_t hits_ours = 0;
  double trace_ours = bench::time_min([&] {
    hits_ours = 0;
    for (int i = 0; i < n_rays; ++i) hits_ours += bvh.intersect(org[i], dir[i]).has_value();
  }, 2);

  RTCDevice device = rtcNewDevice("threads=1");
  RTCScene scene = nullptr;
  double build_embree = bench::time_min([&] {
    if (scene) rtcReleaseScene(scene);
    scene = rtcNewScene(device);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                           3 * sizeof(float), pos.size()));
    for (std::size_t i = 0; i < pos.size(); ++i)
      for (int k = 0; k < 3; ++k) vb[3 * i + k] = static_cast<float>(pos[i][k]);
    auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), tris.size()));
    for (std::size_t i = 0; i < tris.size(); ++i)
      for (int k = 0; k < 3; ++k) ib[3 * i + k] = tris[i][k];
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
  }, 1);
  std::size_t hits_embree = 0;
  double trace_embree = bench::time_min([&] {
    hits_embree = 0;
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (int i = 0; i < n_rays; ++i) {
      RTCRayHit rh{};
      rh.ray.org_x = static_cast<float>(org[i].x());
      rh.ray.org_y = static_cast<float>(org[i].y());
      rh.ray.org_z = static_cast<float>(org[i].z());
      rh.ray.dir_x = static_cast<float>(dir[i].x());
      rh.ray.dir_y = static_cast<float>(dir[i].y());
      rh.ray.dir_z = static_cast<float>(dir[i].z());
      rh.ray.tnear = 0;
      rh.ray.tfar = std::numeric_limits<float>::infinity();
      rh.ray.mask = ~0u;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &ctx, &rh);
      hits_embree += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
  }, 2);
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);

  bench::Table t({"bvh", "build s", "rays", "trace s", "Mrays/s", "hits", "ratio (ours/embree time)"});
  t.add({"geom (double, binned SAH)", bench::fmt(build_ours), std::to_string(n_rays), bench::fmt(trace_ours),
         bench::fmt(n_rays / trace_ours / 1e6), std::to_string(hits_ours), bench::ratio(trace_ours, trace_embree)});
  t.add({"embree 3 (float, 1 thread)", bench::fmt(build_embree), std::to_string(n_rays), bench::fmt(trace_embree),
         bench::fmt(n_rays / trace_embree / 1e6), std::to_string(hits_embree), "1x"});
  std::cout << "\nRay casting on " << tris.size() << " triangles, single thread, incoherent rays:\n";
  t.print();
  t.write_csv(bench::out_dir() / "render_rays.csv");
}

}  // namespace

int main(int argc, char** argv) {
  if (geom::bench::wants_help(argc, argv, "usage: bench_render [n]   (a bumpy torus of 2 n (n/2) triangles; default 1000, 1M)")) return 0;
  int n = argc > 1 ? std::atoi(argv[1]) : 1000;  // 1000 → 2·1000·500 = 1M triangles
  auto mesh = bumpy_torus(n, n / 2);
  effects_table(mesh);
  throughput_table(*mesh);
}
