#include <geom/lod/lod_chain.h>
#include <geom/lod/progressive_mesh.h>
#include <geom/spatial/distance.h>

#include "lod/lod_checks.h"
#include "spatial/procedural.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

namespace geom {
namespace {

// The input's faces fan-triangulated in order, as ProgressiveMesh numbers them.
std::vector<std::array<Vertex, 3>> fan_triangles(const SurfaceMesh& m) {
  std::vector<std::array<Vertex, 3>> out;
  for (Face f : m.faces()) {
    std::vector<Vertex> c;
    for (Vertex v : m.vertices(f)) c.push_back(v);
    for (std::size_t k = 1; k + 1 < c.size(); ++k) out.push_back({c[0], c[k], c[k + 1]});
  }
  return out;
}

void expect_reproduces_input(const ProgressiveMesh& pm, const SurfaceMesh& input) {
  const auto tris = fan_triangles(input);
  ASSERT_EQ(pm.n_faces(), tris.size());
  ASSERT_EQ(pm.n_vertices(), pm.max_vertices());
  for (std::size_t i = 0; i < pm.n_vertices(); ++i)
    ASSERT_EQ(pm.positions()[i], input.position(pm.vertex_origin()[i])) << "vertex " << i;
  std::vector<std::uint8_t> seen(tris.size(), 0);
  for (std::size_t t = 0; t < pm.n_faces(); ++t) {
    const auto& o = tris[pm.face_origin()[t]];
    seen[pm.face_origin()[t]] = 1;
    for (int k = 0; k < 3; ++k) ASSERT_EQ(pm.vertex_origin()[pm.faces()[t][k]], o[k]) << "face " << t;
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<long>(tris.size()));
}

using Triple = std::array<double, 9>;
// Faces as position triples, rotated to start at the smallest corner; degenerate faces (a
// repeated position) left out.
std::multiset<Triple> position_faces(std::span<const Point> pos,
                                     std::span<const std::array<std::uint32_t, 3>> faces) {
  std::multiset<Triple> out;
  for (const auto& f : faces) {
    std::array<Point, 3> p{pos[f[0]], pos[f[1]], pos[f[2]]};
    if (p[0] == p[1] || p[1] == p[2] || p[0] == p[2]) continue;
    auto less = [](const Point& a, const Point& b) {
      return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
    };
    int s = 0;
    for (int k = 1; k < 3; ++k)
      if (less(p[k], p[s])) s = k;
    Triple t;
    for (int k = 0; k < 3; ++k)
      for (int c = 0; c < 3; ++c) t[3 * k + c] = p[(s + k) % 3][c];
    out.insert(t);
  }
  return out;
}

TEST(ProgressiveMesh, RefiningFullyReproducesTheInputExactly) {
  const SurfaceMesh m = test::torus(40, 20, 1.0, 0.35, 0.1);
  ProgressiveMesh pm = ProgressiveMesh::build(m);
  expect_reproduces_input(pm, m);
  EXPECT_LT(pm.base_faces(), 100u);
  pm.coarsen_to(0);
  EXPECT_EQ(pm.n_vertices(), pm.base_vertices());
  EXPECT_EQ(pm.n_faces(), pm.base_faces());
  pm.refine_to(pm.max_vertices() + 10);
  expect_reproduces_input(pm, m);
}

TEST(ProgressiveMesh, EveryLevelIsAValidMeshWithTheInputTopology) {
  const SurfaceMesh m = test::grid(
      12, [](int i, int j) { return i == 5 && j == 6; }, 0.8);
  ProgressiveMesh pm = ProgressiveMesh::build(m);
  std::mt19937 rng(9);
  std::uniform_int_distribution<std::size_t> level(pm.base_vertices(), pm.max_vertices());
  for (int trial = 0; trial < 25; ++trial) {
    const std::size_t n = level(rng);
    pm.set_level(n);
    ASSERT_EQ(pm.n_vertices(), n);
    ASSERT_EQ(pm.n_faces(), pm.faces_at(n));
    test::expect_same_topology(m, pm.mesh());
  }
  pm.set_level(pm.max_vertices());
  expect_reproduces_input(pm, m);
}

TEST(ProgressiveMesh, BaseMeshMatchesSimplify) {
  const SurfaceMesh m = test::torus(30, 16, 1.0, 0.3, 0.1);
  // A progressive mesh never refits (-1, automatic, means none there); simplify() would here.
  const SimplifyOptions so{.ratio = 0.2, .refit_iterations = 0};
  ProgressiveMesh pm = ProgressiveMesh::build(m, {.simplify = so});
  const SimplifyResult r = simplify(m, so);
  EXPECT_EQ(pm.base_faces(), r.faces_after);
  pm.coarsen_to(0);
  const SurfaceMesh base = pm.mesh();
  EXPECT_EQ(base.n_vertices(), r.mesh.n_vertices());
  EXPECT_LT(mesh_distance(base, r.mesh, {.samples = 2000}).hausdorff, 1e-12);
}

TEST(ProgressiveMesh, FacesForVertices) {
  const SurfaceMesh m = test::sphere(10, 12);
  const ProgressiveMesh pm = ProgressiveMesh::build(m);
  EXPECT_EQ(pm.faces_at(pm.base_vertices()), pm.base_faces());
  EXPECT_EQ(pm.faces_at(pm.max_vertices()), m.n_faces());
  for (std::size_t f : {std::size_t{0}, pm.base_faces(), std::size_t{57}, std::size_t{100}, m.n_faces()}) {
    const std::size_t v = pm.vertices_for_faces(f);
    if (f >= pm.base_faces()) {
      EXPECT_LE(pm.faces_at(v), f);
      if (v < pm.max_vertices()) {
        EXPECT_GT(pm.faces_at(v + 1), f);
      }
    } else {
      EXPECT_EQ(v, pm.base_vertices());
    }
  }
  EXPECT_THROW(pm.faces_at(pm.max_vertices() + 1), InvalidArgument);
  EXPECT_THROW(pm.faces_at(pm.base_vertices() - 1), InvalidArgument);
}

TEST(Geomorph, EndpointsEqualTheTwoLevels) {
  const SurfaceMesh m = test::torus(30, 16, 1.0, 0.3, 0.1);
  ProgressiveMesh pm = ProgressiveMesh::build(m);
  const std::size_t a = pm.base_vertices() + 20, b = pm.base_vertices() + 150;
  const Geomorph g = pm.geomorph(a, b);
  EXPECT_EQ(pm.n_vertices(), b);
  ASSERT_EQ(g.fine.size(), b);
  const std::vector<Point> fine = g.at(1.0);
  for (std::size_t i = 0; i < b; ++i) EXPECT_EQ(fine[i], pm.positions()[i]);
  EXPECT_EQ(g.faces.size(), pm.n_faces());
  const auto fine_faces = position_faces(pm.positions(), pm.faces());
  EXPECT_EQ(position_faces(fine, g.faces), fine_faces);
  const std::vector<Point> coarse = g.at(0.0);
  const auto morphed = position_faces(coarse, g.faces);
  pm.set_level(a);
  EXPECT_EQ(morphed, position_faces(pm.positions(), pm.faces()));
  // Halfway: every vertex between its two ends.
  const std::vector<Point> half = g.at(0.5);
  for (std::size_t i = 0; i < b; ++i) EXPECT_LT((half[i] - 0.5 * (g.coarse[i] + g.fine[i])).norm(), 1e-12);
  EXPECT_THROW(pm.geomorph(b, a), InvalidArgument);
  EXPECT_THROW(pm.geomorph(a, pm.max_vertices() + 1), InvalidArgument);
}

TEST(ProgressiveStream, RoundTripsExactly) {
  const SurfaceMesh m = test::grid(
      10, [](int i, int j) { return i == 3 && j == 4; }, 0.6);
  ProgressiveMesh pm = ProgressiveMesh::build(m);
  const std::vector<std::byte> bytes = pm.encode();
  ProgressiveMesh back = ProgressiveMesh::decode(bytes);
  EXPECT_EQ(back.base_vertices(), pm.base_vertices());
  EXPECT_EQ(back.base_faces(), pm.base_faces());
  EXPECT_EQ(back.max_vertices(), pm.max_vertices());
  for (std::size_t n : {pm.max_vertices(), pm.base_vertices(), pm.base_vertices() + 17}) {
    pm.set_level(n);
    back.set_level(n);
    ASSERT_EQ(back.n_faces(), pm.n_faces());
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(back.positions()[i], pm.positions()[i]);
    for (std::size_t f = 0; f < pm.n_faces(); ++f) ASSERT_EQ(back.faces()[f], pm.faces()[f]);
  }
  EXPECT_EQ(back.encode(), bytes);
}

TEST(ProgressiveStream, APrefixIsAUsableCoarseMesh) {
  const SurfaceMesh m = test::torus(40, 20, 1.0, 0.35, 0.05);
  const ProgressiveMesh pm = ProgressiveMesh::build(m);
  const std::vector<std::byte> bytes = pm.encode();
  const std::span<const std::byte> prefix(bytes.data(), bytes.size() * 3 / 10);
  const ProgressiveMesh part = ProgressiveMesh::decode(prefix, true);
  EXPECT_GT(part.n_vertices(), part.base_vertices());
  EXPECT_LT(part.n_vertices(), pm.max_vertices());
  test::expect_same_topology(m, part.mesh());
  EXPECT_THROW(ProgressiveMesh::decode(prefix), DecodeError);
}

TEST(ProgressiveStream, RejectsTruncatedStreams) {
  const ProgressiveMesh pm = ProgressiveMesh::build(test::sphere(6, 8));
  const std::vector<std::byte> bytes = pm.encode();
  for (std::size_t cut = 0; cut < bytes.size(); cut += 7) {
    const std::span<const std::byte> prefix(bytes.data(), cut);
    try {
      ProgressiveMesh::decode(prefix);
      ADD_FAILURE() << "accepted a stream cut at " << cut;
    } catch (const DecodeError& e) {
      EXPECT_LE(e.offset(), cut);
    }
  }
  // Cut inside the base mesh: even a streaming reader refuses.
  EXPECT_THROW(ProgressiveMesh::decode(std::span(bytes.data(), 40), true), DecodeError);
}

void put_u32(std::vector<std::byte>& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = std::byte(static_cast<std::uint8_t>(v >> (8 * i)));
}

TEST(ProgressiveStream, RejectsCorruptedStreams) {
  const ProgressiveMesh pm = ProgressiveMesh::build(test::sphere(6, 8));
  const std::vector<std::byte> good = pm.encode();
  const std::size_t base_end = 28 + pm.base_vertices() * 24 + pm.base_faces() * 12;
  auto expect_rejected = [&](auto edit, const char* what) {
    std::vector<std::byte> b = good;
    edit(b);
    EXPECT_THROW(ProgressiveMesh::decode(b), DecodeError) << what;
    EXPECT_THROW(ProgressiveMesh::decode(b, true), DecodeError) << what;
  };
  expect_rejected([](auto& b) { b[1] = std::byte{'X'}; }, "magic");
  expect_rejected([](auto& b) { put_u32(b, 8, 2); }, "version");
  expect_rejected([](auto& b) { put_u32(b, 12, 1); }, "flags");
  expect_rejected([](auto& b) { put_u32(b, 16, 0xffffffffu); }, "huge vertex count");
  expect_rejected([](auto& b) { put_u32(b, 20, 0x40000000u); }, "huge face count");
  expect_rejected([&](auto& b) { put_u32(b, 28 + pm.base_vertices() * 24, 9999); }, "face index");
  expect_rejected([&](auto& b) { put_u32(b, base_end, 9999); }, "split vertex");
  expect_rejected([&](auto& b) { b[base_end + 52] = std::byte{3}; }, "split face count");
  expect_rejected([&](auto& b) { put_u32(b, 28, 0); put_u32(b, 32, 0x7ff00000u); }, "infinite coordinate");
  {
    std::vector<std::byte> b = good;
    put_u32(b, 24, 0x7fffffffu);
    EXPECT_THROW(ProgressiveMesh::decode(b), DecodeError) << "huge split count";
  }
  {
    std::vector<std::byte> b = good;
    b.push_back(std::byte{0});
    EXPECT_THROW(ProgressiveMesh::decode(b), DecodeError) << "trailing bytes";
  }
  // Random single-byte damage never crashes: either a DecodeError, or a stream that
  // decodes (then mesh() may still refuse non-manifold faces).
  std::mt19937 rng(1);
  for (int trial = 0; trial < 300; ++trial) {
    std::vector<std::byte> b = good;
    b[rng() % b.size()] = std::byte(static_cast<std::uint8_t>(rng()));
    try {
      ProgressiveMesh d = ProgressiveMesh::decode(b);
      d.set_level(d.base_vertices());
      d.set_level(d.max_vertices());
      try {
        (void)d.mesh();
      } catch (const TopologyError&) {
      }
    } catch (const DecodeError&) {
    }
  }
}

TEST(LodChain, LevelsHaveTheirTargetsAndMeasuredErrors) {
  const SurfaceMesh m = test::torus(60, 30, 1.0, 0.35, 0.05);
  const auto levels = lod_chain(m, {.ratios = {0.5, 0.1, 0.02}, .distance = {.samples = 20000}});
  ASSERT_EQ(levels.size(), 3u);
  double previous = 0;
  for (const LodLevel& l : levels) {
    EXPECT_LE(l.faces, static_cast<std::size_t>(std::llround(l.ratio * 3600)));
    EXPECT_GE(l.faces + 2, static_cast<std::size_t>(std::llround(l.ratio * 3600)));
    test::expect_same_topology(m, l.mesh);
    EXPECT_GT(l.error.hausdorff, previous);
    previous = l.error.hausdorff;
  }
  EXPECT_THROW(lod_chain(m, {.ratios = {0.0}}), InvalidArgument);
  EXPECT_THROW(lod_chain(m, {.ratios = {1.5}}), InvalidArgument);
}

}  // namespace
}  // namespace geom
