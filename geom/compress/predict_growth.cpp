// The growth-order pass (predictors 6 and 7): positions are coded in the connectivity's own
// numbering while the decoded triangles are walked in decode order, a vertex as soon as two
// parallelograms predict it (or its deadline passes). One template serves the decoder and
// the encoder, so both walk the same order by construction. FORMAT.md defines the order.
// Measured on the 1M-triangle scan of bench_compress: the walk takes ~565 M instructions
// (~640 per vertex: every decoded corner of the vertex is visited, with the neighbours'
// bookkeeping) against ~315 M for the whole degree pass. Running it inside the connectivity
// decoder, triangle by triangle, was tried: it saves the second traversal (~0.5% of the
// decode) but keeps both working sets live, and still decodes 4-7% slower than the degree
// order, so the codec runs it as a pass of its own.

#include <geom/compress/point_chain.h>
#include <geom/compress/predict.h>
#include <geom/compress/residuals.h>

#include <geom/core/huge_pages.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <vector>

namespace geom::codec::detail {

namespace {

/// Per corner: the next older corner of its vertex (kNone: none), and the vertex across
/// its edge once the triangle there is decoded (kNone until then, and on a boundary). The
/// pass reads both for the triangles around the vertex it codes, which are recent, so it
/// never reaches back to an old triangle's corners except when zipping.
struct CornerRec {
  std::uint32_t link, across;
};

/// Per vertex: its grid point and state (pending: its complete parallelograms, 0–2,
/// saturated; coded: 0x80 | its residual length), in one record, since the walk asks for
/// both of the same neighbours.
struct VertexRec {
  std::uint32_t q[3];
  std::uint32_t state;
};

/// Where the pass keeps its arrays in the scratch block: a CornerRec per corner, then a
/// VertexRec, a list head and a birth triangle per vertex.
struct GrowthLayout {
  std::size_t vertex, head, birth, end;
  GrowthLayout(std::size_t n_corners, std::size_t n_vertices) {
    vertex = (n_corners * sizeof(CornerRec) + 15) / 16 * 16;
    head = vertex + n_vertices * sizeof(VertexRec);
    birth = head + n_vertices * 4;
    end = birth + n_vertices * 4;
  }
};

/// What a vertex's decoded corners tell about it at the current triangle.
struct Gathered {
  std::int64_t sum[3] = {0, 0, 0}, ends[3] = {0, 0, 0};
  std::int64_t cand[kMaxSelect][3], cand_ends[kMaxSelect][3];  // predictor 7: the first ones
  unsigned count = 0, act_sum = 0, act_n = 0;
  std::uint32_t neighbour = kNone;  // the first coded neighbour met
};

/// The growth-order walk (FORMAT.md, Geometry). A vertex's state counts its complete
/// parallelograms while it is pending (saturated at 2, when it is queued) and holds
/// 0x80 | its residual length once coded. A parallelogram is counted when its last piece
/// arrives: the zip that decodes the triangle across, or the coding of one of its vertices.
template <bool kSelect, class Coder>
class GrowthPass {
 public:
  GrowthPass(const CornerTable& t, Coder& coder, std::vector<QPoint>& q, Blend blend,
             unsigned log2_deadline, Scratch& scratch)
      : vx_(t.vertex.data()), op_(t.opposite.data()), coder_(coder), out_(q.data()), blend_(blend),
        deadline_(std::uint64_t{1} << log2_deadline),
        nt_(static_cast<std::uint32_t>(t.n_triangles())), nc_(t.n_vertices) {
    const GrowthLayout at(t.vertex.size(), nc_);
    scratch.reserve(at.end);
    corner_ = scratch.array<CornerRec>(0, t.vertex.size());  // written before read
    head_ = scratch.array<std::uint32_t>(at.head, nc_);
    birth_ = scratch.array<std::uint32_t>(at.birth, nc_);  // written before read
    v_ = scratch.array<VertexRec>(at.vertex, nc_);
    std::fill_n(head_, nc_, kNone);
    std::fill_n(v_, nc_, VertexRec{{0, 0, 0}, 0});
    // Each vertex enters the worklist at most twice (on its second parallelogram and at its
    // deadline), so it never needs more room: pushes are then unconditional stores.
    work_.reset(new std::uint32_t[2 * std::size_t{nc_} + 1]);
  }

