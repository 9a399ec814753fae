// Non-manifold sources: build() splits their non-manifold edges and vertices, the stream
// records which vertices the split made of one (CompressOptions::vertex_origin, extension
// kind 3), and join_vertices() on the decoded soup gives the source back. Also the decoder's
// checks of that entry.

#include "support/data.h"

#include <geom/compress/container/codec.h>
#include <geom/core/build.h>
#include <geom/core/soup.h>
#include <geom/core/validate.h>
#include <geom/io/io.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>

namespace geom {
namespace {

// Two fans (pyramids without bases) meeting at their apex 0: a bow-tie vertex.
PolygonSoup bow_tie() {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {-1, 0, -1}, {-1, -1, -1}, {0, -1, -1}};
  s.add_face({0, 1, 2});
  s.add_face({0, 2, 3});
  s.add_face({0, 3, 1});
  s.add_face({0, 4, 5});
  s.add_face({0, 5, 6});
  s.add_face({0, 6, 4});
  return s;
}

// Three triangles on the edge 0–1 (a fin), and a bow-tie at vertex 5: two kinds of split.
PolygonSoup fin_and_bow_tie() {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}, {0.5, 0, 1},
                 {3, 0, 0}, {4, 0, 0}, {3.5, 1, 0}, {2, 0, 0}, {2.5, -1, 0}};
  s.add_face({0, 1, 2});
  s.add_face({1, 0, 3});
  s.add_face({0, 1, 4});
  s.add_face({5, 6, 7});
  s.add_face({5, 8, 9});
  return s;
}

// part's vertices and faces added to s, moved by offset.
void append(PolygonSoup& s, const PolygonSoup& part, const Point& offset) {
  const auto base = static_cast<std::uint32_t>(s.positions.size());
  for (const Point& p : part.positions) s.positions.push_back(p + offset);
  for (std::size_t f = 0; f < part.n_faces(); ++f) {
    std::vector<std::uint32_t> c;
    for (std::uint32_t v : part.face(f)) c.push_back(base + v);
    s.add_face(c);
  }
}

// k bow-ties in a row, each apex shared by its two fans (separate components after the split).
PolygonSoup bow_ties(std::uint32_t k) {
  PolygonSoup s;
  for (std::uint32_t i = 0; i < k; ++i) append(s, bow_tie(), Point(3.0 * i, 0, 0));
  return s;
}

// A 12 × 12 grid of quads whose vertex (k, k) is also used in place of (11 − k, 11 − k) for
// k = 1 … 4: pinch points whose two fans the rest of the sheet joins. The faces are listed
// from the far corner back, after the first one: build() leaves the source vertex to the
// far fan, listed first, while the traversal starts at face 0 and meets the near fan, with
// the copy, first. The replaced vertices stay, unreferenced.
PolygonSoup pinched_grid() {
  constexpr std::uint32_t n = 12;
  PolygonSoup s;
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) s.positions.push_back({double(i), double(j), 0.1 * double((i * j) % 3)});
  auto id = [&](std::uint32_t i, std::uint32_t j) {
    for (std::uint32_t k = 1; k <= 4; ++k)
      if (i == n - 1 - k && j == n - 1 - k) return k * n + k;
    return j * n + i;
  };
  std::vector<std::array<std::uint32_t, 4>> quads;
  for (std::uint32_t j = 0; j + 1 < n; ++j)
    for (std::uint32_t i = 0; i + 1 < n; ++i) quads.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
  std::reverse(quads.begin() + 1, quads.end());
  for (const auto& q : quads) s.add_face({q[0], q[1], q[2], q[3]});
  return s;
}

struct Coded {
  BuildResult built;
  CompressResult c;
  DecompressResult d;
};

Coded code(const PolygonSoup& soup, CompressOptions opt) {
  Coded r;
  r.built = build(soup);
  opt.vertex_origin = r.built.report.vertex_origin;
  r.c = compress(r.built.mesh, opt);
  r.d = decompress(r.c.bytes);
  return r;
}

std::vector<std::uint32_t> cyclic(std::vector<std::uint32_t> f) {
  std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  return f;
}

std::multiset<std::vector<std::uint32_t>> face_set(const PolygonSoup& s) {
  std::multiset<std::vector<std::uint32_t>> out;
  for (std::size_t f = 0; f < s.n_faces(); ++f) {
    const auto c = s.face(f);
    out.insert(cyclic({c.begin(), c.end()}));
  }
  return out;
}

