#pragma once
// The codec's round-trip check, shared by the codec's test files.

#include <geom/compress/container/codec.h>
#include <geom/core/validate.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace geom::test {

inline std::vector<std::vector<std::uint32_t>> faces_of(const SurfaceMesh& m) {
  std::vector<std::uint32_t> dense(m.vertices_size(), 0);
  std::uint32_t n = 0;
  for (Vertex v : m.vertices()) dense[v.idx()] = n++;
  std::vector<std::vector<std::uint32_t>> out;
  for (Face f : m.faces()) {
    out.emplace_back();
    for (Vertex v : m.vertices(f)) out.back().push_back(dense[v.idx()]);
  }
  return out;
}

inline std::vector<Point> points_of(const SurfaceMesh& m) {
  std::vector<Point> out;
  for (Vertex v : m.vertices()) out.push_back(m.position(v));
  return out;
}

inline std::vector<std::uint32_t> canonical(std::vector<std::uint32_t> f) {
  std::rotate(f.begin(), std::min_element(f.begin(), f.end()), f.end());
  return f;
}

/// Decoded mesh equals the input up to the encoder's permutations (cyclic corner rotation
/// allowed), positions within the bound. With exact_order, rotations must match too.
inline void expect_round_trip(const SurfaceMesh& in, const CompressOptions& opt, bool exact_order) {
  const CompressResult c = compress(in, opt);
  EXPECT_LE(c.bytes.size(), max_compressed_size(in.n_vertices(), in.n_faces(), [&] {
              std::size_t k = 0;
              for (Face f : in.faces()) k += in.valence(f);
              return k;
            }()));
  const DecompressResult d = decompress(c.bytes);
  ASSERT_TRUE(validate(d.mesh).ok());
  ASSERT_EQ(d.mesh.n_vertices(), in.n_vertices());
  ASSERT_EQ(d.mesh.n_faces(), in.n_faces());
  ASSERT_EQ(c.vertex_permutation.size(), in.n_vertices());
  ASSERT_EQ(c.face_permutation.size(), in.n_faces());
  const auto fin = faces_of(in), fout = faces_of(d.mesh);
  const auto pin = points_of(in), pout = points_of(d.mesh);
  const auto& vp = c.vertex_permutation;
  for (std::size_t j = 0; j < fout.size(); ++j) {
    std::vector<std::uint32_t> mapped;
    for (auto v : fout[j]) mapped.push_back(vp[v]);
    const auto& orig = fin[c.face_permutation[j]];
    if (exact_order) ASSERT_EQ(mapped, orig) << "face " << j;
    else ASSERT_EQ(canonical(mapped), canonical(orig)) << "face " << j;
  }
  const double tol = c.stats.max_error * (1 + 1e-9) + 1e-12;
  EXPECT_DOUBLE_EQ(d.max_error, c.stats.max_error);
  for (std::size_t i = 0; i < pout.size(); ++i)
    for (int a = 0; a < 3; ++a)
      ASSERT_LE(std::abs(pout[i][a] - pin[vp[i]][a]), tol + 1e-15 * std::abs(pin[vp[i]][a]))
          << "vertex " << i;
  if (opt.preserve_order) {
    EXPECT_TRUE(d.order_preserved);
    for (std::uint32_t i = 0; i < vp.size(); ++i) ASSERT_EQ(vp[i], i);
  }
}

}  // namespace geom::test
