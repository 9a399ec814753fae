// The degree-order pass (predictors 3–5): vertices are taken when the most triangles around
// them are complete, with prediction and residual coding fused into the traversal, one
// template for the decoder and the encoder so both walk the same order by construction.

#include <geom/compress/point_chain.h>
#include <geom/compress/predict.h>
#include <geom/compress/residuals.h>

#include <geom/core/huge_pages.h>

#include <algorithm>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace geom::codec::detail {

using geom::detail::reserve_huge;

namespace {

/// What a corner k of vertex v contributes: a = vertex(next(k)), b = vertex(prev(k)) and
/// c = vertex(opposite(k)) (on a boundary the table's vertex count, whose slot is never
/// taken, so that c is read without a test). The decoder keeps each vertex's wedges
/// contiguous (ascending corner order), one run per vertex instead of three scattered
/// corner lookups per corner.
struct Wedge {
  std::uint32_t a, b, c;
};

/// What the degree pass asks about a vertex (table numbering) at every wedge end: its place
/// in the traversal (kNone until taken) and its degree. Its grid point is q[order], its
/// residual length is kept by place and its wedges' extent apart: the records are read at
/// random, and 8 bytes instead of 24 keep three times as many in cache, while q in traversal
/// order is mostly read near its recent end. The records hold only what the traversal
/// writes, never what the coding does (see act1 in degree_pass_as).
struct Slot {
  std::uint32_t order;
  std::uint8_t degree;
};

/// The degree pass's scratch block: a wedge per corner, then a record per vertex.
std::size_t slots_at(std::size_t n_corners) {
  return (n_corners * sizeof(Wedge) + alignof(Slot) - 1) / alignof(Slot) * alignof(Slot);
}

/// Encoder-side measurement for encode_positions_degree's `suggest`: the summed residual
/// bit lengths each blend weight would have given, per parallelogram class (one, several).
struct BlendProbe {
  std::uint64_t cost[2][16] = {};
  void add(const QPoint& truth, const std::int64_t* sum, const std::int64_t* ends, unsigned count) {
    const unsigned cls = count > 1 ? 1 : 0;
    for (int x = 0; x < 3; ++x) {
      // Doubles are close enough to pick a weight (the coding pass is exact); the residual
      // is measured from truth + 0.5 so truncation towards −∞ rounds.
      const double mp = double(sum[x]) / count, step = (double(ends[x]) / (2 * count) - mp) / 16;
      const double t = double(truth[x]) + 0.5 - mp;
      for (unsigned k = 0; k < 16; ++k) {
        const auto r = static_cast<std::int64_t>(std::floor(t - k * step));
        const auto z = static_cast<std::uint64_t>(r >= 0 ? 2 * r : -2 * r - 1);
        cost[cls][k] += static_cast<unsigned>(std::bit_width(z));
      }
    }
  }
  /// The weights with the smallest total; zero unless they shorten the residuals by 1/256.
  Blend best() const {
    std::uint8_t k[2] = {0, 0};
    std::uint64_t base = 0, saved = 0;
    for (int cls = 0; cls < 2; ++cls) {
      for (std::uint8_t i = 1; i < 16; ++i)
        if (cost[cls][i] < cost[cls][k[cls]]) k[cls] = i;
      base += cost[cls][0];
      saved += cost[cls][0] - cost[cls][k[cls]];
    }
    if (saved * 64 < base / 4) return {};
    return {k[0], k[1]};
  }
};

/// predict_select, kept out of the encoder's pass: inlined there, GCC 12 takes its ranking
/// for a read of uninitialised values (-Wmaybe-uninitialized); the encoder's subset search
/// costs far more than the call.
template <class Coder>
[[gnu::noinline]] QPoint predict_select_outlined(Coder& coder, std::uint32_t v,
                                                 std::int64_t (&cand)[kMaxSelect][3],
                                                 std::int64_t (&cand_ends)[kMaxSelect][3],
                                                 unsigned count, unsigned activity, Blend blend) {
  return predict_select(coder, v, cand, cand_ends, count, activity, blend);
}

/// The degree-order traversal with prediction and residual coding fused (see
/// decode_positions_degree); Coder is ResidualReader or ResidualWriter. q (table numbering
/// on entry for the writer) receives the grid points in the new order.
/// kSelect: predictor 5's subset choice. The per-vertex loop is compiled once per predictor
/// family and side (the decoder never records a plan), which keeps its state in registers.
/// Out of line: inlined into decode_positions_degree, the pass ran 1.1% more instructions
/// (GCC 12, the shuffled 1M-triangle benchmark mesh).
template <bool kSelect, class Coder>
[[gnu::noinline]] std::vector<std::uint32_t> degree_pass_as(
    CornerTable& t, std::size_t n, Coder& reader, std::vector<QPoint>& q, Blend blend,
    BlendProbe* probe, bool anchored, DegreePlan* plan, Scratch& scratch,
    std::vector<std::uint32_t>* open_corners) {
  constexpr bool kWriter = requires { reader.truth(0u); };
  if constexpr (!kWriter) plan = nullptr;
  constexpr bool select = kSelect;
  constexpr unsigned kTop = 2;
  const std::uint32_t nc = t.n_vertices;
  const std::size_t n_corners = t.vertex.size();
  scratch.reserve(degree_scratch_bytes(n_corners, nc));
  Wedge* const wedge = scratch.array<Wedge>(0, n_corners);  // every one written below
  // Slot nc stands for a boundary's missing opposite vertex: never taken.
  Slot* const slot = scratch.array<Slot>(slots_at(n_corners), std::size_t{nc} + 1);
  slot[nc] = Slot{kNone, 0};
  // Vertex v's wedges are wedge[end[v], end[v + 1]).
  geom::detail::UninitialisedVector<std::uint32_t> end = std::move(t.corners_of);
  t.corners_of.clear();
  std::uint32_t max_wedges = 0;  // the most wedges a vertex has
  {
    // Each vertex's corner count (counted by the connectivity decoder while it grew the
    // table, else here) becomes its wedge list's start and, in place, its fill cursor: the
    // scatter below then bumps a dense array that stays in cache, not the wide records.
    // The starts are stored shifted one place (cursor[v + 1] is v's, cursor[0] is 0), so
    // that after the scatter, which moves each start to its vertex's end, end[v] and
    // end[v + 1] bound v's wedges. Shifted as they are summed, not by an insert at the
    // front afterwards, which moved (and reallocated) the whole array.
    auto& cursor = end;
    // Counts that do not add up to the corners (a table edited without clearing them) are
    // recounted. The check is a cheap guard, not a proof: per-vertex counts are trusted.
    for (bool recount = cursor.size() != nc;; recount = true) {
      if (recount) {
        cursor.assign(nc, 0);
        for (std::uint32_t v : t.vertex) ++cursor[v];
      }
      std::uint32_t run = 0, last = 0;  // last: the previous vertex's start
      max_wedges = 0;
      for (std::uint32_t v = 0; v < nc; ++v) {
        slot[v] = Slot{kNone, 0};
        const std::uint32_t count = cursor[v];
        cursor[v] = last;
        last = run;
        run += count;
        max_wedges = std::max(max_wedges, count);
      }
      cursor.push_back(last);
      if (run == n_corners || recount) break;
    }
    const std::uint32_t* vx = t.vertex.data();
    const std::uint32_t* op = t.opposite.data();
    std::uint32_t* const at = cursor.data() + 1;
    auto scatter = [&](auto list_open) {  // compiled with and without the listing
      for (std::size_t c = 0; c < n_corners; c += 3) {
        const std::uint32_t v0 = vx[c], v1 = vx[c + 1], v2 = vx[c + 2];
        const std::uint32_t o0 = op[c], o1 = op[c + 1], o2 = op[c + 2];
        wedge[at[v0]++] = {v1, v2, o0 == kNone ? nc : vx[o0]};
        wedge[at[v1]++] = {v2, v0, o1 == kNone ? nc : vx[o1]};
        wedge[at[v2]++] = {v0, v1, o2 == kNone ? nc : vx[o2]};
        if constexpr (decltype(list_open)::value)
          for (std::uint32_t k = 0; k < 3; ++k)
            if (op[c + k] == kNone) open_corners->push_back(static_cast<std::uint32_t>(c + k));
      }
    };
    if (open_corners)
      scatter(std::true_type{});
    else
      scatter(std::false_type{});
  }
  // Stacks of vertices by degree, bucket[d][0, top[d]), stale entries skipped when popped.
  // A bump that raises nothing stores to its degree's top without counting it, so each
  // stack keeps a spare entry; degree 0 (never pushed to) is that entry alone. A push takes
  // a wedge, each wedge is scanned once, so a corner per entry (and the spare) never
  // overflows: no room check per vertex. Pages are touched only as the stacks use them.
  std::unique_ptr<std::uint32_t[]> stacks[kTop + 1];
  std::uint32_t* bucket[kTop + 1] = {};
  std::size_t top[kTop + 1] = {};
  for (unsigned d = 0; d <= kTop; ++d) {
    stacks[d].reset(new std::uint32_t[d == 0 ? 1 : n_corners + 1]);
    bucket[d] = stacks[d].get();
  }
  std::vector<std::uint32_t> seq(nc);
  std::uint32_t seed = 0;
  // Raises x (and pushes it) if `raise`, else stores back what it loaded: no branch on
  // which wedge ends are taken, a coin toss to the predictor whose misses would also flush
  // the coding running alongside.
  auto bump = [&](std::uint32_t x, bool raise) {
    Slot& sx = slot[x];
    const unsigned d = sx.degree + unsigned{raise && sx.degree < kTop};
    sx.degree = static_cast<std::uint8_t>(d);
    bucket[d][top[d]] = x;
    top[d] += raise;
    // x's wedges (six 12-byte records on average, at least one: x ends a wedge) usually
    // span two cache lines.
    __builtin_prefetch(wedge + end[x]);
    __builtin_prefetch(wedge + end[x + 1] - 1);
    // The writer reads x's true point when it takes x, usually soon.
    if constexpr (requires { reader.truth(x); }) __builtin_prefetch(&reader.truth(x));
  };
  // The untaken vertex with the most complete triangles (the last pushed among equals).
  auto pick = [&] {
    for (unsigned d = kTop; d > 0; --d) {  // nothing is pushed at degree 0
      while (top[d] > 0) {
        const std::uint32_t x = bucket[d][--top[d]];
        if (slot[x].order == kNone && slot[x].degree == d) return x;
      }
    }
    while (slot[seed].order != kNone) ++seed;
    return seed;
  };
  if (plan) {
    plan->steps.clear();
    plan->steps.reserve(nc);
    plan->act.clear();
    plan->act.reserve(t.vertex.size());
  }
  reserve_huge(q, n);
  q.resize(n);
  // A vertex's complete parallelograms, as the places of their corners a, b, c: gathered
  // without a branch while its wedges are scanned, summed after.
  struct Tri {
    std::uint32_t a, b, c;
  };
  std::vector<Tri> tri(std::max<std::size_t>(max_wedges, 1));  // a parallelogram per wedge
  // Residual lengths by place + 1, each packed with a count as (length << 8) | 1 (kNone + 1
  // wraps to 0, an entry that stays 0: an untaken end adds nothing), kept out of the slots:
  // a length is stored only when its vertex's residuals are decoded, and the next vertex's
  // scan loads the same slots (v is usually its neighbour), so with the length in the record
  // the traversal waited for the rANS chain; apart, the two overlap. One sum over a vertex's
  // wedge ends gives both the lengths' total (bits 8 up) and the taken ends (bits 0–7) in
  // one register, of which the scan is short; a vertex of kPackedWedges wedges or more (two
  // ends each) would carry into the total, so its ends are summed apart.
  // Not cleared: a place's entry is written when its vertex is coded, before any read of it.
  constexpr std::size_t kPackedWedges = 128;
  std::unique_ptr<std::uint16_t[]> act1(new std::uint16_t[std::size_t{nc} + 1]);
  act1[0] = 0;
  unsigned last_rlen = 0;
  for (std::uint32_t i = 0; i < nc; ++i) {
    const std::uint32_t v = pick();
    // Predict from the vertices already taken (exactly decode_positions' rule on the
    // renumbered table: "earlier" = taken, "largest-numbered" = taken last).
    const std::uint32_t first_wedge = end[v], n_wedges = end[v + 1] - first_wedge;
    const Wedge* w_begin = wedge + first_wedge;
    const Wedge* w_end = w_begin + n_wedges;
    Tri* const tri_out = tri.data();
    unsigned count = 0, act_sum = 0, act_n = 0;
    auto scan = [&](auto packed) {
      unsigned act = 0;
      Tri* next = tri_out;  // the next parallelogram's record (a pointer frees a register)
      for (const Wedge* we = w_begin; we != w_end; ++we) {
        const Slot& sa = slot[we->a];
        const Slot& sb = slot[we->b];
        const bool da = sa.order != kNone, db = sb.order != kNone;
        if (plan) {
          if (da) plan->act.push_back(sa.order);
          if (db) plan->act.push_back(sb.order);
        }
        const unsigned ea = act1[sa.order + 1], eb = act1[sb.order + 1];
        if constexpr (decltype(packed)::value) {
          act += ea + eb;
        } else {
          act_sum += (ea >> 8) + (eb >> 8);
          act_n += (ea & 0xffu) + (eb & 0xffu);
        }
        // Taking v raises a wedge's untaken end when the other end is taken. a and b are not
        // v, so raising here, before v is taken, pushes the same vertices in the same order.
        bump(da ? we->b : we->a, da != db);
        // A complete parallelogram: a, b and the opposite vertex c taken.
        const std::uint32_t oc = slot[we->c].order;
        *next = {sa.order, sb.order, oc};
        next += da && db && oc != kNone;
      }
      count = static_cast<unsigned>(next - tri_out);
      if constexpr (decltype(packed)::value) act_sum = act >> 8, act_n = act & 0xffu;
    };
    if (n_wedges < kPackedWedges) [[likely]]
      scan(std::true_type{});
    else
      scan(std::false_type{});
    std::int64_t sum[3] = {0, 0, 0}, ends[3] = {0, 0, 0};
    std::int64_t cand[kMaxSelect][3], cand_ends[kMaxSelect][3];  // select: the first ones
    for (unsigned k = 0; k < count; ++k) {
      const QPoint &qa = q[tri_out[k].a], &qb = q[tri_out[k].b], &qc = q[tri_out[k].c];
      for (int x = 0; x < 3; ++x) {
        const std::int64_t ab = std::int64_t{qa[x]} + std::int64_t{qb[x]};
        sum[x] += ab - std::int64_t{qc[x]};
        ends[x] += ab;  // predictor 4's centroid: the parallelograms' shared edges
        if (select && k < kMaxSelect) {
          cand[k][x] = ab - std::int64_t{qc[x]};
          cand_ends[k][x] = ab;
        }
      }
    }
    const unsigned activity = act_n ? (act_sum + act_n / 2) / act_n : last_rlen;
    QPoint p{0, 0, 0};
    std::uint32_t neighbour = kNone, neighbour_order = 0;
    if (select && count >= 2) {
      if constexpr (kWriter)
        p = predict_select_outlined(reader, v, cand, cand_ends, count, activity, blend);
      else
        p = predict_select(reader, v, cand, cand_ends, count, activity, blend);
    } else if (count > 0) {
      const unsigned k = count == 1 ? blend.one : blend.many;
      if (k == 0) {
        for (int x = 0; x < 3; ++x) p[x] = rounded_mean(sum[x], count, reader.top());
      } else {
        for (int x = 0; x < 3; ++x) p[x] = blended_mean(sum[x], ends[x], count, k, reader.top());
      }
      if constexpr (requires { reader.truth(v); })
        if (probe && i % 4 == 0) probe->add(reader.truth(v), sum, ends, count);  // a sample will do
    } else {
      // Without a parallelogram (rare): the neighbour taken last, found by a second scan so
      // that the common case's loop carries no comparison of places.
      for (const Wedge* we = w_begin; we != w_end; ++we)
        for (const std::uint32_t x : {we->a, we->b})
          if (slot[x].order != kNone && (neighbour == kNone || slot[x].order > neighbour_order))
            neighbour = x, neighbour_order = slot[x].order;
      if (neighbour == kNone && i > 0) neighbour = seq[i - 1], neighbour_order = i - 1;
      if (neighbour != kNone) p = q[neighbour_order];
    }
    if (plan) {
      DegreePlan::Step& st = plan->steps.emplace_back();
      for (int x = 0; x < 3; ++x) st.sum[x] = sum[x], st.ends[x] = ends[x];
      st.count = count;
      st.fallback = count == 0 && neighbour != kNone ? slot[neighbour].order : kNone;
      st.act_begin = static_cast<std::uint32_t>(plan->act.size() - (act_n));
    }
    slot[v].order = i;
    seq[i] = v;
    last_rlen = code(reader, v, p, count, activity, q[i].data());  // in traversal order
    act1[i + 1] = static_cast<std::uint16_t>(last_rlen << 8 | 1);
  }
  {
    // Renumber through the slots' places.
#pragma GCC unroll 4
    for (std::uint32_t& v : t.vertex) v = slot[v].order;
  }
  code_isolated(reader, q, nc, anchored, last_rlen, seq);
  return seq;
}

template <class Coder>
std::vector<std::uint32_t> degree_pass(CornerTable& t, std::size_t n, Coder& coder,
                                       std::vector<QPoint>& q, Blend blend, BlendProbe* probe,
                                       bool select, bool anchored, DegreePlan* plan,
                                       Scratch& scratch,
                                       std::vector<std::uint32_t>* open_corners = nullptr) {
  return select ? degree_pass_as<true>(t, n, coder, q, blend, probe, anchored, plan, scratch,
                                       open_corners)
                : degree_pass_as<false>(t, n, coder, q, blend, probe, anchored, plan, scratch,
                                        open_corners);
}

}  // namespace

