// Predictors 6 and 7, positions in growth order: the encoder's and decoder's walks agree
// for every deadline and weight (exact round trips of random points, isolated vertices
// chained or anchored), level 9 picks them where they are smaller (regular tori) on meshes
// with boundaries, several components, isolated vertices, polygons and attributes, the
// lower levels keep the degree order, and damaged streams throw.

#include "compress/meshes.h"

#include <geom/compress/container/codec.h>
#include <geom/compress/container/mesh_tables.h>
#include <geom/compress/predict.h>
#include <geom/core/soup.h>
#include <geom/core/validate.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace geom::codec::detail {
namespace {

/// A corner table from the connectivity coder (vertices numbered by birth, triangles in
/// decode order, as the growth pass needs) with random grid points, n_isolated last; one
/// coordinate in four sits on the grid's edge, so clamped predictions are exercised.
struct GrowthCase {
  CornerTable table;
  std::vector<QPoint> q;
};

GrowthCase random_case(const test::Arrays& a, unsigned seed, std::size_t n_isolated) {
  const FlatMesh flat = flatten(a.build());
  RansEncoder re;
  BitWriter bw;
  TraversalOrder order;
  GrowthCase c;
  encode_connectivity(flat.table, flat.polygons, Traversal::kRightFirst, re, bw, c.table, order);
  std::mt19937 rng(seed);
  c.q.resize(c.table.n_vertices + n_isolated);
  for (QPoint& p : c.q)
    for (auto& x : p) x = rng() % 4 == 0 ? (rng() % 2 ? 4095 : 0) : rng() % 4096;
  return c;
}

void expect_growth_round_trip(const GrowthCase& c, Predictor predictor, Blend blend,
                              bool anchored, unsigned log2_deadline) {
  RansEncoder re;
  BitWriter bw;
  const auto seq =
      encode_positions_growth(c.table, c.q, 12, re, bw, predictor, blend, anchored, log2_deadline);
  const bool reordered = anchored && c.q.size() > c.table.n_vertices && c.table.n_vertices > 0;
  ASSERT_EQ(seq.size(), reordered ? c.q.size() : 0u);
  const std::vector<std::uint8_t> rans = re.finish(), raw = bw.finish();
  RansDecoder rd(rans, 0);
  BitReader br(raw, 0);
  std::vector<QPoint> decoded;
  decode_positions_growth(c.table, c.q.size(), 12, rd, br, decoded, predictor, blend,
                          reordered, log2_deadline);
  rd.finish();
  ASSERT_EQ(decoded.size(), c.q.size());
  for (std::size_t i = 0; i < c.q.size(); ++i)
    ASSERT_EQ(decoded[i], c.q[seq.empty() ? i : seq[i]]) << "vertex " << i;
}

TEST(CompressGrowth, RoundTripsExactlyForEveryDeadlineAndWeight) {
  test::Arrays a = test::holey_slab(2, true).shuffled(3);
  a.append(test::grid(6, 5), {9, 0, 0});  // a second component, with a boundary
  const GrowthCase c = random_case(a, 4, 7);
  for (const Predictor p : {Predictor::kGrowthBlend, Predictor::kGrowthSelect})
    for (const unsigned d : {0u, 3u, 6u, 12u, 14u, kMaxLog2Deadline})
      for (const Blend blend : {Blend{0, 0}, Blend{5, 9}})
        for (const bool anchored : {false, true})
          expect_growth_round_trip(c, p, blend, anchored && p == Predictor::kGrowthSelect, d);
}

TEST(CompressGrowth, RoundTripsPolygonsAndPointsOnly) {
  expect_growth_round_trip(random_case(test::mixed_polygons(), 5, 0), Predictor::kGrowthBlend,
                           {}, false, 6);
  GrowthCase points;  // no triangles: every vertex is isolated
  points.q = {{1, 2, 3}, {4, 5, 6}};
  expect_growth_round_trip(points, Predictor::kGrowthSelect, {}, true, 12);
}

/// Level 9 codes m in growth order, within the quantisation bound. (On these tori the growth
/// order is smaller than the degree order; should a change to either make the degree order
/// win, pick another mesh: the tests need a growth-order stream.)
CompressResult expect_growth_stream(const SurfaceMesh& m, CompressOptions options = {}) {
  options.level = 9;
  const CompressResult c = compress(m, options);
  EXPECT_TRUE(c.stats.predictor == int(Predictor::kGrowthBlend) ||
              c.stats.predictor == int(Predictor::kGrowthSelect))
      << c.stats.predictor;
  const DecompressResult d = decompress(c.bytes);
  EXPECT_TRUE(validate(d.mesh).ok());
  EXPECT_EQ(d.mesh.n_vertices(), m.n_vertices());
  EXPECT_EQ(d.mesh.n_faces(), m.n_faces());
  std::size_t i = 0;
  for (Vertex v : d.mesh.vertices()) {
    const Point& p = m.position(Vertex(c.vertex_permutation[i++]));
    EXPECT_LE((d.mesh.position(v) - p).cwiseAbs().maxCoeff(), c.stats.max_error * (1 + 1e-9));
  }
  return c;
}

test::Arrays components_with_isolated() {
  test::Arrays a = test::torus(60, 40);
  a.append(test::grid(9, 7), {20, 0, 0});
  a.append(test::mixed_polygons(), {-20, 0, 0});
  a.points.push_back({7, 7, 7});
  a.points.push_back({-3, 1, 2});
  return a;
}

TEST(CompressGrowth, LevelNineUsesItOnBoundariesComponentsAndPolygons) {
  const SurfaceMesh m = components_with_isolated().build();
  const CompressResult c9 = expect_growth_stream(m);
  expect_growth_stream(m, {.preserve_order = true});
  // The lower levels keep the degree order (it decodes as fast; FORMAT.md).
  for (int level : {5, 7, 8}) EXPECT_LT(compress(m, {.level = level}).stats.predictor, 6);
  EXPECT_LE(c9.bytes.size(), compress(m, {.level = 8}).bytes.size());
}

TEST(CompressGrowth, AttributesFollowTheConnectivityNumbering) {
  // Normals and texture coordinates are coded in the positions' order, which in growth
  // order is the connectivity's: they must come back on the right vertices.
  SurfaceMesh m = test::torus(60, 40).build();
  auto n = m.add_property<Vertex, Normal>(prop::kVertexNormal);
  auto t = m.add_property<Vertex, TexCoord>(prop::kVertexTexCoord);
  for (Vertex v : m.vertices()) {
    const Point& p = m.position(v);
    n[v] = Normal(p.x(), p.y(), p.z()).normalized();
    t[v] = TexCoord(p.x() * 0.1, p.z() * 0.2);
  }
  const CompressResult c = expect_growth_stream(m);
  const DecompressResult d = decompress(c.bytes);
  const auto dn = d.mesh.get_property<Vertex, Normal>(prop::kVertexNormal);
  const auto dt = d.mesh.get_property<Vertex, TexCoord>(prop::kVertexTexCoord);
  ASSERT_TRUE(dn && dt);
  std::size_t i = 0;
  for (Vertex v : d.mesh.vertices()) {
    const Vertex o(c.vertex_permutation[i++]);
    EXPECT_LT(std::acos(std::min(1.0, dn[v].dot(n[o]))), 4.5 / 1024 + 1e-9);
    EXPECT_LE((dt[v] - t[o]).cwiseAbs().maxCoeff(), d.texcoord_max_error * (1 + 1e-9));
  }
}

TEST(CompressGrowth, DamagedStreamsThrowOrDecodeValidMeshes) {
  const CompressResult c = expect_growth_stream(components_with_isolated().build());
  const std::uint8_t pred = c.bytes[6];
  const std::size_t deadline_at = 40 + 1 + (pred == 7 ? 1 : 0);
  for (std::size_t len = 0; len < c.bytes.size(); len += 5)
    EXPECT_THROW(decompress(std::span(c.bytes.data(), len)), DecodeError) << len;
  std::vector<std::uint8_t> bad = c.bytes;
  bad[deadline_at] = kMaxLog2Deadline + 1;
  try {
    decompress(bad);
    ADD_FAILURE() << "a deadline beyond 2^31 decoded";
  } catch (const DecodeError& e) {
    EXPECT_EQ(e.offset(), deadline_at);
  }
  std::mt19937 rng(9);
  for (int trial = 0; trial < 600; ++trial) {
    bad = c.bytes;
    bad[7 + rng() % (bad.size() - 7)] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
    try {
      EXPECT_TRUE(validate(decompress(bad).mesh).ok());
    } catch (const DecodeError&) {
    }
  }
}

}  // namespace
}  // namespace geom::codec::detail
