#pragma once
/// \file
/// Position prediction and residual coding on the decoded corner table. Vertices are coded
/// in decoding order; a vertex is predicted only from vertices before it, so the decoder can
/// run the same predictor once connectivity is known.
///
/// Ref: C. Touma, C. Gotsman, "Triangle mesh compression", Graphics Interface 1998
/// (parallelogram rule). M. Isenburg, P. Alliez, "Compressing polygon mesh geometry with
/// parallelogram prediction", IEEE Visualization 2002. Draco's constrained
/// multi-parallelogram predictor (averaging every available parallelogram).

#include <geom/compress/connectivity.h>

#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace geom::codec::detail {

enum class Predictor : std::uint8_t {
  kDelta = 0,               ///< the latest decoded neighbour
  kParallelogram = 1,       ///< the first complete parallelogram
  kMultiParallelogram = 2,  ///< the rounded mean of every complete parallelogram
  /// Multi-parallelogram with vertices renumbered by degree_order(): each vertex is coded
  /// when the most triangles around it are complete, so more parallelograms are averaged.
  kMultiParallelogramDegree = 3,
  /// kMultiParallelogramDegree with the prediction pulled towards the centroid of the
  /// parallelograms' shared edges by per-stream weights (Blend; zero weights: no pull): on
  /// an irregular or curved scan a parallelogram overshoots across uneven triangles, and
  /// the edge midpoints undershoot. Residual lengths use a bits + 2 symbol alphabet.
  kMultiParallelogramBlend = 4,
  /// kMultiParallelogramBlend where a vertex with two or more parallelograms also codes
  /// which of its first kMaxSelect parallelograms the prediction averages (a nonempty
  /// subset, chosen by the encoder for the cheapest residuals): on a noisy scan one of two
  /// parallelograms is often much closer than their mean, and the choice costs about a bit.
  kMultiParallelogramSelect = 5,
  /// kMultiParallelogramBlend in *growth order* instead of the degree order: vertices keep
  /// the connectivity's numbering and are coded while the decoded triangles are walked in
  /// decode order, each once two parallelograms predict it or its deadline (a stream's
  /// power of two of triangles after its birth) has passed (FORMAT.md). Nothing is
  /// renumbered, but the walk costs more instructions than the whole degree pass, so it
  /// decodes a few per cent slower (even fused into the connectivity decoder: measured).
  kGrowthBlend = 6,
  /// kMultiParallelogramSelect in growth order.
  kGrowthSelect = 7,
};

/// How many parallelograms (the first, in corner order) kMultiParallelogramSelect chooses
/// among; later ones are not used.
inline constexpr unsigned kMaxSelect = 4;

/// The pull of kMultiParallelogramBlend, in sixteenths, for vertices with one parallelogram
/// and with several. Stored as one byte: one | many << 4.
struct Blend {
  std::uint8_t one = 0, many = 0;
  bool any() const { return one != 0 || many != 0; }
  std::uint8_t byte() const { return static_cast<std::uint8_t>(one | (many << 4)); }
  static Blend from_byte(std::uint8_t b) { return {static_cast<std::uint8_t>(b & 15), static_cast<std::uint8_t>(b >> 4)}; }
};

/// Renumber the table's vertices in "most complete triangles first" order (a greedy
/// traversal with bucket queues; deterministic, so the decoder repeats it). Returns the
/// old vertex of each new vertex. Complexity: O(V + T). The reference definition of the
/// order (FORMAT.md); the codec runs the fused encode/decode_positions_degree passes, which
/// tests hold to this one.
/// Ref: Draco's MaxPredictionDegreeTraverser (prediction-degree driven attribute order).
std::vector<std::uint32_t> degree_order(CornerTable& table);

using QPoint = std::array<std::uint32_t, 3>;

/// Code q (decoding order; the first table.n_vertices are the table's vertices, the rest
/// are isolated vertices) on a grid of `bits` bits.
/// Pre: every q component < 2^bits; q.size() ≥ table.n_vertices.
/// Complexity: O(V + T).
void encode_positions(const CornerTable& table, std::span<const QPoint> q, unsigned bits,
                      Predictor predictor, RansEncoder& rans, BitWriter& raw);

/// Most predictors encode_positions_each codes in one pass.
inline constexpr std::size_t kMaxEach = 4;