TEST(CompressSplit, PreservedOrderGivesTheSourceBackExactly) {
  for (const PolygonSoup& src : {bow_tie(), fin_and_bow_tie(), bow_ties(12), pinched_grid()}) {
    CompressOptions opt;
    opt.preserve_order = true;
    opt.bits = 16;
    const Coded r = code(src, opt);
    ASSERT_GT(r.built.mesh.n_vertices(), src.positions.size()) << "the source was not split";
    ASSERT_TRUE(validate(r.d.mesh).ok());
    ASSERT_EQ(r.d.vertex_representative.size(), r.d.mesh.n_vertices());
    PolygonSoup back = to_soup(r.d.mesh);
    join_vertices(back, r.d.vertex_representative);
    ASSERT_EQ(back.positions.size(), src.positions.size());
    EXPECT_EQ(back.face_offsets, src.face_offsets);
    EXPECT_EQ(back.face_indices, src.face_indices);
    for (std::size_t v = 0; v < src.positions.size(); ++v)
      EXPECT_LE((back.positions[v] - src.positions[v]).cwiseAbs().maxCoeff(),
                r.c.stats.max_error * (1 + 1e-12))
          << "vertex " << v;
  }
}

TEST(CompressSplit, ReorderedStreamJoinsExactlyTheSplitGroups) {
  const PolygonSoup src = fin_and_bow_tie();
  for (int level : {0, 7, 9}) {
    SCOPED_TRACE(level);
    CompressOptions opt;
    opt.level = level;
    const Coded r = code(src, opt);
    const auto& origin = r.built.report.vertex_origin;
    const auto& perm = r.c.vertex_permutation;  // decoded vertex -> built vertex
    const auto& rep = r.d.vertex_representative;
    ASSERT_EQ(rep.size(), perm.size());
    for (std::uint32_t u = 0; u < rep.size(); ++u) {
      EXPECT_EQ(rep[rep[u]], rep[u]);
      EXPECT_LE(rep[u], u);
      for (std::uint32_t v = 0; v < rep.size(); ++v)
        EXPECT_EQ(rep[u] == rep[v], origin[perm[u]] == origin[perm[v]]) << u << ", " << v;
    }
    // The joined faces, in source numbering, are the source's faces.
    PolygonSoup back = to_soup(r.d.mesh);
    join_vertices(back, rep);
    ASSERT_EQ(back.positions.size(), src.positions.size());
    std::map<std::uint32_t, std::uint32_t> to_source;  // joined vertex -> source vertex
    std::uint32_t k = 0;
    for (std::uint32_t v = 0; v < rep.size(); ++v)
      if (rep[v] == v) to_source[k++] = origin[perm[v]];
    for (std::uint32_t& c : back.face_indices) c = to_source.at(c);
    EXPECT_EQ(face_set(back), face_set(src));
  }
}

// The flat arrays are the joined soup of decompress(): the source's vertex count, each
// group one vertex, the same triangles over it (a flat triangle list, unlike a SurfaceMesh,
// can hold a non-manifold mesh).
TEST(CompressSplit, FlatDecodeJoinsTheSplitGroups) {
  for (const PolygonSoup& src : {fin_and_bow_tie(), bow_ties(5), pinched_grid()}) {
    for (int level : {0, 7, 9}) {
      SCOPED_TRACE(level);
      CompressOptions opt;
      opt.level = level;
      const Coded r = code(src, opt);
      ASSERT_TRUE(r.built.report.split_apart());
      PolygonSoup back = to_soup(r.d.mesh);
      join_vertices(back, r.d.vertex_representative);
      const codec::FlatDecode flat = codec::decompress_flat(r.c.bytes);
      ASSERT_EQ(flat.positions.size(), 3 * src.positions.size());
      ASSERT_EQ(back.positions.size(), src.positions.size());
      for (std::size_t v = 0; v < back.positions.size(); ++v)
        for (int x = 0; x < 3; ++x)
          EXPECT_NEAR(flat.positions[3 * v + x], back.positions[v][x], 1e-6) << v;
      // Each face comes back as its k − 2 triangles over its own corners (the quads fanned
      // from an apex the stream chose), so triangles are matched to faces by vertex sets.
      std::map<std::set<std::uint32_t>, int> faces;  // corner set -> triangles still due
      std::size_t due = 0;
      for (std::size_t f = 0; f < back.n_faces(); ++f) {
        const auto c = back.face(f);
        faces[std::set<std::uint32_t>(c.begin(), c.end())] += static_cast<int>(c.size()) - 2;
        due += c.size() - 2;
      }
      ASSERT_EQ(flat.triangles.size(), 3 * due);
      for (std::size_t t = 0; t < flat.triangles.size(); t += 3) {
        const std::set<std::uint32_t> tri(flat.triangles.begin() + t, flat.triangles.begin() + t + 3);
        ASSERT_EQ(tri.size(), 3u) << "triangle " << t / 3 << " repeats a vertex";
        auto it = std::find_if(faces.begin(), faces.end(), [&](const auto& f) {
          return f.second > 0 && std::includes(f.first.begin(), f.first.end(), tri.begin(), tri.end());
        });
        ASSERT_NE(it, faces.end()) << "triangle " << t / 3 << " lies in no face";
        --it->second;
      }
    }
  }
}