  /// Codes every connected vertex; returns the last residual length (isolated vertices
  /// continue from it).
  unsigned run() {
    std::uint32_t born = 0, cursor = 0;
    for (std::uint32_t T = 0; T < nt_; ++T) {
      const std::uint32_t c0 = 3 * T;
      bool seed = true;
      for (std::uint32_t c = c0; c < c0 + 3; ++c) {
        const std::uint32_t v = vx_[c];
        // Vertices are numbered by first appearance, so a new one is `born`.
        if (v >= born) {
          while (born <= v) birth_[born++] = T;
        } else {
          seed = false;
        }
        corner_[c] = {head_[v], kNone};
        head_[v] = c;
      }
      // A seed triangle's vertices start a component: nothing else would ever predict them.
      if (seed)
        for (std::uint32_t c = c0; c < c0 + 3; ++c)
          if (!coded(vx_[c])) code(vx_[c]);
      while (cursor < born && std::uint64_t{birth_[cursor]} + deadline_ <= T) {
        work_[wn_] = cursor;
        wn_ += !coded(cursor);
        ++cursor;
      }
      // Each zip of T with an earlier triangle makes a parallelogram on either side; the
      // edge's ends are the same two vertices on both.
      for (std::uint32_t c = c0; c < c0 + 3; ++c) {
        const std::uint32_t o = op_[c];
        if (o == kNone || o >= c0) continue;
        const std::uint32_t vc = vx_[c], vo = vx_[o];
        corner_[c].across = vo;
        corner_[o].across = vc;
        if (!coded(vx_[next_corner(c)]) || !coded(vx_[prev_corner(c)])) continue;
        const bool dc = coded(vc), dv = coded(vo);
        if (dv) bump(vc);
        if (dc) bump(vo);
      }
      cascade();
    }
    // What the deadline left (meshes smaller than it, mostly): everything is known now.
    for (std::uint32_t v = 0; v < nc_; ++v)
      if (!coded(v)) code(v);
    for (std::uint32_t v = 0; v < nc_; ++v) out_[v] = {v_[v].q[0], v_[v].q[1], v_[v].q[2]};
    return last_rlen_;
  }

 private:
  bool coded(std::uint32_t x) const { return v_[x].state >= 0x80; }

  /// One more complete parallelogram for u if pending, which queues u when it makes two.
  void bump(std::uint32_t u) {
    std::uint32_t& su = v_[u].state;
    if (su >= 2) return;  // coded (≥ 0x80), or queued already
    work_[wn_] = u;
    if (++su == 2) {
      ++wn_;
      // u is coded soon: start loading its newest triangle.
      const std::uint32_t h = head_[u];
      __builtin_prefetch(corner_ + h);
      __builtin_prefetch(vx_ + h);
    }
  }

  /// Codes the queued vertices in FIFO order until none is left (coding one may queue more).
  void cascade() {
    for (std::size_t i = 0; i < wn_; ++i)
      if (!coded(work_[i])) code(work_[i]);
    wn_ = 0;
  }

  /// Codes x from its decoded corners, walked newest first. The same walk gathers the
  /// prediction (x's complete parallelograms a + b − c: a, b, c coded and c's triangle
  /// decoded; the coded neighbours' residual lengths; the first coded neighbour) and, x
  /// counting as coded from its start, completes the parallelograms x was the last missing
  /// vertex of: those at the other two corners of each triangle (x an edge end) and at the
  /// opposite corner (x the vertex across).
  void code(std::uint32_t x) {
    v_[x].state = 0x80;
    Gathered g;
    for (std::uint32_t k = head_[x]; k != kNone; k = corner_[k].link) {
      const std::uint32_t n = next_corner(k), p = prev_corner(k);
      const std::uint32_t a = vx_[n], b = vx_[p];
      const VertexRec& ra = v_[a];
      const VertexRec& rb = v_[b];
      const std::uint32_t sa = ra.state, sb = rb.state;
      const bool da = sa >= 0x80, db = sb >= 0x80;
      g.act_sum += (da ? sa & 0x3fu : 0u) + (db ? sb & 0x3fu : 0u);
      g.act_n += unsigned{da} + unsigned{db};
      g.neighbour = g.neighbour == kNone && (da || db) ? (da ? a : b) : g.neighbour;
      // a's parallelogram at n (edge x, b) and b's at p (edge a, x), if their vertex across
      // is known and coded.
      if (db && !da) {
        const std::uint32_t cn = corner_[n].across;
        if (cn != kNone && coded(cn)) bump(a);
      }
      if (da && !db) {
        const std::uint32_t cp = corner_[p].across;
        if (cp != kNone && coded(cp)) bump(b);
      }
      const std::uint32_t c = corner_[k].across;
      if (c == kNone || !da || !db) continue;
      if (!coded(c)) {
        bump(c);  // c's parallelogram across k's edge (a, b), x across
        continue;
      }
      for (int i = 0; i < 3; ++i) {
        const std::int64_t ab = std::int64_t{ra.q[i]} + std::int64_t{rb.q[i]};
        g.sum[i] += ab - std::int64_t{v_[c].q[i]};
        g.ends[i] += ab;
        if (kSelect && g.count < kMaxSelect) {
          g.cand[g.count][i] = ab - std::int64_t{v_[c].q[i]};
          g.cand_ends[g.count][i] = ab;
        }
      }
      ++g.count;
    }
    predict_and_code(x, g);
  }