/// encode_positions for several predictors in one pass over the table (the level search
/// tries them all on one traversal; the corner scan is shared): rans[i] and raw[i] receive
/// exactly what encode_positions(table, q, bits, predictors[i], ...) would code.
/// Pre: as encode_positions; rans and raw hold one coder per predictor, at most kMaxEach.
/// Throws: InvalidArgument when they do not. Complexity: O(V + T) per predictor.
void encode_positions_each(const CornerTable& table, std::span<const QPoint> q, unsigned bits,
                           std::span<const Predictor> predictors, std::span<RansEncoder> rans,
                           std::span<BitWriter> raw);

/// Decode n positions. Throws: DecodeError on truncated data or a value off the grid.
/// Complexity: O(V + T).
void decode_positions(const CornerTable& table, std::size_t n, unsigned bits, Predictor predictor,
                      RansDecoder& rans, BitReader& raw, std::vector<QPoint>& q);

/// Decode n positions of a kMultiParallelogramDegree stream in one pass: the degree-order
/// traversal takes a vertex and decodes it at once, so nothing is renumbered twice. Same
/// result as degree_order(table) followed by decode_positions (table renumbered, q in the new
/// order); returns the old vertex of each new vertex.
/// Throws: DecodeError as decode_positions. Complexity: O(V + T).
/// kMultiParallelogramBlend's prediction on one axis from `count` parallelograms a + b − c
/// summing to s, whose edge ends a + b sum to e: (16 − k)/16 of their mean s/count plus k/16
/// of the ends' centroid e/(2·count), i.e. floor((2N + D) / 2D) with N = 2(16 − k)·s + k·e
/// and D = 32·count, clamped to [0, top]. Exact. Pre: count > 0, k < 16.
std::uint32_t blended_mean_wide(std::int64_t s, std::int64_t e, unsigned count, unsigned k,
                                std::uint32_t top);  // in 128 bits, for counts ≥ 2^24
inline std::uint32_t blended_mean(std::int64_t s, std::int64_t e, unsigned count, unsigned k,
                                  std::uint32_t top) {
  if (count >= (1u << 24)) [[unlikely]] return blended_mean_wide(s, e, count, k, top);
  // |s| < count·2^31 and 0 ≤ e < count·2^31, so 2·num + den stays below 2^62. Inline, and
  // floor(x / 64c) taken as floor(floor(x / 64) / c): a shift, then a division only by the
  // count (none for one or two parallelograms, the common cases), once per axis and vertex.
  const std::int64_t num = 2 * std::int64_t(16 - k) * s + std::int64_t(k) * e;
  const std::int64_t x = (2 * num + 32 * std::int64_t{count}) >> 6;  // arithmetic: floor
  std::int64_t m = x;
  if (count == 2) {
    m = x >> 1;
  } else if (count > 2) {
    m = x / count;
    if (m * count > x) --m;  // truncated towards zero: floor for negative x
  }
  return static_cast<std::uint32_t>(m < 0 ? 0 : (m > top ? top : m));
}

/// predictor is kMultiParallelogramDegree, kMultiParallelogramBlend (whose predictions
/// with parallelograms are pulled towards their edges' centroid by `blend`; FORMAT.md) or
/// kMultiParallelogramSelect (the same, over a coded subset of the parallelograms).
/// With kMultiParallelogramSelect and anchor_isolated, the isolated vertices are predicted
/// from anchors (FORMAT.md) and the result also lists them (n entries, identity past the
/// connected ones). The traversal's per-corner and per-vertex records live in `scratch` (a
/// block of its own when null), dead on return. open_corners, when given, receives the
/// corners without an opposite in ascending order (the pass reads every opposite anyway;
/// the chunk merge needs the boundary).
/// Throws: DecodeError also for an anchor beyond the connected vertices.
std::vector<std::uint32_t> decode_positions_degree(
    CornerTable& table, std::size_t n, unsigned bits, RansDecoder& rans, BitReader& raw,
    std::vector<QPoint>& q, Predictor predictor = Predictor::kMultiParallelogramDegree,
    Blend blend = {}, bool anchor_isolated = false, Scratch* scratch = nullptr,
    std::vector<std::uint32_t>* open_corners = nullptr);

/// The scratch bytes decode_positions_degree uses for a table of n_corners corners and
/// n_vertices connected vertices.
std::size_t degree_scratch_bytes(std::size_t n_corners, std::size_t n_vertices);