TEST(CompressSplit, StreamWithoutSharedOriginsIsUnchanged) {
  const BuildResult b = build(bow_tie());
  std::vector<std::uint32_t> identity(b.mesh.n_vertices());
  for (std::uint32_t v = 0; v < identity.size(); ++v) identity[v] = v;
  CompressOptions with;
  with.vertex_origin = identity;
  EXPECT_EQ(compress(b.mesh, with).bytes, compress(b.mesh, {}).bytes);
  EXPECT_TRUE(decompress(compress(b.mesh, with).bytes).vertex_representative.empty());
}

TEST(CompressSplit, RejectsAnOriginListOfTheWrongLength) {
  const BuildResult b = build(bow_tie());
  CompressOptions opt;
  opt.vertex_origin = {0, 1, 2};
  EXPECT_THROW(compress(b.mesh, opt), InvalidArgument);
}

TEST(CompressSplit, SizeStaysWithinTheBound) {
  const PolygonSoup src = fin_and_bow_tie();
  const Coded r = code(src, {});
  const std::size_t copies = r.built.mesh.n_vertices() - src.positions.size();
  EXPECT_EQ(copies, 3u);  // vertex 0 and 1 of the fin once each, vertex 5 once
  std::size_t corners = 0;
  for (Face f : r.built.mesh.faces()) corners += r.built.mesh.valence(f);
  const std::size_t nv = r.built.mesh.n_vertices(), nf = r.built.mesh.n_faces();
  EXPECT_LE(r.c.bytes.size(), max_compressed_size(nv, nf, corners, 0, 0, 0, copies));
  // The entry's allowance: a kind byte, a count and two varints of at most 5 bytes a copy
  // (the block's own count is always allowed for: face rotations may open it).
  EXPECT_EQ(max_compressed_size(nv, nf, corners, 0, 0, 0, copies) -
                max_compressed_size(nv, nf, corners, 0, 0, 0, 0),
            6 + 10 * copies);
}

TEST(CompressSplit, LargeSplitMeshIsCodedAsOneStream) {
  // A 180 × 100 grid (36000 triangles, enough for two chunks of 16384) and a bow-tie.
  PolygonSoup s;
  const std::uint32_t nx = 181, ny = 101;
  for (std::uint32_t j = 0; j < ny; ++j)
    for (std::uint32_t i = 0; i < nx; ++i) s.positions.push_back({double(i), double(j), 0.01 * ((i * 7 + j * 3) % 5)});
  for (std::uint32_t j = 0; j + 1 < ny; ++j)
    for (std::uint32_t i = 0; i + 1 < nx; ++i) {
      const std::uint32_t a = j * nx + i;
      s.add_face({a, a + 1, a + nx + 1});
      s.add_face({a, a + nx + 1, a + nx});
    }
  append(s, bow_tie(), Point(0, 0, 5));
  CompressOptions opt;
  opt.chunk_triangles = 16384;
  const Coded r = code(s, opt);
  EXPECT_EQ(r.c.stats.chunks, 1u);
  PolygonSoup back = to_soup(r.d.mesh);
  join_vertices(back, r.d.vertex_representative);
  EXPECT_EQ(back.positions.size(), s.positions.size());
  EXPECT_EQ(back.n_faces(), s.n_faces());
}

