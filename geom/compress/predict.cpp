#include <geom/compress/predict.h>

#include <geom/compress/point_chain.h>

#include <geom/core/huge_pages.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <string>

namespace geom::codec::detail {

using geom::detail::reserve_huge;

namespace {

constexpr unsigned kLengthClasses = 12;

/// Residual models. A residual's bit length is coded adaptively in a context of its axis,
/// how many parallelograms backed the prediction (more ⇒ smaller residuals) and the length
/// of the previous residual (errors are locally correlated); the first bit below the
/// leading one is modelled too, the rest are raw. Length models have 33 symbols (0–32), or
/// (predictor 4) only the bits + 2 lengths a grid residual can have: every symbol keeps a
/// minimum frequency, so 20 unused ones cost about 0.03 bits per residual.
struct ResidualModels {
  std::vector<AdaptiveModel> length;
  std::vector<AdaptiveModel> top;
  /// kMultiParallelogramSelect's subset masks, one model per number of candidates (2 … 4).
  std::vector<AdaptiveModel> subset;
  explicit ResidualModels(unsigned n_lengths = 33)
      : length(3 * 3 * kLengthClasses, AdaptiveModel(n_lengths)) {
    top.reserve(3 * 33);
    for (unsigned i = 0; i < 3 * 33; ++i) top.emplace_back(i % 33 <= 2 ? 2 : 4);
    for (unsigned m = 2; m <= kMaxSelect; ++m) subset.emplace_back((1u << m) - 1);
  }
};

/// −log2(f / 2^15) for every frequency f ≤ 2^15: what a symbol of frequency f costs, for the
/// encoder's choices (a table, since the subset search asks for it a dozen times a vertex).
float symbol_bits(std::uint32_t f) {
  static const std::vector<float> table = [] {
    std::vector<float> t(kProbScale + 1);
    t[0] = float(kProbBits + 1);  // never coded: models keep every frequency ≥ kMinFreq
    for (std::uint32_t i = 1; i <= kProbScale; ++i) t[i] = float(kProbBits) - std::log2(float(i));
    return t;
  }();
  return table[f];
}

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

/// What a corner k of vertex v contributes: a = vertex(next(k)), b = vertex(prev(k)) and
/// c = vertex(opposite(k)) (kNone on a boundary). The decoder keeps each vertex's wedges
/// contiguous (ascending corner order), one run per vertex instead of three scattered
/// corner lookups per corner.
struct Wedge {
  std::uint32_t a, b, c;
};

/// Everything the degree pass asks about a vertex (table numbering) in one record: its grid
/// point, its place in the traversal (kNone until taken), where its wedges start, its
/// degree and residual length. A vertex's record is in cache when it is raised, so its
/// wedges can be prefetched before the traversal takes it.
struct Slot {
  std::uint32_t q[3];
  std::uint32_t order;
  std::uint32_t first;  // its wedges are wedge[first, next record's first)
  std::uint8_t degree, rlen;
};

/// The degree pass's scratch block: a wedge per corner, then a record per vertex (+1).
std::size_t slots_at(std::size_t n_corners) {
  return (n_corners * sizeof(Wedge) + alignof(Slot) - 1) / alignof(Slot) * alignof(Slot);
}

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

namespace {

/// Decodes a vertex's three residuals onto its prediction (shared by both decoders).
class ResidualReader {
 public:
  ResidualReader(unsigned bits, RansDecoder& rans, BitReader& raw, bool compact = false)
      : m_(compact ? bits + 2 : 33), rans_(rans), raw_(raw),
        top_(static_cast<std::uint32_t>((std::uint64_t{1} << bits) - 1)), bits_(bits) {}
  std::uint32_t top() const { return top_; }
  /// Writes the decoded grid point to out; returns the largest residual length.
  unsigned read(const QPoint& p, unsigned count, unsigned activity, std::uint32_t* out) {
    unsigned longest = 0;
    for (unsigned x = 0; x < 3; ++x) {
      const unsigned len = rans_.decode(m_.length[context(x, count, prev_len_, activity)]);
      std::uint32_t z = len;  // lengths 0 and 1 are the values 0 and 1
      if (len >= 2) {
        if (len > 32) fail("position residual too long");
        const unsigned mb = modelled_bits(len), rb = len - 1 - mb;
        const std::uint64_t high = (std::uint64_t{1} << mb) | rans_.decode(m_.top[x * 33 + len]);
        z = static_cast<std::uint32_t>((high << rb) | raw_.get(rb));
      }
      const std::int64_t r = (z & 1u) ? -static_cast<std::int64_t>((z >> 1) + 1)
                                      : static_cast<std::int64_t>(z >> 1);
      const std::int64_t v = std::int64_t{p[x]} + r;
      if (v < 0 || v > top_)
        fail(("decoded position off the " + std::to_string(bits_) + "-bit grid").c_str());
      out[x] = static_cast<std::uint32_t>(v);
      prev_len_ = len;
      longest = std::max(longest, len);
    }
    return longest;
  }
  /// kMultiParallelogramSelect: the subset mask (1 … 2^m − 1) of m candidates.
  template <class Predict>
  unsigned choose(std::uint32_t, unsigned m, unsigned, unsigned, Predict&&) {
    return rans_.decode(m_.subset[m - 2]) + 1;
  }
  /// An anchored isolated vertex: advances `at` by the coded gap to its anchor.
  void anchor(GammaModel& gaps, std::uint64_t& at, std::uint32_t n_connected, std::uint32_t) {
    at += gaps.decode(rans_, raw_);
    if (at >= n_connected) fail("isolated vertex anchored beyond the connected vertices");
  }

