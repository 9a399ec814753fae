// Streams written before TWO_LANES (one rANS state per section) still decode. The fixtures in
// legacy/ were written by the encoder of commit 3d77444 from data/sample.obj (default
// options, and --preserve-order), from it with radial normals and per-corner texture
// coordinates (version 2, extension block), and from its Catmull-Clark level 2 (50688
// triangles) as a chunked stream (--bits 8 --chunk-triangles 16384); and from data/sample.obj
// at level 9 (growth-order predictor 7) and with a per-vertex colour (an ascii PLY with red,
// green and blue: a generic attribute in the extension block). A misread lane count
// fails the sections' end check (every state back at 2^23, every byte consumed).
// spindle_closed.gmc and spindle_open.gmc were written by the encoder of commit 41c5cd8 from
// test::spindle(300, 4, closed) at the default level (predictor 5): apexes of 300 wedges,
// whose residual contexts the degree pass sums apart from a smaller vertex's.

#include <geom/compress/container/codec.h>
#include <geom/core/errors.h>
#include <geom/io/io.h>

#include "meshes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace geom {
namespace {

const std::filesystem::path kDir = std::filesystem::path(GEOM_SOURCE_DIR) / "tests/compress/legacy";

std::vector<std::uint8_t> read_bytes(const std::filesystem::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

std::vector<std::uint8_t> fixture(const char* name) {
  const std::vector<std::uint8_t> b = read_bytes(kDir / name);
  EXPECT_GT(b.size(), 8u) << name;
  return b;
}

TEST(CompressLegacy, OneLaneStreamInInputOrderDecodesToTheInput) {
  const SurfaceMesh input = load_mesh(std::filesystem::path(GEOM_SOURCE_DIR) / "data/sample.obj").mesh;
  const std::vector<std::uint8_t> bytes = fixture("sample_one_lane_ordered.gmc");
  ASSERT_EQ(bytes[5] & 32, 0);  // no TWO_LANES flag
  const DecompressResult r = decompress(bytes);
  ASSERT_TRUE(r.order_preserved);
  ASSERT_EQ(r.mesh.n_vertices(), input.n_vertices());
  ASSERT_EQ(r.mesh.n_faces(), input.n_faces());
  for (Vertex v : input.vertices())
    for (int i = 0; i < 3; ++i)
      ASSERT_LE(std::abs(r.mesh.position(v)[i] - input.position(v)[i]), r.max_error * (1 + 1e-9)) << v.idx();
  for (Face f : input.faces()) {
    std::vector<Vertex> a, b;
    for (Vertex v : input.vertices(f)) a.push_back(v);
    for (Vertex v : r.mesh.vertices(f)) b.push_back(v);
    ASSERT_EQ(a, b) << f.idx();
  }
}

TEST(CompressLegacy, OneLaneStreamsOfEveryKindDecode) {
  const SurfaceMesh input = load_mesh(std::filesystem::path(GEOM_SOURCE_DIR) / "data/sample.obj").mesh;
  // Reordered: every decoded vertex lies within the bound of an input vertex.
  const DecompressResult plain = decompress(fixture("sample_one_lane.gmc"));
  ASSERT_EQ(plain.mesh.n_vertices(), input.n_vertices());
  ASSERT_EQ(plain.mesh.n_faces(), input.n_faces());
  for (Vertex v : plain.mesh.vertices()) {
    double best = INFINITY;
    for (Vertex w : input.vertices())
      best = std::min(best, (plain.mesh.position(v) - input.position(w)).cwiseAbs().maxCoeff());
    ASSERT_LE(best, plain.max_error * (1 + 1e-9)) << v.idx();
  }
  // Version 2: the normals' sections and the extension block's (corner texture coordinates).
  const std::vector<std::uint8_t> attr = fixture("sample_attr_one_lane.gmc");
  ASSERT_EQ(attr[4], 2);
  const DecompressResult a = decompress(attr);
  EXPECT_EQ(a.mesh.n_vertices(), input.n_vertices());
  EXPECT_EQ(a.mesh.n_faces(), input.n_faces());
  EXPECT_TRUE(a.mesh.has_property<Vertex>("v:normal"));
  EXPECT_TRUE(a.mesh.has_property<Halfedge>("h:texcoord"));
  // Predictor 7 (growth order, coded subsets) and a generic attribute's planes.
  const std::vector<std::uint8_t> growth = fixture("sample_growth_one_lane.gmc");
  ASSERT_EQ(growth[6], 7);
  EXPECT_EQ(decompress(growth).mesh.n_vertices(), input.n_vertices());
  const DecompressResult colour = decompress(fixture("sample_colour_one_lane.gmc"));
  EXPECT_EQ(colour.mesh.n_vertices(), input.n_vertices());
  ASSERT_EQ(colour.attributes.size(), 1u);
  EXPECT_EQ(colour.attributes[0].name, "v:color");
  // Version 3: the merge map's section and each chunk's.
  const std::vector<std::uint8_t> chunked = fixture("sample_chunked_one_lane.gmc");
  ASSERT_EQ(chunked[4], 3);
  const DecompressResult c = decompress(chunked);
  EXPECT_EQ(c.mesh.n_faces(), 25344u);
  EXPECT_EQ(c.mesh.n_vertices(), 25344u);  // a closed torus of quads: V = F
  EXPECT_EQ(c.mesh.n_edges(), 50688u);
}

TEST(CompressLegacy, CurrentStreamsHaveTwoLanesAndDecodeTheSame) {
  const SurfaceMesh input = load_mesh(std::filesystem::path(GEOM_SOURCE_DIR) / "data/sample.obj").mesh;
  CompressOptions o;
  o.preserve_order = true;
  const std::vector<std::uint8_t> now = compress(input, o).bytes;
  ASSERT_EQ(now[5] & 32, 32);
  const DecompressResult a = decompress(now), b = decompress(fixture("sample_one_lane_ordered.gmc"));
  for (Vertex v : input.vertices()) ASSERT_EQ(a.mesh.position(v), b.mesh.position(v)) << v.idx();
  // The flag decides: the same bytes read with the other lane count fail.
  std::vector<std::uint8_t> flipped = now;
  flipped[5] &= static_cast<std::uint8_t>(~32);
  EXPECT_THROW(decompress(flipped), DecodeError);
}

TEST(CompressLegacy, HighValenceVerticesCodeAsBefore) {
  for (const bool closed : {true, false}) {
    const SurfaceMesh input = test::spindle(300, 4, closed).build();
    const std::vector<std::uint8_t> before =
        fixture(closed ? "spindle_closed.gmc" : "spindle_open.gmc");
    ASSERT_EQ(before[6], 5) << closed;  // the degree pass with coded subsets
    // The same bytes today, so the same contexts on both sides; and the old stream decodes.
    const CompressResult now = compress(input, {});
    EXPECT_EQ(now.bytes, before) << closed;
    const DecompressResult d = decompress(before);
    ASSERT_EQ(d.mesh.n_vertices(), input.n_vertices());
    ASSERT_EQ(d.mesh.n_faces(), input.n_faces());
    std::size_t i = 0;
    for (Vertex v : d.mesh.vertices()) {
      const Point& p = input.position(Vertex(now.vertex_permutation[i++]));
      ASSERT_LE((d.mesh.position(v) - p).cwiseAbs().maxCoeff(), now.stats.max_error * (1 + 1e-9));
    }
  }
}

}  // namespace
}  // namespace geom
