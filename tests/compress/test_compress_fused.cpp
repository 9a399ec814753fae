// The fused degree-order passes (encode_positions_degree / decode_positions_degree) against
// the format's reference definition, degree_order() followed by encode_positions /
// decode_positions: same vertex order, same renumbered table, byte-identical streams. The
// fused passes are a speed-up only; streams of earlier encoders must keep decoding.

#include "compress/meshes.h"

#include <geom/compress/container/mesh_tables.h>
#include <geom/compress/predict.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace geom::codec::detail {
namespace {

struct Coded {
  std::vector<std::uint8_t> rans, raw;
};

void expect_fused_matches_reference(const test::Arrays& arrays, unsigned bits, unsigned seed) {
  const FlatMesh flat = flatten(arrays.build());
  RansEncoder conn_rans;
  BitWriter conn_raw;
  CornerTable table;
  TraversalOrder order;
  encode_connectivity(flat.table, flat.polygons, Traversal::kLeftFirst, conn_rans, conn_raw, table,
                      order);
  // The connectivity coder counts each vertex's corners for the degree pass.
  std::vector<std::uint32_t> counted(table.n_vertices, 0);
  for (std::uint32_t v : table.vertex) ++counted[v];
  EXPECT_TRUE(std::ranges::equal(table.corners_of, counted));
  // Random grid points (isolated vertices past the table's): residuals of every sign and
  // length, predictions clamped at both grid ends.
  std::mt19937 rng(seed);
  const std::uint32_t top = (1u << bits) - 1;
  std::vector<QPoint> q(table.n_vertices + 3);
  for (QPoint& p : q)
    for (auto& x : p) x = rng() % 4 == 0 ? (rng() % 2 ? top : 0) : rng() % (top + 1);

  CornerTable ref_table = table;
  const std::vector<std::uint32_t> ref_seq = degree_order(ref_table);
  std::vector<QPoint> ref_q = q;
  for (std::size_t i = 0; i < ref_seq.size(); ++i) ref_q[i] = q[ref_seq[i]];
  RansEncoder ref_re;
  BitWriter ref_bw;
  encode_positions(ref_table, ref_q, bits, Predictor::kMultiParallelogramDegree, ref_re, ref_bw);
  const Coded ref{ref_re.finish(), ref_bw.finish()};

  CornerTable fused_table = table;
  RansEncoder re;
  BitWriter bw;
  const std::vector<std::uint32_t> seq = encode_positions_degree(fused_table, q, bits, re, bw);
  const Coded fused{re.finish(), bw.finish()};
  EXPECT_EQ(seq, ref_seq);
  EXPECT_EQ(fused_table.vertex, ref_table.vertex);
  EXPECT_EQ(fused.rans, ref.rans);
  EXPECT_EQ(fused.raw, ref.raw);

  // The decoder gives the reference's order and points, whatever corner counts the table
  // carries: the connectivity coder's, none (a table from elsewhere), or counts that do not
  // add up to the corners (the pass then counts for itself). It also lists the corners
  // without an opposite (the chunk merge's boundary), replacing what the list held.
  std::vector<std::uint32_t> open_scanned;
  for (std::uint32_t c = 0; c < table.opposite.size(); ++c)
    if (table.opposite[c] == kNone) open_scanned.push_back(c);
  auto expect_decodes = [&](CornerTable dec_table) {
    RansDecoder rd(ref.rans, 0);
    BitReader br(ref.raw, 0);
    std::vector<QPoint> decoded;
    std::vector<std::uint32_t> open = {7, 7};
    EXPECT_EQ(decode_positions_degree(dec_table, q.size(), bits, rd, br, decoded,
                                      Predictor::kMultiParallelogramDegree, {}, false, nullptr,
                                      &open),
              ref_seq);
    rd.finish();
    EXPECT_EQ(dec_table.vertex, ref_table.vertex);
    EXPECT_EQ(decoded, ref_q);
    EXPECT_EQ(open, open_scanned);
    EXPECT_TRUE(dec_table.corners_of.empty());  // renumbered: no longer valid
  };
  expect_decodes(table);
  for (const bool stale : {false, true}) {
    CornerTable again = table;
    again.corners_of.assign(stale ? table.n_vertices : 0, 1);
    expect_decodes(std::move(again));
  }
}

TEST(CompressFused, DegreeOrderPassesMatchTheReference) {
  expect_fused_matches_reference(test::torus(30, 20).shuffled(1), 11, 1);
  expect_fused_matches_reference(test::holey_slab(3, true).shuffled(2), 14, 2);
  expect_fused_matches_reference(test::grid(9, 7, true), 3, 3);  // quads, fanned; a boundary
  expect_fused_matches_reference(test::mixed_polygons(), 20, 4);
}

}  // namespace
}  // namespace geom::codec::detail