  void predict_and_code(std::uint32_t x, Gathered& g) {
    const unsigned activity = g.act_n ? (g.act_sum + g.act_n / 2) / g.act_n : last_rlen_;
    QPoint p{0, 0, 0};
    if (kSelect && g.count >= 2) {
      p = predict_select(coder_, x, g.cand, g.cand_ends, g.count, activity, blend_);
    } else if (g.count > 0) {
      const unsigned k = g.count == 1 ? blend_.one : blend_.many;
      for (int i = 0; i < 3; ++i)
        p[i] = k == 0 ? rounded_mean(g.sum[i], g.count, coder_.top())
                      : blended_mean(g.sum[i], g.ends[i], g.count, k, coder_.top());
    } else {
      const std::uint32_t from = g.neighbour != kNone ? g.neighbour : last_;
      if (from != kNone) p = {v_[from].q[0], v_[from].q[1], v_[from].q[2]};
    }
    last_rlen_ = geom::codec::detail::code(coder_, x, p, g.count, activity, v_[x].q);
    v_[x].state = 0x80u | last_rlen_;
    last_ = x;
  }

  const std::uint32_t* vx_;
  const std::uint32_t* op_;
  Coder& coder_;
  QPoint* out_;  // the grid points, table numbering
  Blend blend_;
  std::uint64_t deadline_;
  std::uint32_t nt_, nc_;
  CornerRec* corner_ = nullptr;
  std::uint32_t* head_ = nullptr;  // per vertex: its newest decoded corner
  std::uint32_t* birth_ = nullptr;  // per vertex: the triangle that introduced it
  VertexRec* v_ = nullptr;
  std::unique_ptr<std::uint32_t[]> work_;  // the queue; cleared after each triangle
  std::size_t wn_ = 0;
  std::uint32_t last_ = kNone;
  unsigned last_rlen_ = 0;
};

/// The growth pass and the isolated vertices after it; returns, with anchored isolated
/// vertices, the coded vertex of each stream position (empty otherwise: the identity).
template <bool kSelect, class Coder>
std::vector<std::uint32_t> growth_pass(const CornerTable& t, std::size_t n, Coder& coder,
                                       std::vector<QPoint>& q, Blend blend, bool anchored,
                                       unsigned log2_deadline, Scratch& scratch) {
  const std::uint32_t nc = t.n_vertices;
  geom::detail::reserve_huge(q, n);
  q.resize(n);
  unsigned last_rlen =
      GrowthPass<kSelect, Coder>(t, coder, q, blend, log2_deadline, scratch).run();
  std::vector<std::uint32_t> seq;
  if (anchored && n > nc) {
    seq.resize(nc);
    for (std::uint32_t i = 0; i < nc; ++i) seq[i] = i;
  }
  code_isolated(coder, q, nc, anchored, last_rlen, seq);
  return seq;
}

}  // namespace

std::size_t growth_scratch_bytes(std::size_t n_corners, std::size_t n_vertices) {
  return GrowthLayout(n_corners, n_vertices).end;
}

void decode_positions_growth(const CornerTable& table, std::size_t n, unsigned bits,
                             RansDecoder& rans, BitReader& raw, std::vector<QPoint>& q,
                             Predictor predictor, Blend blend, bool anchor_isolated,
                             unsigned log2_deadline, Scratch* scratch) {
  const bool select = predictor == Predictor::kGrowthSelect;
  ResidualReader reader(bits, rans, raw, true);
  Scratch own;
  Scratch& s = scratch ? *scratch : own;
  if (select)
    growth_pass<true>(table, n, reader, q, blend, anchor_isolated, log2_deadline, s);
  else
    growth_pass<false>(table, n, reader, q, blend, false, log2_deadline, s);
}

std::vector<std::uint32_t> encode_positions_growth(const CornerTable& table,
                                                   std::span<const QPoint> q, unsigned bits,
                                                   RansEncoder& rans, BitWriter& raw,
                                                   Predictor predictor, Blend blend,
                                                   bool anchor_isolated, unsigned log2_deadline) {
  ResidualWriter writer(q, bits, rans, raw, true);
  std::vector<QPoint> coded;
  Scratch scratch;
  if (predictor == Predictor::kGrowthSelect)
    return growth_pass<true>(table, q.size(), writer, coded, blend,
                             anchor_isolated && table.n_vertices > 0, log2_deadline, scratch);
  return growth_pass<false>(table, q.size(), writer, coded, blend, false, log2_deadline, scratch);
}

}  // namespace geom::codec::detail
