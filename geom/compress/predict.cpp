#include <geom/compress/predict.h>
#include <geom/compress/residuals.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

namespace geom::codec::detail {

namespace {

/// Vertex → corners, as a compressed row table.
struct Incidence {
  std::vector<std::uint32_t> offset, corner;
  explicit Incidence(const CornerTable& t) : offset(t.n_vertices + 1, 0), corner(t.vertex.size()) {
    for (std::uint32_t v : t.vertex) ++offset[v + 1];
    for (std::size_t i = 1; i < offset.size(); ++i) offset[i] += offset[i - 1];
    std::vector<std::uint32_t> fill(offset.begin(), offset.end() - 1);
    for (std::uint32_t c = 0; c < t.vertex.size(); ++c) corner[fill[t.vertex[c]]++] = c;
  }
};

/// The prediction of vertex w from earlier vertices; returns the number of parallelograms
/// used (0 when it fell back to a neighbour or the previous vertex).
unsigned predict(const CornerTable& t, const Incidence& inc, std::span<const QPoint> q,
                 std::span<const std::uint8_t> rlen, std::uint32_t w, Predictor predictor,
                 std::uint32_t top, QPoint& out, unsigned& activity) {
  unsigned act_sum = 0, act_n = 0;
  std::int64_t sum[3] = {0, 0, 0};
  unsigned count = 0;
  std::uint32_t neighbour = kNone;
  if (w < t.n_vertices) {
    for (std::uint32_t i = inc.offset[w]; i < inc.offset[w + 1]; ++i) {
      const std::uint32_t k = inc.corner[i];
      const std::uint32_t a = t.vertex[next_corner(k)], b = t.vertex[prev_corner(k)];
      if (a < w) act_sum += rlen[a], ++act_n;
      if (b < w) act_sum += rlen[b], ++act_n;
      if (a < w && (neighbour == kNone || a > neighbour)) neighbour = a;
      if (b < w && (neighbour == kNone || b > neighbour)) neighbour = b;
      if (predictor == Predictor::kDelta || a >= w || b >= w) continue;
      const std::uint32_t o = t.opposite[k];
      if (o == kNone) continue;
      const std::uint32_t c = t.vertex[o];
      if (c >= w) continue;
      for (int x = 0; x < 3; ++x)
        sum[x] += std::int64_t{q[a][x]} + std::int64_t{q[b][x]} - std::int64_t{q[c][x]};
      ++count;
      if (predictor == Predictor::kParallelogram) break;
    }
  }
  activity = act_n ? (act_sum + act_n / 2) / act_n : (w > 0 ? rlen[w - 1] : 0);
  if (count > 0) {
    for (int x = 0; x < 3; ++x) {
      // Rounded mean with floor division, identical on both sides for negative sums.
      const std::int64_t num = 2 * sum[x] + count, den = 2 * std::int64_t{count};
      std::int64_t m = num / den;
      if ((num % den != 0) && (num < 0)) --m;
      out[x] = static_cast<std::uint32_t>(std::clamp<std::int64_t>(m, 0, top));
    }
    return count;
  }
  if (neighbour == kNone && w > 0) neighbour = w - 1;
  if (neighbour == kNone) out = {0, 0, 0};
  else out = q[neighbour];
  return 0;
}

}  // namespace

std::vector<std::uint32_t> degree_order(CornerTable& t) {
  constexpr unsigned kTop = 2;
  const std::uint32_t n = t.n_vertices;
  const Incidence inc(t);
  std::vector<std::uint8_t> done(n, 0), degree(n, 0);
  std::vector<std::uint32_t> bucket[kTop + 1];
  std::vector<std::uint32_t> seq;
  seq.reserve(n);
  std::uint32_t seed = 0;
  auto bump = [&](std::uint32_t x) {
    if (degree[x] < kTop) ++degree[x];
    bucket[degree[x]].push_back(x);
  };
  while (seq.size() < n) {
    std::uint32_t v = kNone;
    for (int d = kTop; d >= 0 && v == kNone; --d) {
      auto& b = bucket[d];
      while (!b.empty()) {
        const std::uint32_t x = b.back();
        b.pop_back();
        if (!done[x] && degree[x] == d) {
          v = x;
          break;
        }
      }
    }
    if (v == kNone) {
      while (done[seed]) ++seed;
      v = seed;
    }
    done[v] = 1;
    seq.push_back(v);
    for (std::uint32_t i = inc.offset[v]; i < inc.offset[v + 1]; ++i) {
      const std::uint32_t k = inc.corner[i];
      const std::uint32_t a = t.vertex[next_corner(k)], b = t.vertex[prev_corner(k)];
      if (done[b] && !done[a]) bump(a);
      if (done[a] && !done[b]) bump(b);
    }
  }
  std::vector<std::uint32_t> new_id(n);
  for (std::uint32_t i = 0; i < n; ++i) new_id[seq[i]] = i;
  for (std::uint32_t& v : t.vertex) v = new_id[v];
  t.corners_of.clear();
  return seq;
}

void encode_positions(const CornerTable& table, std::span<const QPoint> q, unsigned bits,
                      Predictor predictor, RansEncoder& rans, BitWriter& raw) {
  const Incidence inc(table);
  ResidualModels m;
  const std::uint32_t top = static_cast<std::uint32_t>((std::uint64_t{1} << bits) - 1);
  unsigned prev_len = 0, activity = 0;
  std::vector<std::uint8_t> rlen(q.size(), 0);
  for (std::uint32_t w = 0; w < q.size(); ++w) {
    QPoint p;
    const unsigned count = predict(table, inc, q, rlen, w, predictor, top, p, activity);
    for (unsigned x = 0; x < 3; ++x) {
      const std::int64_t r = std::int64_t{q[w][x]} - std::int64_t{p[x]};
      const auto z = static_cast<std::uint32_t>(r >= 0 ? 2 * r : -2 * r - 1);
      const unsigned len = static_cast<unsigned>(std::bit_width(z));
      rans.encode(m.length[context(x, count, prev_len, activity)], len);
      m.encode_below_length(rans, raw, x, len, z);
      prev_len = len;
      if (len > rlen[w]) rlen[w] = static_cast<std::uint8_t>(len);
    }
  }
}

void encode_positions_each(const CornerTable& t, std::span<const QPoint> q, unsigned bits,
                           std::span<const Predictor> predictors, std::span<RansEncoder> rans,
                           std::span<BitWriter> raw) {
  const std::size_t np = predictors.size();
  if (np > kMaxEach || rans.size() != np || raw.size() != np)
    throw InvalidArgument("encode_positions_each: one coder per predictor, at most 4");
  const Incidence inc(t);
  const std::uint32_t top = static_cast<std::uint32_t>((std::uint64_t{1} << bits) - 1);
  std::vector<ResidualModels> models(np);
  // Residual lengths interleaved per vertex: a neighbour's lengths share a cache line.
  std::vector<std::uint8_t> rlen(q.size() * np, 0);
  unsigned prev_len[kMaxEach] = {}, activity[kMaxEach] = {};
  for (std::uint32_t w = 0; w < q.size(); ++w) {
    // predict() for every predictor at once: one scan of w's corners. A parallelogram
    // predictor stops at its first parallelogram, and its activity with it.
    unsigned act_sum[kMaxEach] = {}, act_n[kMaxEach] = {}, count[kMaxEach] = {};
    std::int64_t sum[kMaxEach][3] = {};
    bool stopped[kMaxEach] = {};
    std::uint32_t neighbour = kNone;
    for (std::uint32_t i = w < t.n_vertices ? inc.offset[w] : 0;
         w < t.n_vertices && i < inc.offset[w + 1]; ++i) {
      const std::uint32_t k = inc.corner[i];
      const std::uint32_t a = t.vertex[next_corner(k)], b = t.vertex[prev_corner(k)];
      for (std::size_t j = 0; j < np; ++j) {
        if (stopped[j]) continue;
        if (a < w) act_sum[j] += rlen[a * np + j], ++act_n[j];
        if (b < w) act_sum[j] += rlen[b * np + j], ++act_n[j];
      }
      if (a < w && (neighbour == kNone || a > neighbour)) neighbour = a;
      if (b < w && (neighbour == kNone || b > neighbour)) neighbour = b;
      if (a >= w || b >= w) continue;
      const std::uint32_t o = t.opposite[k];
      if (o == kNone) continue;
      const std::uint32_t c = t.vertex[o];
      if (c >= w) continue;
      std::int64_t par[3];
      for (int x = 0; x < 3; ++x)
        par[x] = std::int64_t{q[a][x]} + std::int64_t{q[b][x]} - std::int64_t{q[c][x]};
      for (std::size_t j = 0; j < np; ++j) {
        if (stopped[j] || predictors[j] == Predictor::kDelta) continue;
        for (int x = 0; x < 3; ++x) sum[j][x] += par[x];
        ++count[j];
        stopped[j] = predictors[j] == Predictor::kParallelogram;
      }
    }
    for (std::size_t j = 0; j < np; ++j) {
      activity[j] = act_n[j] ? (act_sum[j] + act_n[j] / 2) / act_n[j]
                             : (w > 0 ? rlen[(w - 1) * np + j] : 0);
      QPoint p{0, 0, 0};
      if (count[j] > 0) {
        for (int x = 0; x < 3; ++x) p[x] = rounded_mean(sum[j][x], count[j], top);
      } else {
        const std::uint32_t from = neighbour == kNone && w > 0 ? w - 1 : neighbour;
        if (from != kNone) p = q[from];
      }
      ResidualModels& m = models[j];
      for (unsigned x = 0; x < 3; ++x) {
        const std::int64_t r = std::int64_t{q[w][x]} - std::int64_t{p[x]};
        const auto z = static_cast<std::uint32_t>(r >= 0 ? 2 * r : -2 * r - 1);
        const unsigned len = static_cast<unsigned>(std::bit_width(z));
        rans[j].encode(m.length[context(x, count[j], prev_len[j], activity[j])], len);
        m.encode_below_length(rans[j], raw[j], x, len, z);
        prev_len[j] = len;
        std::uint8_t& rl = rlen[w * np + j];
        if (len > rl) rl = static_cast<std::uint8_t>(len);
      }
    }
  }
}

std::uint32_t blended_mean_wide(std::int64_t s, std::int64_t e, unsigned count, unsigned k,
                                std::uint32_t top) {
  __extension__ typedef __int128 Wide;  // a vertex on millions of triangles
  const Wide num = 2 * Wide(16 - k) * s + Wide(k) * e, den = Wide(32) * count;
  const auto m = static_cast<std::int64_t>(floor_div<Wide>(2 * num + den, 2 * den));
  return static_cast<std::uint32_t>(std::clamp<std::int64_t>(m, 0, top));
}

void decode_positions(const CornerTable& table, std::size_t n, unsigned bits, Predictor predictor,
                      RansDecoder& rans, BitReader& raw, std::vector<QPoint>& q) {
  const Incidence inc(table);
  ResidualReader reader(bits, rans, raw);
  q.resize(n);
  unsigned activity = 0;
  std::vector<std::uint8_t> rlen(n, 0);
  for (std::uint32_t w = 0; w < n; ++w) {
    QPoint p;
    const unsigned count = predict(table, inc, q, rlen, w, predictor, reader.top(), p, activity);
    rlen[w] = static_cast<std::uint8_t>(reader.read(p, count, activity, q[w].data()));
  }
}

}  // namespace geom::codec::detail