 private:
  [[noreturn]] void fail(const char* what) const {
    throw DecodeError(rans_.offset(),
                      std::string(what) + " near byte " + std::to_string(rans_.offset()));
  }
  ResidualModels m_;
  RansDecoder& rans_;
  BitReader& raw_;
  std::uint32_t top_;
  unsigned bits_;
  unsigned prev_len_ = 0;
};

/// The rounded mean of `count` parallelogram sums, clamped to the grid (floor division, so
/// negative sums round the same on both sides).
inline std::uint32_t rounded_mean(std::int64_t sum, unsigned count, std::uint32_t top) {
  std::int64_t m = sum;
  if (count > 1) {
    const std::int64_t num = 2 * sum + count, den = 2 * std::int64_t{count};
    m = num / den;
    if ((num % den != 0) && (num < 0)) --m;
  }
  return static_cast<std::uint32_t>(std::clamp<std::int64_t>(m, 0, top));
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

/// floor(a / b) for b > 0 (C++ division truncates towards zero).
template <class T>
inline T floor_div(T a, T b) {
  const T d = a / b;
  return (a % b != 0 && a < 0) ? d - 1 : d;
}

}  // namespace

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
        if (len >= 2) {
          const unsigned mb = modelled_bits(len), rb = len - 1 - mb;
          rans[j].encode(m.top[x * 33 + len], (z >> rb) & ((1u << mb) - 1));
          raw[j].put(z & ((1u << rb) - 1), rb);
        }
        prev_len[j] = len;
        std::uint8_t& rl = rlen[w * np + j];
        if (len > rl) rl = static_cast<std::uint8_t>(len);
      }
    }
  }
}

