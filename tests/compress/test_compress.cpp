// Round trips, order preservation, error bounds, levels and hostile streams for the codec.

#include "compress/meshes.h"
#include "compress/round_trip.h"
#include "support/data.h"

#include <geom/compress/container/codec.h>
#include <geom/core/validate.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

namespace geom {
namespace {

using test::Arrays;
using test::expect_round_trip;
using test::points_of;

void expect_all_modes(const Arrays& a) {
  const SurfaceMesh m = a.build();
  for (int level : {0, 1, 3, 7, 9}) expect_round_trip(m, {.level = level}, false);
  expect_round_trip(m, {.preserve_order = true}, true);
  expect_round_trip(m, {.bits = 16, .level = 9, .preserve_order = true}, true);
}

TEST(Compress, RoundTripOpenGrid) { expect_all_modes(test::grid(12, 9)); }
TEST(Compress, RoundTripClosedTorus) { expect_all_modes(test::torus(24, 16)); }
TEST(Compress, RoundTripHighGenusTriangles) { expect_all_modes(test::holey_slab(3, true)); }
TEST(Compress, RoundTripHighGenusQuads) { expect_all_modes(test::holey_slab(3, false)); }
TEST(Compress, RoundTripQuadGrid) { expect_all_modes(test::grid(7, 5, true)); }
TEST(Compress, RoundTripMixedPolygons) { expect_all_modes(test::mixed_polygons()); }

TEST(Compress, RoundTripSeveralComponentsAndIsolatedVertices) {
  Arrays a = test::torus(10, 8);
  a.append(test::grid(5, 4), {20, 0, 0});
  a.append(test::holey_slab(2, false), {0, 20, 0});
  a.append(test::mixed_polygons(), {-20, 0, 0});
  a.points.push_back({7, 7, 7});
  a.points.insert(a.points.begin() + 3, Point(1, 2, 3));  // isolated, mid-array
  for (auto& f : a.faces)
    for (auto& v : f)
      if (v >= 3) ++v;
  expect_all_modes(a);
}

TEST(Compress, RoundTripShuffledOrder) {
  Arrays a = test::torus(30, 20);
  a.append(test::holey_slab(2, true), {10, 0, 0});
  expect_all_modes(a.shuffled(7));
  expect_all_modes(test::holey_slab(2, false).shuffled(11));
}

TEST(Compress, EmptyMeshAndIsolatedOnly) {
  SurfaceMesh empty;
  const auto c = compress(empty);
  const auto d = decompress(c.bytes);
  EXPECT_EQ(d.mesh.n_vertices(), 0u);
  SurfaceMesh pts;
  pts.add_vertex({1, 2, 3});
  pts.add_vertex({4, 5, 6});
  expect_round_trip(pts, {}, false);
  expect_round_trip(pts, {.preserve_order = true}, true);
}

TEST(Compress, SingleTriangleAndCoincidentPositions) {
  Arrays a;
  a.points = {{1, 1, 1}, {1, 1, 1}, {1, 1, 1}};  // zero extent
  a.faces = {{0, 1, 2}};
  expect_all_modes(a);
}

TEST(Compress, HugeAndTinyCoordinates) {
  for (double scale : {1e-12, 1e12}) {
    Arrays a = test::torus(12, 8);
    for (auto& p : a.points) p = p * scale + Eigen::Vector3d(scale * 5, -scale, 0);
    expect_round_trip(a.build(), {.bits = 14}, false);
  }
}

// The ends of double: an extent of a few subnormals (the fuzzer found it through a
// re-encoded decoded stream), coordinates near ±1e308, and a span no double holds.
TEST(Compress, SubnormalAndOverflowingExtents) {
  for (double scale : {4.9e-324 * 3, 8e307}) {
    Arrays a;
    a.points = {{0, 0, 0}, {scale, 0, 0}, {0, -scale, 0}, {-scale, scale, scale}};
    a.faces = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};
    const SurfaceMesh m = a.build();
    const auto c = compress(m, {.bits = 11});
    ASSERT_GT(c.stats.step, 0.0);
    const SurfaceMesh d = decompress(c.bytes).mesh;
    ASSERT_EQ(d.n_vertices(), 4u);
    for (Vertex v : m.vertices()) {  // each input point has a decoded point within step / 2
      double nearest = INFINITY;
      for (Vertex w : d.vertices()) {
        ASSERT_TRUE(d.position(w).allFinite()) << scale;
        nearest = std::min(nearest, (d.position(w) - m.position(v)).cwiseAbs().maxCoeff());
      }
      EXPECT_LE(nearest, 0.5 * c.stats.step * (1 + 1e-9)) << scale;
    }
  }
  Arrays wide = test::torus(6, 4);
  for (auto& p : wide.points) p *= 3e307;  // spans ±1.2e308: more than a double holds
  EXPECT_THROW(compress(wide.build(), {.bits = 11}), InvalidArgument);
}

TEST(Compress, BitsRangeEnds) {
  const SurfaceMesh m = test::torus(16, 12).build();
  for (unsigned bits : {1u, 2u, 8u, 20u, 30u}) expect_round_trip(m, {.bits = bits, .level = 9}, false);
}

TEST(Compress, AbsolutePrecisionKeepsLongObjectsAccurate) {
  Arrays a = test::grid(200, 2);
  for (auto& p : a.points) p.x() *= 1000.0;  // 200 km long, 2 m wide
  const SurfaceMesh m = a.build();
  const auto c = compress(m, {.precision = 1e-3});
  EXPECT_LE(c.stats.max_error, 1e-3 * (1 + 1e-12));
  EXPECT_GT(c.stats.bits, 11u);
  expect_round_trip(m, {.precision = 1e-3}, false);
}

TEST(Compress, LevelsAreMonotonic) {
  for (const Arrays& a : {test::torus(40, 30).shuffled(3), test::holey_slab(3, false)}) {
    const SurfaceMesh m = a.build();
    std::size_t prev = SIZE_MAX;
    for (int level = 0; level <= 9; ++level) {
      const std::size_t size = compress(m, {.level = level}).bytes.size();
      EXPECT_LE(size, prev) << "level " << level;
      prev = size;
    }
  }
}

TEST(Compress, PreserveOrderCostsBytes) {
  const SurfaceMesh m = test::torus(40, 30).shuffled(5).build();
  const auto a = compress(m), b = compress(m, {.preserve_order = true});
  EXPECT_GT(b.bytes.size(), a.bytes.size());
  EXPECT_GT(b.stats.order_bytes, 0u);
  EXPECT_EQ(a.stats.order_bytes, 0u);
}

TEST(Compress, InvalidOptionsThrow) {
  const SurfaceMesh m = test::torus(8, 6).build();
  EXPECT_THROW(compress(m, {.bits = 0}), InvalidArgument);
  EXPECT_THROW(compress(m, {.bits = 31}), InvalidArgument);
  EXPECT_THROW(compress(m, {.level = 10}), InvalidArgument);
  EXPECT_THROW(compress(m, {.level = -1}), InvalidArgument);
  EXPECT_THROW(compress(m, {.precision = -1.0}), InvalidArgument);
  EXPECT_THROW(compress(m, {.precision = 1e-300}), InvalidArgument);  // needs > 30 bits
  SurfaceMesh bad = m;
  bad.position(Vertex(0)) = Point(std::nan(""), 0, 0);
  EXPECT_THROW(compress(bad), InvalidArgument);
}

TEST(Decompress, RejectsBadHeaderWithOffset) {
  auto bytes = compress(test::torus(8, 6).build()).bytes;
  auto bad = bytes;
  bad[0] = 'X';
  try {
    decompress(bad);
    FAIL();
  } catch (const DecodeError& e) {
    EXPECT_EQ(e.offset(), 0u);
  }
  bad = bytes;
  bad[4] = 4;  // version (1, 2 and 3 exist)
  try {
    decompress(bad);
    FAIL();
  } catch (const DecodeError& e) {
    EXPECT_EQ(e.offset(), 4u);
  }
  bytes.push_back(0);
  EXPECT_THROW(decompress(bytes), DecodeError);
  EXPECT_THROW(decompress(std::span<const std::uint8_t>()), DecodeError);
}

/// Decoding a damaged stream must throw DecodeError or yield a valid mesh — never crash.
void expect_safe(const std::vector<std::uint8_t>& bytes) {
  try {
    const auto d = decompress(bytes);
    EXPECT_TRUE(validate(d.mesh).ok());
  } catch (const DecodeError&) {
  }
}

TEST(Decompress, EveryTruncationThrows) {
  for (bool preserve : {false, true}) {
    const auto bytes =
        compress(test::holey_slab(1, false).build(), {.preserve_order = preserve}).bytes;
    for (std::size_t n = 0; n < bytes.size(); ++n) {
      std::vector<std::uint8_t> cut(bytes.begin(), bytes.begin() + static_cast<long>(n));
      EXPECT_THROW(decompress(cut), DecodeError) << "length " << n;
    }
  }
}

TEST(Decompress, RandomBitFlipsNeverCrash) {
  std::mt19937 rng(1234);
  for (bool preserve : {false, true}) {
    Arrays a = test::torus(8, 6);
    a.append(test::mixed_polygons(), {10, 0, 0});
    const auto bytes = compress(a.build(), {.preserve_order = preserve}).bytes;
    for (int trial = 0; trial < 2500; ++trial) {
      auto bad = bytes;
      const int flips = 1 + static_cast<int>(rng() % 3);
      for (int i = 0; i < flips; ++i) bad[rng() % bad.size()] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
      expect_safe(bad);
    }
  }
}

TEST(Decompress, RandomBytesNeverCrash) {
  std::mt19937 rng(99);
  const auto header = compress(test::torus(8, 6).build()).bytes;
  for (int trial = 0; trial < 2000; ++trial) {
    std::vector<std::uint8_t> bytes(header.begin(), header.begin() + 8);  // valid magic/flags
    const std::size_t n = rng() % 200;
    for (std::size_t i = 0; i < n; ++i) bytes.push_back(static_cast<std::uint8_t>(rng()));
    expect_safe(bytes);
  }
}

// The connectivity would grow the 400th triangle after the count says 399: the flat decoder
// used to return it (its gates now live in a block sized by the count, so this matters).
TEST(Decompress, TriangleCountBelowTheConnectivityThrows) {
  auto bytes = compress(test::torus(20, 10).build()).bytes;
  const std::uint8_t predictor = bytes[6];
  // The blend byte (4–7), the isolated byte (5, 7) and the deadline byte (6, 7).
  const std::size_t counts = 40 + (predictor >= 4 ? 1 : 0) + (predictor == 5 || predictor == 7) +
                             (predictor >= 6 ? 1 : 0);
  // n_faces and n_triangles: 400 = varint 90 03; 399 = 8f 03.
  for (std::size_t at : {counts, counts + 2}) {
    ASSERT_EQ(bytes[at], 0x90);
    ASSERT_EQ(bytes[at + 1], 0x03);
    bytes[at] = 0x8f;
  }
  EXPECT_THROW(codec::decompress_flat(bytes), DecodeError);
  EXPECT_THROW(decompress(bytes), DecodeError);
}

TEST(Compress, FlatDecodeMatchesMeshDecode) {
  const SurfaceMesh m = test::torus(20, 10).build();
  const auto c = compress(m);
  const auto flat = codec::decompress_flat(c.bytes);
  const auto d = decompress(c.bytes);
  ASSERT_EQ(flat.positions.size(), 3 * m.n_vertices());
  ASSERT_EQ(flat.triangles.size(), 3 * m.n_faces());
  const auto pts = points_of(d.mesh);
  for (std::size_t i = 0; i < pts.size(); ++i)
    EXPECT_NEAR(flat.positions[3 * i], pts[i].x(), 1e-5);
}

}  // namespace
}  // namespace geom
