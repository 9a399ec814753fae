// The codec keeps what a file holds (issue 42): every face, degenerate ones included
// (extension kind 5), each polygon's first corner (kind 4) and each face's orientation, through
// compress(const PolygonSoup&) and to_soup(const DecompressResult&).

#include "support/data.h"

#include <geom/compress/container/codec.h>
#include <geom/compress/container/soup_codec.h>
#include <geom/core/build.h>
#include <geom/core/soup.h>
#include <geom/io/io.h>
#include <geom/spatial/distance.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

namespace geom {
namespace {

using Faces = std::vector<std::vector<std::uint32_t>>;

// An n × n grid of quads on z = amp · sin(x) cos(y): non-planar quads whose fan
// triangulation depends on their first corner; each quad starts at a corner chosen by `start`.
PolygonSoup wavy_grid(std::uint32_t n, double amp, std::uint32_t start = 0) {
  PolygonSoup s;
  for (std::uint32_t j = 0; j <= n; ++j)
    for (std::uint32_t i = 0; i <= n; ++i)
      s.positions.push_back({double(i), double(j), amp * std::sin(1.3 * i) * std::cos(1.7 * j)});
  for (std::uint32_t j = 0; j < n; ++j)
    for (std::uint32_t i = 0; i < n; ++i) {
      const std::uint32_t a = j * (n + 1) + i;
      std::vector<std::uint32_t> q = {a, a + 1, a + n + 2, a + n + 1};
      std::rotate(q.begin(), q.begin() + (i * 7 + j * 3 + start) % 4, q.end());
      s.add_face(q);
    }
  return s;
}

// The grid with the faces build() drops or changes: a repeated index, a collapsed repeat
// (a a b c), three collinear corners, a duplicate of a quad's vertex set, a flipped quad.
PolygonSoup grid_with_bad_faces() {
  const PolygonSoup grid = wavy_grid(6, 0.0);
  PolygonSoup s;
  s.positions = grid.positions;
  for (std::size_t f = 0; f < grid.n_faces(); ++f) {
    std::vector<std::uint32_t> c(grid.face(f).begin(), grid.face(f).end());
    if (f == 20) std::reverse(c.begin(), c.end());  // disagrees with its neighbours
    s.add_face(c);
  }
  s.add_face({0, 0, 1});
  s.add_face({8, 8, 9, 15});
  s.add_face({0, 1, 2});  // collinear: zero area
  s.add_face({7, 8, 1, 0});  // the first quad's vertex set, reversed
  return s;
}

// Each decoded vertex's input vertex, matched by (x, y): the test grids' vertices lie on
// distinct integer points in x and y, far beyond the grid error.
std::vector<std::uint32_t> match_vertices(const PolygonSoup& in, const PolygonSoup& out) {
  std::vector<std::uint32_t> m(out.positions.size(), 0xffffffffu);
  std::map<std::array<long long, 2>, std::uint32_t> at;
  auto key = [](const Point& p) {
    return std::array<long long, 2>{std::llround(p.x()), std::llround(p.y())};
  };
  for (std::uint32_t v = 0; v < in.positions.size(); ++v) at[key(in.positions[v])] = v;
  for (std::uint32_t v = 0; v < out.positions.size(); ++v)
    if (auto it = at.find(key(out.positions[v])); it != at.end()) m[v] = it->second;
  return m;
}

Faces faces_of(const PolygonSoup& s, std::span<const std::uint32_t> to_input = {}) {
  Faces out;
  for (std::size_t f = 0; f < s.n_faces(); ++f) {
    out.emplace_back();
    for (std::uint32_t v : s.face(f)) out.back().push_back(to_input.empty() ? v : to_input[v]);
  }
  return out;
}

/// Triangles to their lowest corner (their first corner is not kept by default).
Faces rotate_triangles(Faces fs) {
  for (auto& f : fs)
    if (f.size() == 3) std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  return fs;
}

Faces sorted(Faces fs) {
  std::sort(fs.begin(), fs.end());
  return fs;
}

PolygonSoup round_trip(const PolygonSoup& in, const CompressOptions& o = {}) {
  return to_soup(decompress(compress(in, o).bytes));
}

TEST(CompressFidelity, KeepsDegenerateZeroAreaDuplicateAndFlippedFaces) {
  const PolygonSoup in = grid_with_bad_faces();
  const BuildResult built = build(in);
  ASSERT_LT(built.mesh.n_faces(), in.n_faces());  // what the mesh alone loses
  const CompressResult r = compress(in);
  EXPECT_EQ(r.stats.loose_faces, 4u);
  EXPECT_GT(r.stats.loose_face_bytes, 0u);
  const PolygonSoup out = to_soup(decompress(r.bytes));
  ASSERT_EQ(out.n_faces(), in.n_faces());
  ASSERT_EQ(out.positions.size(), in.positions.size());
  const auto m = match_vertices(in, out);
  EXPECT_EQ(sorted(rotate_triangles(faces_of(out, m))), sorted(rotate_triangles(faces_of(in))));
  // The flat path checks the new entries and returns the mesh's triangles.
  EXPECT_EQ(codec::decompress_flat(r.bytes).triangles.size(), 3u * 2 * 36);  // the 36 quads
}

TEST(CompressFidelity, CornerValuesOfLooseFacesAreNamedAsNotStored) {
  PolygonSoup in = grid_with_bad_faces();
  in.corner_texcoords.assign(in.face_indices.size(), TexCoord(0.25, 0.5));
  const CompressResult r = compress(in);
  ASSERT_EQ(r.stats.loose_faces, 4u);
  const auto& d = r.stats.dropped_properties;
  EXPECT_NE(std::find(d.begin(), d.end(),
                      "corner texture coordinates of 4 loose faces (they decode as zeros)"),
            d.end())
      << ::testing::PrintToString(d);
  // Without loose faces nothing is said.
  PolygonSoup clean = wavy_grid(4, 0.1);
  clean.corner_texcoords.assign(clean.face_indices.size(), TexCoord(0.25, 0.5));
  EXPECT_TRUE(compress(clean).stats.dropped_properties.empty());
}

TEST(CompressFidelity, PreservedOrderGivesTheSoupBack) {
  const PolygonSoup in = grid_with_bad_faces();
  const PolygonSoup out = round_trip(in, {.preserve_order = true});
  EXPECT_EQ(faces_of(out), faces_of(in));
  ASSERT_EQ(out.positions.size(), in.positions.size());
  for (std::size_t v = 0; v < in.positions.size(); ++v)
    EXPECT_LT((out.positions[v] - in.positions[v]).norm(), 1e-2);
}

TEST(CompressFidelity, OutOfRangeFacesAreCountedNotStored) {
  PolygonSoup in = wavy_grid(3, 0.2);
  in.add_face({0, 1, 99});
  const CompressResult r = compress(in);
  EXPECT_EQ(r.stats.unstorable_faces, 1u);
  EXPECT_EQ(to_soup(decompress(r.bytes)).n_faces(), in.n_faces() - 1);
}

TEST(CompressFidelity, NonPlanarQuadsKeepTheirFirstCornerAndSurface) {
  const PolygonSoup in = wavy_grid(40, 2.0);
  const SurfaceMesh mesh = build(in).mesh;
  const CompressOptions o{.bits = 14};
  const CompressResult r = compress(mesh, o);
  EXPECT_GT(r.stats.rotation_bytes, 0u);
  const DecompressResult d = decompress(r.bytes);
  // Every decoded face starts at its input face's first corner.
  const PolygonSoup out = to_soup(d);
  for (std::size_t f = 0; f < out.n_faces(); ++f) {
    const auto input = in.face(r.face_permutation[f]);
    EXPECT_EQ(r.vertex_permutation[out.face(f)[0]], input[0]) << "face " << f;
  }
  const double step = r.stats.step;
  const MeshDistance kept = mesh_distance(mesh, d.mesh);
  EXPECT_LT(kept.hausdorff, 4 * step);
  // The old stream (any first corner) moves the surface by far more than the grid.
  const DecompressResult old = decompress(compress(mesh, {.bits = 14, .keep_corner_order = false}).bytes);
  EXPECT_GT(mesh_distance(mesh, old.mesh).hausdorff, 100 * step);
}

TEST(CompressFidelity, TriangleCornersOnRequest) {
  PolygonSoup in;
  const PolygonSoup grid = wavy_grid(10, 1.0);
  in.positions = grid.positions;
  for (std::size_t f = 0; f < grid.n_faces(); ++f) {
    const auto q = grid.face(f);
    in.add_face({q[(f % 3)], q[(f % 3 + 1) % 4], q[(f % 3 + 2) % 4]});
    in.add_face({q[(f % 3 + 2) % 4], q[(f % 3 + 3) % 4], q[(f % 3)]});
  }
  const PolygonSoup out = round_trip(in, {.keep_triangle_corners = true});
  const auto m = match_vertices(in, out);
  EXPECT_EQ(sorted(faces_of(out, m)), sorted(faces_of(in)));
}

TEST(CompressFidelity, AnyCornerOrderWritesNoRotations) {
  const PolygonSoup in = wavy_grid(10, 1.0);
  const CompressResult r = compress(in, {.keep_corner_order = false});
  EXPECT_EQ(r.stats.rotation_bytes, 0u);
  EXPECT_LT(r.bytes.size(), compress(in).bytes.size());
}

TEST(CompressFidelity, CorruptLooseFacesAreRefused) {
  const CompressResult r = compress(grid_with_bad_faces());
  std::size_t refused = 0;
  // Each byte of the loose face entry (at the end of the stream) changed in turn.
  for (std::size_t i = r.bytes.size() - r.stats.loose_face_bytes; i < r.bytes.size(); ++i) {
    std::vector<std::uint8_t> b = r.bytes;
    b[i] ^= 0x7f;
    try {
      const DecompressResult d = decompress(b);
      for (const auto& f : d.loose_faces)
        for (std::uint32_t v : f) ASSERT_LT(v, d.mesh.n_vertices());
    } catch (const DecodeError&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, 0u);
}

TEST(CompressFidelity, CorruptRotationDegreeIsRefused) {
  const CompressResult r = compress(wavy_grid(10, 1.0));
  ASSERT_GT(r.stats.rotation_bytes, 0u);
  std::vector<std::uint8_t> b = r.bytes;
  const std::size_t at = b.size() - r.stats.rotation_bytes;  // the last entry: kind, degree
  ASSERT_EQ(b[at], 4);
  b[at + 1] = 5;
  EXPECT_THROW(decompress(b), DecodeError);
}

TEST(CompressFidelity, DamagedRotationsNeverCrash) {
  // Quads and pentagons, so that every rotation model is used.
  PolygonSoup in = wavy_grid(8, 1.0);
  in.positions.push_back({20, 0, 0});
  in.positions.push_back({21, 0, 0});
  in.positions.push_back({21.5, 1, 0});
  in.positions.push_back({21, 2, 0.5});
  in.positions.push_back({20, 2, 0});
  in.add_face({81, 82, 83, 84, 85});
  const CompressResult r = compress(in, {.keep_triangle_corners = true});
  ASSERT_GT(r.stats.rotation_bytes, 0u);
  std::size_t refused = 0;
  for (std::size_t i = r.bytes.size() - r.stats.rotation_bytes; i < r.bytes.size(); ++i)
    for (std::uint8_t flip : {0x01, 0x10, 0xff}) {
      std::vector<std::uint8_t> b = r.bytes;
      b[i] ^= flip;
      try {
        decompress(b);
      } catch (const DecodeError&) {
        ++refused;
      }
    }
  EXPECT_GT(refused, 0u);
}

TEST(CompressFidelity, LooseFacesBeyondTheVerticesThrow) {
  const SurfaceMesh m = build(wavy_grid(3, 0.2)).mesh;
  EXPECT_THROW(compress(m, {.loose_faces = {{0, 1, 16}}}), InvalidArgument);
  EXPECT_THROW(compress(m, {.preserve_order = true, .loose_faces = {{0, 0, 1}},
                            .loose_face_positions = {20}}),
               InvalidArgument);
  // Without positions, preserved order puts them after the mesh's faces.
  const DecompressResult d = decompress(compress(m, {.preserve_order = true, .loose_faces = {{0, 0, 1}}}).bytes);
  EXPECT_EQ(d.loose_face_positions, std::vector<std::uint32_t>{9});
  EXPECT_EQ(d.loose_faces, (Faces{{0, 0, 1}}));
}

// The real meshes: every face comes back; with the order preserved exactly as given, and by
// default (mesh faces matched through the permutations) each polygon from its first corner.
void expect_faces_kept(const std::filesystem::path& path) {
  SCOPED_TRACE(path.string());
  const PolygonSoup in = read_soup(path.string());
  const PolygonSoup exact = round_trip(in, {.bits = 16, .preserve_order = true});
  EXPECT_EQ(faces_of(exact), faces_of(in));
  const CompressResult r = compress(in, {.bits = 16});
  const DecompressResult d = decompress(r.bytes);
  const PolygonSoup out = to_soup(d);
  ASSERT_EQ(out.n_faces(), in.n_faces() - r.stats.unstorable_faces);
  ASSERT_EQ(out.positions.size(), in.positions.size());
  if (r.stats.split_copies + r.stats.loose_faces + r.stats.unstorable_faces > 0) return;
  // Nothing split or loose: the built mesh is the soup, and the permutations map onto it.
  const PolygonSoup decoded = to_soup(d.mesh);
  Faces got, want;
  for (std::size_t f = 0; f < decoded.n_faces(); ++f) {
    got.emplace_back();
    for (std::uint32_t v : decoded.face(f)) got.back().push_back(r.vertex_permutation[v]);
    const auto c = in.face(r.face_permutation[f]);
    want.emplace_back(c.begin(), c.end());
  }
  EXPECT_EQ(rotate_triangles(got), rotate_triangles(want));
}

TEST(CompressFidelity, RealMeshesKeepEveryFaceAndFirstCorner) {
  GEOM_REQUIRE_DATA_DIR(dir);
  for (const char* name : {"spot_quadrangulated.obj", "fandisk_quads.off", "horse_quad.obj",
                           "suzanne.obj", "cylinder.obj", "beast.obj", "teapot.obj",
                           "opensubdiv/catmark_nonquads.obj", "fandisk.off"})
    if (std::filesystem::exists(dir / name)) expect_faces_kept(dir / name);
}

// The corpus beside the meshes (MANIFEST.md there): files whose faces build() drops or
// changes. The "10,200-face CAD mesh" is not among them; AnisotropyBarnLamp (10,203
// triangles, 207 parts) is the one of that size, and Lantern (174 zero-area faces of 5,394),
// DuplicateMeshes (1,344 duplicates of 1,568) and VC (30 duplicates) lose faces to build().
TEST(CompressFidelity, CorpusFilesKeepEveryFace) {
  GEOM_REQUIRE_DATA_DIR(dir);
  const std::filesystem::path corpus = dir.parent_path() / "corpus";
  if (!std::filesystem::is_directory(corpus)) GTEST_SKIP() << "no corpus beside " << dir;
  const std::pair<const char*, std::size_t> files[] = {
      {"gltf-samples/Models/AnisotropyBarnLamp/glTF/AnisotropyBarnLamp.gltf", 10203},
      {"gltf-samples/Models/Lantern/glTF-Draco/Lantern.gltf", 5394},
      {"draco/testdata/DuplicateMeshes/duplicate_meshes.gltf", 1568},
      {"gltf-samples/Models/VC/glTF/VC.gltf", 8383},
      {"draco/testdata/deg_faces.obj", 4}};
  for (const auto& [name, faces] : files) {
    if (!std::filesystem::exists(corpus / name)) continue;
    SCOPED_TRACE(name);
    const PolygonSoup in = read_soup(corpus / name);
    ASSERT_EQ(in.n_faces(), faces);
    const CompressResult r = compress(in);
    EXPECT_EQ(r.stats.unstorable_faces, 0u);
    EXPECT_EQ(to_soup(decompress(r.bytes)).n_faces(), faces);
    expect_faces_kept(corpus / name);
  }
}

}  // namespace
}  // namespace geom