// The split entry is the stream's last: kind 3, count, then (gap, representative) per copy,
// one byte each for these small meshes.
std::vector<std::uint8_t> split_stream(const PolygonSoup& src, std::size_t copies) {
  const Coded r = code(src, {});
  const auto& b = r.c.bytes;
  EXPECT_GE(b.size(), 2 + 2 * copies);
  EXPECT_EQ(b[b.size() - 2 - 2 * copies], 3) << "the split entry is not last";
  EXPECT_EQ(b[b.size() - 1 - 2 * copies], copies);
  return b;
}

// Both decoders reject it with the same message: the flat one reads the split entry too.
void expect_rejected(const std::vector<std::uint8_t>& bytes, const std::string& what) {
  for (bool flat : {false, true}) {
    SCOPED_TRACE(flat ? "decompress_flat" : "decompress");
    try {
      if (flat) codec::decompress_flat(bytes);
      else decompress(bytes);
      ADD_FAILURE() << "accepted: " << what;
    } catch (const DecodeError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("byte"), std::string::npos) << e.what();
    }
  }
}

TEST(CompressSplit, DecoderRejectsBadSplitEntries) {
  const std::vector<std::uint8_t> one = split_stream(bow_tie(), 1);
  const std::size_t n = one.size();
  ASSERT_NO_THROW(decompress(one));
  auto patched = [&](std::vector<std::uint8_t> b, std::size_t from_end, std::uint8_t value) {
    b[b.size() - from_end] = value;
    return b;
  };
  expect_rejected(patched(one, 1, one[n - 2]), "not before it");  // joined to itself
  expect_rejected(patched(one, 2, 120), "beyond the vertex count");
  expect_rejected(patched(one, 3, 0), "split vertex count 0 impossible");
  expect_rejected(patched(one, 3, 2), "impossible");  // more copies than bytes
  expect_rejected(patched(one, 4, 9), "unknown extension entry kind 9");
  expect_rejected(std::vector<std::uint8_t>(one.begin(), one.end() - 1), "impossible");  // truncated
  // The entry twice (the block's entry count, just before it, raised to 2).
  std::vector<std::uint8_t> twice = patched(one, 5, 2);
  twice.insert(twice.end(), one.end() - 4, one.end());
  expect_rejected(twice, "split vertices given twice");
  // A ten-byte gap: far beyond the vertices, and no overflow on the way.
  std::vector<std::uint8_t> far(one.begin(), one.end() - 2);
  far.insert(far.end(), {0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x01, 0});
  expect_rejected(far, "beyond the vertex count");
  // A representative before the copy but elsewhere: the copy would move onto it.
  const std::uint8_t copy = one[n - 2];
  for (std::uint8_t other = 0; other < copy; ++other) {
    if (other == one[n - 1]) continue;
    expect_rejected(patched(one, 1, other), "not at its representative's position");
  }

  // Two copies: the second joined to the first copy, a chain.
  const std::vector<std::uint8_t> two = split_stream(fin_and_bow_tie(), 3);
  ASSERT_NO_THROW(decompress(two));
  const std::size_t m = two.size();
  const std::uint8_t first_copy = two[m - 6];  // the first gap is the copy's number
  expect_rejected(patched(two, 3, first_copy), "another split vertex");
  expect_rejected(patched(two, 2, 100), "beyond the vertex count");
}

TEST(CompressSplit, SplitVerticesTravelWithGenericAttributesAndDetachedFaces) {
  // Five vertices whose faces put three triangles on an edge: build() detaches one face.
  PolygonSoup src;
  src.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0.5, 0.5, 1}};
  for (const auto& f : {std::array<std::uint32_t, 3>{2, 1, 4}, {3, 1, 2}, {1, 3, 4}, {4, 3, 0}, {3, 2, 4}})
    src.add_face({f[0], f[1], f[2]});
  src.vertex_colors = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}};
  CompressOptions opt;
  opt.preserve_order = true;
  const Coded r = code(src, opt);
  ASSERT_GT(r.built.report.detached_faces, 0u);
  ASSERT_GT(r.built.mesh.n_vertices(), src.positions.size());
  PolygonSoup back = to_soup(r.d.mesh);
  join_vertices(back, r.d.vertex_representative);
  EXPECT_EQ(back.face_indices, src.face_indices);
  ASSERT_EQ(back.vertex_colors.size(), src.positions.size());
  for (std::size_t v = 0; v < src.positions.size(); ++v)
    EXPECT_LE((back.vertex_colors[v] - src.vertex_colors[v]).cwiseAbs().maxCoeff(), 0.5 / 4095 + 1e-9);
}

