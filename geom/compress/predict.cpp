#include <geom/compress/predict.h>

#include <algorithm>
#include <bit>
#include <string>

namespace geom::codec::detail {

namespace {

constexpr unsigned kLengthClasses = 12;

/// Residual models. A residual's bit length is coded adaptively in a context of its axis,
/// how many parallelograms backed the prediction (more ⇒ smaller residuals) and the length
/// of the previous residual (errors are locally correlated); the first bit below the
/// leading one is modelled too, the rest are raw.
struct ResidualModels {
  std::vector<AdaptiveModel> length =
      std::vector<AdaptiveModel>(3 * 3 * kLengthClasses, AdaptiveModel(33));
  std::vector<AdaptiveModel> top;
  ResidualModels() {
    top.reserve(3 * 33);
    for (unsigned i = 0; i < 3 * 33; ++i) top.emplace_back(i % 33 <= 2 ? 2 : 4);
  }
};

/// Bits below the leading one that are modelled (the rest are close to uniform).
inline unsigned modelled_bits(unsigned len) { return len <= 2 ? (len == 2 ? 1 : 0) : 2; }

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
  return seq;
}

namespace {

/// The residual length context: the neighbours' mean residual length (local roughness),
/// blended with this vertex's previous axis once one is known.
inline unsigned context(unsigned axis, unsigned count, unsigned prev_len, unsigned activity) {
  const unsigned cc = count > 2 ? 2 : count;
  const unsigned blend = axis == 0 ? activity : (prev_len + activity + 1) / 2;
  const unsigned pl = blend >= kLengthClasses ? kLengthClasses - 1 : blend;
  return (axis * 3 + cc) * kLengthClasses + pl;
}

}  // namespace

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
      if (len >= 2) {
        const unsigned mb = modelled_bits(len), rb = len - 1 - mb;
        rans.encode(m.top[x * 33 + len], (z >> rb) & ((1u << mb) - 1));
        raw.put(z & ((1u << rb) - 1), rb);
      }
      prev_len = len;
      if (len > rlen[w]) rlen[w] = static_cast<std::uint8_t>(len);
    }
  }
}

void decode_positions(const CornerTable& table, std::size_t n, unsigned bits, Predictor predictor,
                      RansDecoder& rans, BitReader& raw, std::vector<QPoint>& q) {
  const Incidence inc(table);
  ResidualModels m;
  const std::uint32_t top = static_cast<std::uint32_t>((std::uint64_t{1} << bits) - 1);
  q.resize(n);
  unsigned prev_len = 0, activity = 0;
  std::vector<std::uint8_t> rlen(n, 0);
  for (std::uint32_t w = 0; w < n; ++w) {
    QPoint p;
    const unsigned count = predict(table, inc, q, rlen, w, predictor, top, p, activity);
    for (unsigned x = 0; x < 3; ++x) {
      const unsigned len = rans.decode(m.length[context(x, count, prev_len, activity)]);
      std::uint32_t z = 0;
      if (len == 1) {
        z = 1;
      } else if (len >= 2) {
        if (len > 32) throw DecodeError(rans.offset(), "position residual too long");
        const unsigned mb = modelled_bits(len), rb = len - 1 - mb;
        const std::uint64_t high = (std::uint64_t{1} << mb) | rans.decode(m.top[x * 33 + len]);
        z = static_cast<std::uint32_t>((high << rb) | raw.get(rb));
      }
      const std::int64_t r = (z & 1u) ? -static_cast<std::int64_t>((z >> 1) + 1)
                                      : static_cast<std::int64_t>(z >> 1);
      const std::int64_t v = std::int64_t{p[x]} + r;
      if (v < 0 || v > top)
        throw DecodeError(rans.offset(), "decoded position off the " + std::to_string(bits) +
                                             "-bit grid near byte " + std::to_string(rans.offset()));
      q[w][x] = static_cast<std::uint32_t>(v);
      prev_len = len;
      if (len > rlen[w]) rlen[w] = static_cast<std::uint8_t>(len);
    }
  }
}

}  // namespace geom::codec::detail