std::size_t degree_scratch_bytes(std::size_t n_corners, std::size_t n_vertices) {
  return slots_at(n_corners) + (n_vertices + 1) * sizeof(Slot);
}

std::vector<std::uint32_t> decode_positions_degree(CornerTable& table, std::size_t n, unsigned bits,
                                                   RansDecoder& rans, BitReader& raw,
                                                   std::vector<QPoint>& q, Predictor predictor,
                                                   Blend blend, bool anchor_isolated,
                                                   Scratch* scratch,
                                                   std::vector<std::uint32_t>* open_corners) {
  const bool select = predictor == Predictor::kMultiParallelogramSelect;
  ResidualReader reader(bits, rans, raw,
                        select || predictor == Predictor::kMultiParallelogramBlend);
  Scratch own;
  if (open_corners) open_corners->clear();
  return degree_pass(table, n, reader, q, blend, nullptr, select, select && anchor_isolated,
                     nullptr, scratch ? *scratch : own, open_corners);
}

std::vector<std::uint32_t> encode_positions_degree(CornerTable& table, std::span<const QPoint> q,
                                                   unsigned bits, RansEncoder& rans, BitWriter& raw,
                                                   Predictor predictor, Blend blend, Blend* suggest,
                                                   bool anchor_isolated, DegreePlan* plan) {
  const bool select = predictor == Predictor::kMultiParallelogramSelect;
  ResidualWriter writer(q, bits, rans, raw,
                        select || predictor == Predictor::kMultiParallelogramBlend);
  std::vector<QPoint> reordered;
  Scratch scratch;
  BlendProbe probe;
  const bool measure = suggest && !blend.any();
  std::vector<std::uint32_t> seq =
      degree_pass(table, q.size(), writer, reordered, blend, measure ? &probe : nullptr, select,
                  select && anchor_isolated, plan, scratch);
  if (suggest) *suggest = measure ? probe.best() : Blend{};
  if (plan) {
    plan->seq = seq;
    plan->q = std::move(reordered);
  }
  return seq;
}