std::uint32_t blended_mean(std::int64_t s, std::int64_t e, unsigned count, unsigned k,
                           std::uint32_t top) {
  std::int64_t m;
  if (count < (1u << 24)) {
    // |s| < count·2^31 and 0 ≤ e < count·2^31, so 2·num + den stays below 2^62.
    const std::int64_t num = 2 * std::int64_t(16 - k) * s + std::int64_t(k) * e;
    const std::int64_t den = 32 * std::int64_t{count};
    m = floor_div(2 * num + den, 2 * den);
  } else {
    __extension__ typedef __int128 Wide;  // a vertex on millions of triangles
    const Wide num = 2 * Wide(16 - k) * s + Wide(k) * e, den = Wide(32) * count;
    m = static_cast<std::int64_t>(floor_div<Wide>(2 * num + den, 2 * den));
  }
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

namespace {

/// Codes residuals against predictions on the encoder side (the mirror of ResidualReader):
/// `out` receives the vertex's true grid point.
class ResidualWriter {
 public:
  ResidualWriter(std::span<const QPoint> q, unsigned bits, RansEncoder& rans, BitWriter& raw,
                 bool compact = false)
      : m_(compact ? bits + 2 : 33), q_(q), rans_(rans), raw_(raw),
        top_(static_cast<std::uint32_t>((std::uint64_t{1} << bits) - 1)) {}
  std::uint32_t top() const { return top_; }
  const QPoint& truth(std::uint32_t v) const { return q_[v]; }
  unsigned code(std::uint32_t v, const QPoint& p, unsigned count, unsigned activity,
                std::uint32_t* out) {
    unsigned longest = 0;
    for (unsigned x = 0; x < 3; ++x) {
      out[x] = q_[v][x];
      const std::int64_t r = std::int64_t{q_[v][x]} - std::int64_t{p[x]};
      const auto z = static_cast<std::uint32_t>(r >= 0 ? 2 * r : -2 * r - 1);
      const unsigned len = static_cast<unsigned>(std::bit_width(z));
      rans_.encode(m_.length[context(x, count, prev_len_, activity)], len);
      if (len >= 2) {
        const unsigned mb = modelled_bits(len), rb = len - 1 - mb;
        rans_.encode(m_.top[x * 33 + len], (z >> rb) & ((1u << mb) - 1));
        raw_.put(z & ((1u << rb) - 1), rb);
      }
      prev_len_ = len;
      longest = std::max(longest, len);
    }
    return longest;
  }
  /// kMultiParallelogramSelect: codes and returns the subset mask (1 … 2^m − 1) of m
  /// candidates whose prediction (predict(mask)) codes v in the fewest estimated bits, the
  /// mask's own symbol included; ties go to the lowest mask.
  template <class Predict>
  unsigned choose(std::uint32_t v, unsigned m, unsigned count, unsigned activity,
                  Predict&& predict) {
    AdaptiveModel& model = m_.subset[m - 2];
    unsigned best = 1;
    float best_bits = 0;
    for (unsigned mask = 1; mask < (1u << m); ++mask) {
      const float b =
          symbol_bits(model.freq(mask - 1)) + estimate(v, predict(mask), count, activity);
      if (mask == 1 || b < best_bits) best = mask, best_bits = b;
    }
    rans_.encode(model, best - 1);
    return best;
  }
  void anchor(GammaModel& gaps, std::uint64_t& at, std::uint32_t, std::uint32_t gap) {
    gaps.encode(rans_, raw_, gap);
    at += gap;
  }

 private:
  /// The bits code() would spend on v against prediction p, at the models' current state
  /// (the bits below the leading one counted as raw).
  float estimate(std::uint32_t v, const QPoint& p, unsigned count, unsigned activity) const {
    float bits = 0;
    unsigned prev = prev_len_;
    for (unsigned x = 0; x < 3; ++x) {
      const std::int64_t r = std::int64_t{q_[v][x]} - std::int64_t{p[x]};
      const auto z = static_cast<std::uint32_t>(r >= 0 ? 2 * r : -2 * r - 1);
      const unsigned len = static_cast<unsigned>(std::bit_width(z));
      bits += symbol_bits(m_.length[context(x, count, prev, activity)].freq(len));
      if (len >= 2) bits += float(len - 1);
      prev = len;
    }
    return bits;
  }
  ResidualModels m_;
  std::span<const QPoint> q_;
  RansEncoder& rans_;
  BitWriter& raw_;
  std::uint32_t top_;
  unsigned prev_len_ = 0;
};

inline unsigned code(ResidualReader& r, std::uint32_t, const QPoint& p, unsigned count,
                     unsigned activity, std::uint32_t* out) {
  return r.read(p, count, activity, out);
}
inline unsigned code(ResidualWriter& w, std::uint32_t v, const QPoint& p, unsigned count,
                     unsigned activity, std::uint32_t* out) {
  return w.code(v, p, count, activity, out);
}

/// The degree-order traversal with prediction and residual coding fused (see
/// decode_positions_degree); Coder is ResidualReader or ResidualWriter. q (table numbering
/// on entry for the writer) receives the grid points in the new order.
/// kSelect: predictor 5's subset choice. The per-vertex loop is compiled once per predictor
/// family and side (the decoder never records a plan), which keeps its state in registers.
template <bool kSelect, class Coder>
std::vector<std::uint32_t> degree_pass_as(CornerTable& t, std::size_t n, Coder& reader,
                                          std::vector<QPoint>& q, Blend blend, BlendProbe* probe,
                                          bool anchored, DegreePlan* plan, Scratch& scratch) {
  constexpr bool kWriter = requires { reader.truth(0u); };
  if constexpr (!kWriter) plan = nullptr;
  constexpr bool select = kSelect;
  constexpr unsigned kTop = 2;
  const std::uint32_t nc = t.n_vertices;
  const std::size_t n_corners = t.vertex.size();
  scratch.reserve(degree_scratch_bytes(n_corners, nc));
  Wedge* const wedge = scratch.array<Wedge>(0, n_corners);  // every one written below
  Slot* const slot = scratch.array<Slot>(slots_at(n_corners), nc + 1);
  std::fill_n(slot, nc + 1, Slot{{0, 0, 0}, kNone, 0, 0, 0});
  {
    for (std::uint32_t v : t.vertex) ++slot[v + 1].first;
    for (std::uint32_t i = 1; i <= nc; ++i) slot[i].first += slot[i - 1].first;
    // Fill with the records' `order` fields as cursors, then restore them.
    for (std::uint32_t i = 0; i < nc; ++i) slot[i].order = slot[i].first;
    const std::uint32_t* vx = t.vertex.data();
    const std::uint32_t* op = t.opposite.data();
    for (std::size_t c = 0; c < t.vertex.size(); c += 3) {
      const std::uint32_t v0 = vx[c], v1 = vx[c + 1], v2 = vx[c + 2];
      const std::uint32_t o0 = op[c], o1 = op[c + 1], o2 = op[c + 2];
      wedge[slot[v0].order++] = {v1, v2, o0 == kNone ? kNone : vx[o0]};
      wedge[slot[v1].order++] = {v2, v0, o1 == kNone ? kNone : vx[o1]};
      wedge[slot[v2].order++] = {v0, v1, o2 == kNone ? kNone : vx[o2]};
    }
    for (std::uint32_t i = 0; i < nc; ++i) slot[i].order = kNone;
  }
  std::vector<std::uint32_t> bucket[kTop + 1];
  for (auto& b : bucket) b.reserve(nc);
  std::vector<std::uint32_t> seq(nc);
  std::uint32_t seed = 0;
  auto bump = [&](std::uint32_t x) {
    Slot& sx = slot[x];
    if (sx.degree < kTop) ++sx.degree;
    bucket[sx.degree].push_back(x);
    // x's wedges (six 12-byte records on average) usually span two cache lines.
    __builtin_prefetch(wedge + sx.first);
    __builtin_prefetch(wedge + std::min<std::size_t>(sx.first + 5, n_corners));
    // The writer reads x's true point when it takes x, usually soon.
    if constexpr (requires { reader.truth(x); }) __builtin_prefetch(&reader.truth(x));
  };
  unsigned last_rlen = 0;
  if (plan) {
    plan->steps.clear();
    plan->steps.reserve(nc);
    plan->act.clear();
    plan->act.reserve(t.vertex.size());
  }
  for (std::uint32_t i = 0; i < nc; ++i) {
    std::uint32_t v = kNone;
    for (int d = kTop; d >= 0 && v == kNone; --d) {
      auto& b = bucket[d];
      while (!b.empty()) {
        const std::uint32_t x = b.back();
        b.pop_back();
        if (slot[x].order == kNone && slot[x].degree == d) {
          v = x;
          break;
        }
      }
    }
    if (v == kNone) {
      while (slot[seed].order != kNone) ++seed;
      v = seed;
    }
    // Predict from the vertices already taken (exactly decode_positions' rule on the
    // renumbered table: "earlier" = taken, "largest-numbered" = taken last).
    const Wedge* w_begin = wedge + slot[v].first;
    const Wedge* w_end = wedge + slot[v + 1].first;
    std::int64_t sum[3] = {0, 0, 0}, ends[3] = {0, 0, 0};
    std::int64_t cand[kMaxSelect][3], cand_ends[kMaxSelect][3];  // select: the first ones
    unsigned count = 0, act_sum = 0, act_n = 0;
    for (const Wedge* we = w_begin; we != w_end; ++we) {
      const Slot& sa = slot[we->a];
      const Slot& sb = slot[we->b];
      const bool da = sa.order != kNone, db = sb.order != kNone;
      if (plan) {
        if (da) plan->act.push_back(sa.order);
        if (db) plan->act.push_back(sb.order);
      }
      // Selects, not branches: which ends are taken is a coin toss to the branch predictor.
      act_sum += (da ? sa.rlen : 0u) + (db ? sb.rlen : 0u);
      act_n += unsigned{da} + unsigned{db};
      // Taking v raises a wedge's untaken end when the other end is taken. a and b are not v,
      // so raising here, before v is taken, pushes the same vertices in the same order.
      if (da != db) {
        bump(da ? we->b : we->a);
        continue;
      }
      if (!da || we->c == kNone) continue;
      const Slot& sc = slot[we->c];
      if (sc.order == kNone) continue;
      for (int x = 0; x < 3; ++x) {
        const std::int64_t ab = std::int64_t{sa.q[x]} + std::int64_t{sb.q[x]};
        sum[x] += ab - std::int64_t{sc.q[x]};
        ends[x] += ab;  // predictor 4's centroid: the parallelograms' shared edges
        if (select && count < kMaxSelect) {
          cand[count][x] = ab - std::int64_t{sc.q[x]};
          cand_ends[count][x] = ab;
        }
      }
      ++count;
    }
    const unsigned activity = act_n ? (act_sum + act_n / 2) / act_n : last_rlen;
    QPoint p{0, 0, 0};
    std::uint32_t neighbour = kNone;
    if (select && count >= 2) {
      const unsigned m = std::min(count, kMaxSelect);
      // Candidates ranked by |2c − a − b|², how far their opposite vertex c lies from the
      // middle of their edge ab (stable; |2c − a − b| < 2^31 on a 30-bit grid, so the sum
      // fits): on a quad grid the parallelogram across a quad's diagonal (c nearer the
      // middle) predicts the quad's fourth corner, the one across a grid edge a diagonal
      // neighbour instead, so the masks' probabilities concentrate on the low bits.
      std::uint64_t spread[kMaxSelect];
      for (unsigned j = 0; j < m; ++j) {
        spread[j] = 0;
        for (int x = 0; x < 3; ++x) {
          const std::int64_t d = cand_ends[j][x] - 2 * cand[j][x];
          spread[j] += static_cast<std::uint64_t>(d * d);
        }
      }
      for (unsigned j = 1; j < m; ++j)
        for (unsigned i = j; i > 0 && spread[i] < spread[i - 1]; --i) {
          std::swap(spread[i], spread[i - 1]);
          for (int x = 0; x < 3; ++x) {
            std::swap(cand[i][x], cand[i - 1][x]);
            std::swap(cand_ends[i][x], cand_ends[i - 1][x]);
          }
        }
      auto predict_subset = [&](unsigned mask) {
        std::int64_t s[3] = {0, 0, 0}, e[3] = {0, 0, 0};
        unsigned used = 0;
        for (unsigned j = 0; j < m; ++j) {
          if (!((mask >> j) & 1u)) continue;
          for (int x = 0; x < 3; ++x) s[x] += cand[j][x], e[x] += cand_ends[j][x];
          ++used;
        }
        const unsigned k = used == 1 ? blend.one : blend.many;
        QPoint r;
        for (int x = 0; x < 3; ++x)
          r[x] = k == 0 ? rounded_mean(s[x], used, reader.top())
                        : blended_mean(s[x], e[x], used, k, reader.top());
        return r;
      };
      p = predict_subset(reader.choose(v, m, count, activity, predict_subset));
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
      std::uint32_t neighbour_order = 0;
      for (const Wedge* we = w_begin; we != w_end; ++we)
        for (const std::uint32_t x : {we->a, we->b})
          if (slot[x].order != kNone && (neighbour == kNone || slot[x].order > neighbour_order))
            neighbour = x, neighbour_order = slot[x].order;
      if (neighbour == kNone && i > 0) neighbour = seq[i - 1];
      if (neighbour != kNone) p = {slot[neighbour].q[0], slot[neighbour].q[1], slot[neighbour].q[2]};
    }
    if (plan) {
      DegreePlan::Step& st = plan->steps.emplace_back();
      for (int x = 0; x < 3; ++x) st.sum[x] = sum[x], st.ends[x] = ends[x];
      st.count = count;
      st.fallback = count == 0 && neighbour != kNone ? slot[neighbour].order : kNone;
      st.act_begin = static_cast<std::uint32_t>(plan->act.size() - (act_n));
    }
    Slot& sv = slot[v];
    last_rlen = code(reader, v, p, count, activity, sv.q);
    sv.rlen = static_cast<std::uint8_t>(last_rlen);
    sv.order = i;
    seq[i] = v;
  }
  reserve_huge(q, n);
  q.resize(n);
  for (std::uint32_t i = 0; i < nc; ++i) {
    const Slot& s = slot[seq[i]];
    q[i] = {s.q[0], s.q[1], s.q[2]};
  }
  {
    // Renumber through a dense map (a quarter of the records' size, so it stays in cache).
    std::uint32_t* const new_id = scratch.array<std::uint32_t>(0, nc);  // over the dead wedges
    for (std::uint32_t i = 0; i < nc; ++i) new_id[seq[i]] = i;
    for (std::uint32_t& v : t.vertex) v = new_id[v];
  }
  if (anchored && n > nc) {
    // Each isolated vertex is predicted by its anchor, a connected vertex (the nearest, in
    // the encoder), coded as the gap from the previous one: scan points left out of the
    // surface lie close to it. The encoder codes them in anchor order and says so in seq.
    std::vector<std::uint32_t> anchors, by_anchor;
    if constexpr (requires { reader.truth(0); }) {
      std::vector<QPoint> points(n - nc);
      for (std::size_t w = nc; w < n; ++w)
        points[w - nc] = reader.truth(static_cast<std::uint32_t>(w));
      anchors = nearest_sites(std::span<const QPoint>(q.data(), nc), points);
      by_anchor.resize(points.size());
      for (std::uint32_t k = 0; k < by_anchor.size(); ++k) by_anchor[k] = k;
      std::stable_sort(by_anchor.begin(), by_anchor.end(),
                       [&](std::uint32_t a, std::uint32_t b) { return anchors[a] < anchors[b]; });
    }
    GammaModel gaps;
    std::uint64_t at = 0;
    seq.reserve(n);
    for (std::size_t w = nc; w < n; ++w) {
      std::uint32_t src = static_cast<std::uint32_t>(w), gap = 0;
      if (!by_anchor.empty()) {
        const std::uint32_t k = by_anchor[w - nc];
        src = nc + k;
        gap = static_cast<std::uint32_t>(anchors[k] - at);
      }
      reader.anchor(gaps, at, nc, gap);
      const QPoint p = q[static_cast<std::size_t>(at)];
      last_rlen = code(reader, src, p, 0, last_rlen, q[w].data());
      seq.push_back(src);
    }
    return seq;
  }
  // Isolated vertices follow in stream order, predicted from the previous vertex.
  for (std::size_t w = nc; w < n; ++w) {
    const QPoint p = w > 0 ? q[w - 1] : QPoint{0, 0, 0};
    last_rlen = code(reader, static_cast<std::uint32_t>(w), p, 0, last_rlen, q[w].data());
  }
  return seq;
}

template <class Coder>
std::vector<std::uint32_t> degree_pass(CornerTable& t, std::size_t n, Coder& coder,
                                       std::vector<QPoint>& q, Blend blend, BlendProbe* probe,
                                       bool select, bool anchored, DegreePlan* plan,
                                       Scratch& scratch) {
  return select ? degree_pass_as<true>(t, n, coder, q, blend, probe, anchored, plan, scratch)
                : degree_pass_as<false>(t, n, coder, q, blend, probe, anchored, plan, scratch);
}

}  // namespace

std::size_t degree_scratch_bytes(std::size_t n_corners, std::size_t n_vertices) {
  return slots_at(n_corners) + (n_vertices + 1) * sizeof(Slot);
}

std::vector<std::uint32_t> decode_positions_degree(CornerTable& table, std::size_t n, unsigned bits,
                                                   RansDecoder& rans, BitReader& raw,
                                                   std::vector<QPoint>& q, Predictor predictor,
                                                   Blend blend, bool anchor_isolated,
                                                   Scratch* scratch) {
  const bool select = predictor == Predictor::kMultiParallelogramSelect;
  ResidualReader reader(bits, rans, raw,
                        select || predictor == Predictor::kMultiParallelogramBlend);
  Scratch own;
  return degree_pass(table, n, reader, q, blend, nullptr, select, select && anchor_isolated,
                     nullptr, scratch ? *scratch : own);
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
  return plan.seq;
}

}  // namespace geom::codec::detail