TEST(CompressSplit, RejectsGroupedVerticesAtDifferentPositions) {
  const BuildResult b = build(bow_tie());
  CompressOptions opt;
  opt.vertex_origin = b.report.vertex_origin;
  opt.vertex_origin[1] = opt.vertex_origin[0];  // the apex and a rim vertex "one vertex"
  try {
    compress(b.mesh, opt);
    ADD_FAILURE() << "accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("vertices 0 and 1"), std::string::npos) << e.what();
  }
}

TEST(JoinVertices, CarriesAttributesAndTagsAndRejectsBadEntries) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}};
  s.vertex_colors = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  s.vertex_scalars = {{"q", {1, 2, 3, 4}}};
  s.add_face({0, 1, 2});
  s.add_face({3, 2, 1});
  s.creases = {{3, 1, 2.0}};
  s.corners = {{3, 1.5}};
  PolygonSoup j = s;
  join_vertices(j, std::vector<std::uint32_t>{0, 1, 2, 0});
  EXPECT_EQ(j.positions.size(), 3u);
  EXPECT_EQ(j.face_indices, (std::vector<std::uint32_t>{0, 1, 2, 0, 2, 1}));
  EXPECT_EQ(j.vertex_colors.size(), 3u);
  EXPECT_EQ(j.vertex_scalars[0].values, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(j.creases[0].a, 0u);
  EXPECT_EQ(j.corners[0].v, 0u);
  // Vertex 2 removed: 3 becomes 2.
  PolygonSoup k = s;
  join_vertices(k, std::vector<std::uint32_t>{0, 1, 1, 3});
  EXPECT_EQ(k.face_indices, (std::vector<std::uint32_t>{0, 1, 1, 2, 1, 1}));
  EXPECT_THROW(join_vertices(k, std::vector<std::uint32_t>{0, 1}), InvalidArgument);
  PolygonSoup bad = s;
  EXPECT_THROW(join_vertices(bad, std::vector<std::uint32_t>{0, 1, 2, 9}), InvalidArgument);
  EXPECT_THROW(join_vertices(bad, std::vector<std::uint32_t>{3, 1, 2, 0}), InvalidArgument);
  bad.vertex_colors.pop_back();  // the soup's own arrays are checked first
  EXPECT_THROW(join_vertices(bad, std::vector<std::uint32_t>{0, 1, 2, 0}), InvalidArgument);
}

TEST(JoinVertices, TagsOfTheCopiesBecomeOneOfTheLargerSharpness) {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 0}, {1, 0, 0}};
  s.add_face({0, 1, 2});
  s.add_face({4, 3, 2});
  s.creases = {{0, 1, 1.0}, {4, 3, 3.0}, {1, 2, 0.5}};
  s.corners = {{0, 2.0}, {3, 1.0}};
  join_vertices(s, std::vector<std::uint32_t>{0, 1, 2, 0, 1});
  ASSERT_EQ(s.creases.size(), 2u);
  EXPECT_EQ(s.creases[0].a, 0u);
  EXPECT_EQ(s.creases[0].b, 1u);
  EXPECT_EQ(s.creases[0].sharpness, 3.0);
  EXPECT_EQ(s.creases[1].a, 1u);
  EXPECT_EQ(s.creases[1].b, 2u);
  ASSERT_EQ(s.corners.size(), 1u);
  EXPECT_EQ(s.corners[0].sharpness, 2.0);
}

TEST(CompressSplit, TeapotRoundTripsWithItsNonManifoldVertices) {
  GEOM_REQUIRE_DATA_DIR(dir);
  const PolygonSoup src = read_soup(dir / "teapot.obj");
  CompressOptions opt;
  opt.preserve_order = true;
  const Coded r = code(src, opt);
  ASSERT_GT(r.built.report.split_nonmanifold_vertices + r.built.report.split_nonmanifold_edges, 0u);
  PolygonSoup back = to_soup(r.d.mesh);
  join_vertices(back, r.d.vertex_representative);
  ASSERT_EQ(back.positions.size(), src.positions.size());
  EXPECT_EQ(back.face_indices, src.face_indices);
}

}  // namespace
}  // namespace geom