/// What encode_positions_degree's traversal saw, kept so that the same traversal can be
/// coded again with other blend weights without being repeated (the order and the
/// parallelogram sums do not depend on the weights; only the residuals do).
struct DegreePlan {
  struct Step {
    std::int64_t sum[3], ends[3];  // parallelogram sums and their shared edges' ends
    std::uint32_t count;           // parallelograms
    std::uint32_t fallback;        // without any: position of the predicting vertex, or kNone
    std::uint32_t act_begin;       // this step's entries in act
  };
  std::vector<Step> steps;         // one per table vertex, in traversal order
  std::vector<std::uint32_t> act;  // traversal positions of each step's taken wedge ends
  std::vector<std::uint32_t> seq;  // traversal position → old vertex
  std::vector<QPoint> q;           // grid points in traversal order, isolated vertices last
};

/// The encoder's side of decode_positions_degree: q in the table's numbering (isolated
/// vertices last); renumbers the table and returns the old vertex of each new vertex (the
/// degree_order result), coding exactly what degree_order + encode_positions would.
/// With `suggest` (and zero blend weights), also measures every weight on the way and
/// stores the ones that would have given the shortest residuals (zero: pulling would not
/// help), so a second pass can code with them. With kMultiParallelogramSelect and
/// anchor_isolated (Pre: the table has a vertex), each isolated vertex is predicted from its
/// nearest connected vertex and they are coded in anchor order: the result then has
/// q.size() entries, the isolated vertices' indices in q following the connected ones.
/// With `plan` (predictor 4 only), records the traversal for encode_positions_degree_again.
std::vector<std::uint32_t> encode_positions_degree(
    CornerTable& table, std::span<const QPoint> q, unsigned bits, RansEncoder& rans, BitWriter& raw,
    Predictor predictor = Predictor::kMultiParallelogramDegree, Blend blend = {},
    Blend* suggest = nullptr, bool anchor_isolated = false, DegreePlan* plan = nullptr);

/// encode_positions_degree on the table and points the plan was recorded from (table in
/// their original numbering), without the traversal: renumbers the table, codes exactly
/// the same stream, and returns plan.seq. Complexity: O(V + T).
std::vector<std::uint32_t> encode_positions_degree_again(CornerTable& table, const DegreePlan& plan,
                                                         unsigned bits, RansEncoder& rans,
                                                         BitWriter& raw, Predictor predictor,
                                                         Blend blend);

/// The deadlines (log2 of triangles) compress() chooses among for predictors 6 and 7
/// (meshes under 2^15 vertices also try 2^10, 2^8 and 2^6); a decoder accepts any of
/// 0 … kMaxLog2Deadline.
inline constexpr unsigned kLog2Deadlines[2] = {12, 14};
inline constexpr unsigned kMaxLog2Deadline = 31;

/// Decode n positions of a kGrowthBlend or kGrowthSelect stream (FORMAT.md) into q, in the
/// table's numbering (isolated vertices last; with kGrowthSelect and anchor_isolated, from
/// their anchors). The pass's per-corner and per-vertex arrays live in `scratch` (a block of
/// its own when null), dead on return.
/// Throws: DecodeError on truncated data, a value off the grid or an anchor beyond the
/// connected vertices. Complexity: O(V + T), each corner list walked once; memory
/// 8 bytes per corner and 32 per vertex (each vertex enters the worklist at most twice).
/// It decodes a few per cent slower than the degree order (predict_growth.cpp).
void decode_positions_growth(const CornerTable& table, std::size_t n, unsigned bits,
                             RansDecoder& rans, BitReader& raw, std::vector<QPoint>& q,
                             Predictor predictor, Blend blend, bool anchor_isolated,
                             unsigned log2_deadline, Scratch* scratch = nullptr);

/// The scratch bytes decode_positions_growth uses.
std::size_t growth_scratch_bytes(std::size_t n_corners, std::size_t n_vertices);

/// The encoder's side of decode_positions_growth (q in the table's numbering, isolated
/// vertices last). With kGrowthSelect and anchor_isolated (and a connected vertex), the
/// isolated vertices are coded from their nearest connected vertex in anchor order and the
/// result lists the coded vertex of each stream position (q.size() entries, the identity
/// over the connected ones); otherwise it is empty (the identity). compress() chooses the
/// weights and deadline by the streams' sizes. Complexity: O(V + T).
std::vector<std::uint32_t> encode_positions_growth(const CornerTable& table,
                                                   std::span<const QPoint> q, unsigned bits,
                                                   RansEncoder& rans, BitWriter& raw,
                                                   Predictor predictor, Blend blend = {},
                                                   bool anchor_isolated = false,
                                                   unsigned log2_deadline = kLog2Deadlines[1]);

}  // namespace geom::codec::detail
