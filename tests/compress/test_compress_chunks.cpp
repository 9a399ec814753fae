// Chunked streams (version 3): large meshes split into spatial chunks that decode in
// parallel. Round trips at every level on closed, open, polygonal, multi-component and
// shuffled meshes; the same grid and decoded positions as one stream; monotonic levels;
// when chunking does not apply; and damaged streams.

#include "compress/meshes.h"
#include "compress/round_trip.h"

#include <geom/compress/container/codec.h>
#include <geom/core/errors.h>
#include <geom/core/soup.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <string>

namespace geom {
namespace {

using test::Arrays;
using test::expect_round_trip;

constexpr std::size_t kChunk = 16384;  // the smallest chunk compress() accepts

/// Offsets of the chunk sections' payloads in a version 3 stream (FORMAT.md layout).
std::vector<std::size_t> chunk_offsets(const std::vector<std::uint8_t>& b) {
  std::size_t at = 6;
  auto varint = [&] {
    std::uint64_t v = 0;
    for (int shift = 0;; shift += 7) {
      const std::uint8_t x = b.at(at++);
      v |= std::uint64_t{x & 0x7fu} << shift;
      if (!(x & 0x80)) return v;
    }
  };
  const std::uint64_t n = varint();
  for (int s = 0; s < 2; ++s) at += varint();  // the merge map's two sections
  std::vector<std::size_t> out;
  for (std::uint64_t k = 0; k < n; ++k) {
    const std::uint64_t len = varint();
    out.push_back(at);
    at += len;
  }
  EXPECT_EQ(at, b.size());
  return out;
}

Arrays mixed_big() {
  Arrays a = test::torus(200, 100);                    // 40000 triangles, closed
  a.append(test::grid(150, 120, true), {10, 0, 0});    // 18000 quads, open
  a.append(test::holey_slab(6, false), {0, 10, 0});    // quads, high genus
  a.points.push_back({7, 7, 7});                       // isolated
  a.points.push_back({-7, 7, 7});
  return a.shuffled(3);
}

TEST(Chunks, RoundTripAtEveryLevel) {
  const SurfaceMesh m = test::torus(200, 100).build();
  EXPECT_EQ(compress(m, {.chunk_triangles = kChunk}).stats.chunks, 2u);
  for (int level : {0, 1, 3, 5, 7, 9}) expect_round_trip(m, {.level = level, .chunk_triangles = kChunk}, false);
}

TEST(Chunks, RoundTripPolygonsComponentsIsolatedVerticesShuffled) {
  // 14 bits: the dense quad grid's seam vertices need their own grid points (see below).
  const SurfaceMesh m = mixed_big().build();
  const CompressResult c = compress(m, {.bits = 14, .chunk_triangles = kChunk, .keep_corner_order = false});
  EXPECT_EQ(c.stats.chunks, 4u);
  for (int level : {0, 7}) expect_round_trip(m, {.bits = 14, .level = level, .chunk_triangles = kChunk, .keep_corner_order = false}, false);
}

// A chunk has no extension block, so polygons whose first corners are kept (the default)
// make one stream; keep_corner_order = false lets such a mesh be chunked (as above).
TEST(Chunks, PolygonsKeepingTheirFirstCornersAreOneStream) {
  const SurfaceMesh m = mixed_big().build();
  EXPECT_EQ(compress(m, {.bits = 14, .level = 0, .chunk_triangles = kChunk}).stats.chunks, 1u);
}

TEST(Chunks, SameGridAndPositionsAsOneStream) {
  const SurfaceMesh m = mixed_big().build();
  const CompressResult one = compress(m, {.bits = 14, .chunk_triangles = 0});
  const CompressResult many = compress(m, {.bits = 14, .chunk_triangles = kChunk, .keep_corner_order = false});
  ASSERT_EQ(one.stats.chunks, 1u);
  ASSERT_GT(many.stats.chunks, 1u);
  EXPECT_EQ(one.stats.step, many.stats.step);
  EXPECT_EQ(one.stats.max_error, many.stats.max_error);
  const auto a = test::points_of(decompress(one.bytes).mesh);
  const auto b = test::points_of(decompress(many.bytes).mesh);
  std::vector<Point> by_input(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) by_input[one.vertex_permutation[i]] = a[i];
  for (std::size_t i = 0; i < b.size(); ++i)
    ASSERT_EQ(b[i], by_input[many.vertex_permutation[i]]) << "vertex " << i;
  // The flat decode gives the same triangles and (float) positions as the mesh decode.
  const codec::FlatDecode flat = codec::decompress_flat(many.bytes);
  ASSERT_EQ(flat.positions.size(), 3 * b.size());
  for (std::size_t i = 0; i < b.size(); ++i)
    for (int x = 0; x < 3; ++x) ASSERT_EQ(flat.positions[3 * i + x], static_cast<float>(b[i][x]));
  std::size_t triangles = 0;
  for (Face f : m.faces()) triangles += m.valence(f) - 2;
  EXPECT_EQ(flat.triangles.size(), 3 * triangles);
  // It builds its triangles without merging the chunks' tables: every triangle face of the
  // mesh decode is one of them, in the same numbering and orientation.
  std::set<std::vector<std::uint32_t>> flat_tris;
  for (std::size_t c = 0; c < flat.triangles.size(); c += 3)
    flat_tris.insert(test::canonical({flat.triangles[c], flat.triangles[c + 1], flat.triangles[c + 2]}));
  std::size_t checked = 0;
  for (const auto& f : test::faces_of(decompress(many.bytes).mesh)) {
    if (f.size() != 3) continue;
    ASSERT_TRUE(flat_tris.count(test::canonical(f))) << "triangle face " << checked;
    ++checked;
  }
  EXPECT_EQ(checked, 40000u);  // the torus's; the rest are quads
  // Seams cost some bytes: a few percent at this small chunk size.
  EXPECT_LT(many.bytes.size(), one.bytes.size() * 110 / 100);
}

TEST(Chunks, LevelsAreMonotonic) {
  const SurfaceMesh m = test::torus(200, 100).build();
  std::size_t prev = SIZE_MAX;
  for (int level = 0; level <= 9; ++level) {
    const CompressResult c = compress(m, {.level = level, .chunk_triangles = kChunk});
    ASSERT_EQ(c.stats.chunks, 2u);
    EXPECT_LE(c.bytes.size(), prev) << "level " << level;
    prev = c.bytes.size();
  }
}

TEST(Chunks, SeamVerticesOnOneGridPointAreToldApartByTheirBoundaryNeighbours) {
  // At 6 and 7 bits some seam vertices of this torus share a grid point (so the merge map
  // cannot name them by grid point alone), but not their neighbours along the seam.
  const SurfaceMesh m = test::torus(200, 100).build();
  for (unsigned bits : {6u, 7u}) {
    ASSERT_EQ(compress(m, {.bits = bits, .chunk_triangles = kChunk}).stats.chunks, 2u) << bits;
    expect_round_trip(m, {.bits = bits, .chunk_triangles = kChunk}, false);
  }
  std::size_t prev = SIZE_MAX;
  for (int level = 0; level <= 9; ++level) {
    const std::size_t size = compress(m, {.bits = 6, .level = level, .chunk_triangles = kChunk}).bytes.size();
    EXPECT_LE(size, prev) << "level " << level;
    prev = size;
  }
}

TEST(Chunks, OnlyWhereTheyApply) {
  SurfaceMesh m = test::torus(200, 100).build();
  EXPECT_EQ(compress(m, {.chunk_triangles = 20001}).stats.chunks, 1u);  // under twice the size
  EXPECT_EQ(compress(m, {.chunk_triangles = 0}).stats.chunks, 1u);
  EXPECT_EQ(compress(m, {.preserve_order = true, .chunk_triangles = kChunk}).stats.chunks, 1u);
  expect_round_trip(m, {.preserve_order = true, .chunk_triangles = kChunk}, true);
  // A grid too coarse to tell the seam vertices apart, even by their neighbours: one
  // stream, still exact.
  EXPECT_EQ(compress(m, {.bits = 5, .chunk_triangles = kChunk}).stats.chunks, 1u);
  expect_round_trip(m, {.bits = 5, .chunk_triangles = kChunk}, false);
  auto normals = m.add_property<Vertex, Normal>(prop::kVertexNormal);
  for (Vertex v : m.vertices()) normals[v] = Normal(0, 0, 1);
  EXPECT_EQ(compress(m, {.chunk_triangles = kChunk}).stats.chunks, 1u);
  EXPECT_THROW(compress(m, {.chunk_triangles = 1000}), InvalidArgument);
}

TEST(Chunks, DamagedStreamsThrow) {
  const SurfaceMesh m = test::torus(200, 100).build();
  const std::vector<std::uint8_t> good = compress(m, {.chunk_triangles = kChunk}).bytes;
  const std::vector<std::size_t> at = chunk_offsets(good);
  ASSERT_EQ(at.size(), 2u);
  auto error_of = [](const std::vector<std::uint8_t>& b) -> std::string {
    try {
      decompress(b);
    } catch (const DecodeError& e) {
      return e.what();
    }
    return "";
  };
  std::vector<std::uint8_t> b = good;
  b[at[1] + 4] = 9;  // chunk 1's version byte
  EXPECT_EQ(error_of(b), "byte " + std::to_string(at[1] + 4) + ": chunk 1: unsupported stream version 9 "
                         "(this decoder reads versions 1, 2 and 3)");
  b = good;
  b[5] = 1;
  EXPECT_NE(error_of(b).find("unknown flags"), std::string::npos);
  b = good;
  b[6] = 1;  // one chunk
  EXPECT_NE(error_of(b).find("chunk count"), std::string::npos);
  b = good;
  b[at[1] + 9] ^= 0x40;  // chunk 1's grid origin
  EXPECT_NE(error_of(b).find("grid other than chunk 0's"), std::string::npos) << error_of(b);
  // The flat decoder reads chunks by a path of its own (no merged table): the same damage
  // must throw there too.
  for (std::size_t n = 0; n < good.size(); n += 1 + n / 8) {
    const std::vector<std::uint8_t> cut(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n));
    EXPECT_THROW(decompress(cut), DecodeError) << "truncated at " << n;
    EXPECT_THROW(codec::decompress_flat(cut), DecodeError) << "truncated at " << n;
  }
  std::mt19937 rng(5);
  for (int i = 0; i < 300; ++i) {
    b = good;
    b[rng() % b.size()] ^= static_cast<std::uint8_t>(1u << (rng() % 8));
    try {
      const DecompressResult d = decompress(b);
      EXPECT_EQ(d.mesh.n_faces(), m.n_faces());  // a flipped raw bit may only move a point
    } catch (const DecodeError&) {
    }
    try {
      const codec::FlatDecode f = codec::decompress_flat(b);
      EXPECT_EQ(f.triangles.size(), 3 * m.n_faces());
      EXPECT_EQ(f.positions.size(), 3 * m.n_vertices());
    } catch (const DecodeError&) {
    }
  }
}

/// A torus with a normal per vertex (the flat decode's attribute path).
SurfaceMesh torus_with_normals() {
  SurfaceMesh m = test::torus(30, 20).build();
  auto n = m.add_property<Vertex, Normal>(prop::kVertexNormal);
  for (Vertex v : m.vertices()) n[v] = m.position(v).normalized();
  return m;
}

void expect_same_flat(const codec::FlatDecode& a, const codec::FlatDecode& b) {
  EXPECT_TRUE(std::ranges::equal(a.positions, b.positions));
  EXPECT_TRUE(std::ranges::equal(a.triangles, b.triangles));
  EXPECT_EQ(a.normals, b.normals);
  EXPECT_EQ(a.texcoords, b.texcoords);
  EXPECT_EQ(a.corner_normals, b.corner_normals);
  EXPECT_EQ(a.corner_texcoords, b.corner_texcoords);
}

// A torus whose faces alternate between two UV charts: per-corner texture coordinates with
// a seam on every other edge.
SurfaceMesh torus_with_corner_uvs() {
  SurfaceMesh m = test::torus(16, 10).build();
  auto uv = m.add_property<Halfedge, TexCoord>(prop::kCornerTexCoord);
  for (Face f : m.faces())
    for (Halfedge h : m.halfedges(f))
      uv[h] = m.position(m.to_vertex(h)).head<2>() + TexCoord(f.idx() % 2 ? 3.0 : 0.0, 0.0);
  return m;
}

// One FlatDecoder keeps its memory from stream to stream: chunked and single streams, larger
// and smaller, with and without normals, and after a damaged one, each decodes exactly as
// decompress_flat decodes it alone (nothing of the previous stream shows through).
TEST(Chunks, OneFlatDecoderDecodesStreamAfterStream) {
  const SurfaceMesh big = mixed_big().build();
  const std::vector<std::vector<std::uint8_t>> streams = {
      compress(torus_with_normals(), {.level = 5}).bytes,
      compress(big, {.bits = 14, .level = 7, .chunk_triangles = kChunk, .keep_corner_order = false}).bytes,
      compress(big, {.bits = 14, .level = 9, .chunk_triangles = 0}).bytes,
      compress(torus_with_corner_uvs(), {.level = 7}).bytes,  // then a chunked one
      compress(test::torus(200, 100).build(), {.bits = 14, .level = 1, .chunk_triangles = kChunk}).bytes,
      compress(test::grid(20, 10, true).build(), {.level = 7}).bytes};
  ASSERT_EQ(streams[0][4], 2);  // normals
  ASSERT_EQ(streams[1][4], 3);  // chunked
  ASSERT_FALSE(codec::decompress_flat(streams[3]).corner_texcoords.empty());
  ASSERT_EQ(streams[4][4], 3);
  codec::FlatDecoder decoder;
  codec::FlatDecode out;
  for (int round = 0; round < 2; ++round) {
    for (const std::vector<std::uint8_t>& bytes : streams) {
      decoder.decode(bytes, out);
      expect_same_flat(out, codec::decompress_flat(bytes));
      const std::vector<std::uint8_t> cut(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(bytes.size() / 2));
      EXPECT_THROW(decoder.decode(cut, out), DecodeError);
    }
  }
}

}  // namespace
}  // namespace geom