std::vector<std::uint32_t> encode_positions_degree_again(CornerTable& table, const DegreePlan& plan,
                                                         unsigned bits, RansEncoder& rans,
                                                         BitWriter& raw, Predictor predictor,
                                                         Blend blend) {
  // degree_pass's coding step, replayed: positions are traversal positions here.
  const std::uint32_t nc = table.n_vertices;
  ResidualWriter writer(plan.q, bits, rans, raw, predictor == Predictor::kMultiParallelogramBlend);
  std::vector<std::uint8_t> rlen(plan.q.size(), 0);
  unsigned last_rlen = 0;
  QPoint scratch;
  for (std::uint32_t i = 0; i < nc; ++i) {
    const DegreePlan::Step& st = plan.steps[i];
    const std::uint32_t act_end =
        i + 1 < nc ? plan.steps[i + 1].act_begin : static_cast<std::uint32_t>(plan.act.size());
    unsigned act_sum = 0;
    for (std::uint32_t j = st.act_begin; j < act_end; ++j) act_sum += rlen[plan.act[j]];
    const unsigned act_n = act_end - st.act_begin;
    const unsigned activity = act_n ? (act_sum + act_n / 2) / act_n : last_rlen;
    QPoint p{0, 0, 0};
    if (st.count > 0) {
      const unsigned k = st.count == 1 ? blend.one : blend.many;
      for (int x = 0; x < 3; ++x)
        p[x] = k == 0 ? rounded_mean(st.sum[x], st.count, writer.top())
                      : blended_mean(st.sum[x], st.ends[x], st.count, k, writer.top());
    } else if (st.fallback != kNone) {
      p = plan.q[st.fallback];
    }
    last_rlen = writer.code(i, p, st.count, activity, scratch.data());
    rlen[i] = static_cast<std::uint8_t>(last_rlen);
  }
  for (std::size_t w = nc; w < plan.q.size(); ++w) {
    const QPoint p = w > 0 ? plan.q[w - 1] : QPoint{0, 0, 0};
    last_rlen = writer.code(static_cast<std::uint32_t>(w), p, 0, last_rlen, scratch.data());
  }
  std::vector<std::uint32_t> new_id(nc);
  for (std::uint32_t i = 0; i < nc; ++i) new_id[plan.seq[i]] = i;
  for (std::uint32_t& v : table.vertex) v = new_id[v];
  table.corners_of.clear();
  return plan.seq;
}

}  // namespace geom::codec::detail
