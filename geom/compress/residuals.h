#pragma once
/// \file
/// Residual coding shared by the predictors that code in traversal order (predict.cpp) and
/// the degree-order pass (predict_degree.cpp); internal to geom/compress.

#include <geom/compress/point_chain.h>
#include <geom/compress/predict.h>
#include <geom/compress/rans.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace geom::codec::detail {

inline constexpr unsigned kLengthClasses = 12;

/// Bits below the leading one that are modelled (the rest are close to uniform).
inline unsigned modelled_bits(unsigned len) { return len <= 2 ? (len == 2 ? 1 : 0) : 2; }

/// Residual models. A residual's bit length is coded adaptively in a context of its axis,
/// how many parallelograms backed the prediction (more ⇒ smaller residuals) and the length
/// of the previous residual (errors are locally correlated); the first bit below the
/// leading one is modelled too, the rest are raw. Length models have 33 symbols (0–32), or
/// (predictor 4) only the bits + 2 lengths a grid residual can have: every symbol keeps a
/// minimum frequency, so 20 unused ones cost about 0.03 bits per residual.
struct ResidualModels {
  std::vector<AdaptiveModel> length;
  /// The modelled bits below the leading one (modelled_bits(len)), per axis and length:
  /// top[axis * 33 + len] has one symbol for lengths 0 and 1 (certain: coded on both sides
  /// for its lane turn, costing no byte), two for length 2 and four for lengths 3 … 32. One model
  /// type for every length, so that the decoder runs the same steps whatever the length:
  /// branches on it mispredicted about twice a vertex. Fixed alphabets, so the decoder's
  /// symbol search is three compares.
  std::vector<TinyModel> top;  // (a vector: an over-aligned member would over-align the
                               //  coders holding the models)
  /// kMultiParallelogramSelect's subset masks, one model per number of candidates (2 … 4).
  std::vector<AdaptiveModel> subset;
  explicit ResidualModels(unsigned n_lengths = 33)
      : length(3 * 3 * kLengthClasses, AdaptiveModel(n_lengths)) {
    top.reserve(3 * 33);
    for (unsigned axis = 0; axis < 3; ++axis)
      for (unsigned len = 0; len <= 32; ++len) top.emplace_back(len < 2 ? 1 : len == 2 ? 2 : 4);
    for (unsigned m = 2; m <= kMaxSelect; ++m) subset.emplace_back((1u << m) - 1);
  }
  /// Codes the modelled bits of a residual z of length len whose lowest rb bits are raw
  /// (rb = 0 below length 2). Lengths 0 and 1 code their certain symbol too: the decoder
  /// reads one for every residual, and each symbol takes its turn on the rANS lanes.
  void encode_top(RansEncoder& rans, unsigned axis, unsigned len, std::uint32_t z, unsigned rb) {
    rans.encode(top[axis * 33 + len], len < 2 ? 0u : (z >> rb) & (len == 2 ? 1u : 3u));
  }
  /// Codes what follows a residual's length len: its modelled bits (encode_top), then the
  /// raw ones. The one sequence every position coder runs, so that all code the same turns.
  void encode_below_length(RansEncoder& rans, BitWriter& raw, unsigned axis, unsigned len,
                           std::uint32_t z) {
    const unsigned rb = len >= 2 ? len - 1 - modelled_bits(len) : 0;
    encode_top(rans, axis, len, z, rb);
    if (len >= 2) raw.put(z & ((1u << rb) - 1), rb);
  }
};

/// −log2(f / 2^15) for every frequency f ≤ 2^15: what a symbol of frequency f costs, for the
/// encoder's choices (a table, since the subset search asks for it a dozen times a vertex).
inline float symbol_bits(std::uint32_t f) {
  static const std::vector<float> table = [] {
    std::vector<float> t(kProbScale + 1);
    t[0] = float(kProbBits + 1);  // never coded: models keep every frequency ≥ kMinFreq
    for (std::uint32_t i = 1; i <= kProbScale; ++i) t[i] = float(kProbBits) - std::log2(float(i));
    return t;
  }();
  return table[f];
}


/// The residual length context: the neighbours' mean residual length (local roughness),
/// blended with this vertex's previous axis once one is known.
inline unsigned context(unsigned axis, unsigned count, unsigned prev_len, unsigned activity) {
  const unsigned cc = count > 2 ? 2 : count;
  const unsigned blend = axis == 0 ? activity : (prev_len + activity + 1) / 2;
  const unsigned pl = blend >= kLengthClasses ? kLengthClasses - 1 : blend;
  return (axis * 3 + cc) * kLengthClasses + pl;
}


/// Decodes a vertex's three residuals onto its prediction (shared by both decoders).
class ResidualReader {
 public:
  ResidualReader(unsigned bits, RansDecoder& rans, BitReader& raw, bool compact = false)
      : m_(compact ? bits + 2 : 33), rans_(rans), raw_(raw),
        top_(static_cast<std::uint32_t>((std::uint64_t{1} << bits) - 1)), bits_(bits) {}
  std::uint32_t top() const { return top_; }
  /// Writes the decoded grid point to out; returns the largest residual length.
  unsigned read(const QPoint& p, unsigned count, unsigned activity, std::uint32_t* out) {
    return rans_.lanes() == 2 ? read_on<2>(p, count, activity, out)
                              : read_on<1>(p, count, activity, out);
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
  template <unsigned kLanes>
  unsigned read_on(const QPoint& p, unsigned count, unsigned activity, std::uint32_t* out) {
    // context()'s terms that do not depend on the axis, hoisted.
    AdaptiveModel* const length = m_.length.data() + (count > 2 ? 2 : count) * kLengthClasses;
    TinyModel* const top = m_.top.data();
    std::uint32_t point[3];  // stored to out at the end: out may alias the models' counts
    // The coders as locals, stored back at the end: through the references their states
    // were stored and reloaded around every decode, since the models' count stores might
    // alias them (4% of a read's instructions, with the lane count fixed per read).
    RansDecoder rans = rans_;
    BitReader raw = raw_;
    const std::uint32_t grid_top = top_;
    unsigned longest = 0, prev = prev_len_;
#pragma GCC unroll 3
    for (unsigned x = 0; x < 3; ++x) {
      const unsigned blend = x == 0 ? activity : (prev + activity + 1) / 2;
      const unsigned pl = blend >= kLengthClasses ? kLengthClasses - 1 : blend;
      // The length models have at most 33 symbols, so len ≤ 32.
      const unsigned len = rans.template decode_on<kLanes>(length[x * 3 * kLengthClasses + pl]);
      // z = the leading one, the modelled bits below it, then rb raw bits; lengths 0 and 1
      // are the values 0 and 1 (their certain symbol decodes as 0). No branch on len.
      const std::uint32_t high = rans.template decode_on<kLanes>(top[x * 33 + len]);
      const unsigned rb = len > 3 ? len - 3 : 0;  // modelled_bits(len) = 2 from length 3
      const std::uint32_t lead = len > 2 ? 4 : len;
      const std::uint32_t z = ((lead | high) << rb) | raw.get(rb);
      // Zigzag: even z are z / 2, odd z are −(z + 1) / 2. A point below 0 wraps above top_.
      const std::int64_t r = std::int64_t{z >> 1} ^ -std::int64_t{z & 1u};
      const auto v = static_cast<std::uint64_t>(std::int64_t{p[x]} + r);
      if (v > grid_top) {
        rans_.resume(rans);  // for the offset in the message
        fail(("decoded position off the " + std::to_string(bits_) + "-bit grid").c_str());
      }
      point[x] = static_cast<std::uint32_t>(v);
      prev = len;
      longest = std::max(longest, len);
    }
    prev_len_ = prev;
    rans_.resume(rans);
    raw_.resume(raw);
    for (unsigned x = 0; x < 3; ++x) out[x] = point[x];
    return longest;
  }
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
      m_.encode_below_length(rans_, raw_, x, len, z);
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

/// floor(a / b) for b > 0 (C++ division truncates towards zero).
template <class T>
inline T floor_div(T a, T b) {
  const T d = a / b;
  return (a % b != 0 && a < 0) ? d - 1 : d;
}

/// The coders' common step, so that one pass template serves the decoder and the encoder.
inline unsigned code(ResidualReader& r, std::uint32_t, const QPoint& p, unsigned count,
                     unsigned activity, std::uint32_t* out) {
  return r.read(p, count, activity, out);
}
inline unsigned code(ResidualWriter& w, std::uint32_t v, const QPoint& p, unsigned count,
                     unsigned activity, std::uint32_t* out) {
  return w.code(v, p, count, activity, out);
}

/// kMultiParallelogramSelect's prediction of vertex v with count ≥ 2 parallelograms, whose
/// first min(count, kMaxSelect) are cand (a + b − c) and cand_ends (a + b), in the order met:
/// ranks them, lets the coder choose (and code) the subset, and returns its prediction.
/// Shared by the degree-order and growth-order passes; the arrays are reordered.
template <class Coder>
QPoint predict_select(Coder& reader, std::uint32_t v, std::int64_t (&cand)[kMaxSelect][3],
                      std::int64_t (&cand_ends)[kMaxSelect][3], unsigned count, unsigned activity,
                      Blend blend) {
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
  return predict_subset(reader.choose(v, m, count, activity, predict_subset));
}

/// The isolated vertices q[nc ..) after the connected ones q[0 .. nc) (FORMAT.md, Geometry),
/// in either pass. Chained: in stream order, each predicted from the previous vertex.
/// Anchored: each predicted by its anchor, a connected vertex (the nearest, in the encoder)
/// coded as the gap from the previous one, since scan points left out of the surface lie
/// close to it; the encoder codes them in anchor order and appends the vertex coded at each
/// stream position to seq.
template <class Coder>
void code_isolated(Coder& coder, std::vector<QPoint>& q, std::size_t nc, bool anchored,
                   unsigned last_rlen, std::vector<std::uint32_t>& seq) {
  const std::size_t n = q.size();
  if (!anchored || n == nc) {
    for (std::size_t w = nc; w < n; ++w) {
      const QPoint p = w > 0 ? q[w - 1] : QPoint{0, 0, 0};
      last_rlen = code(coder, static_cast<std::uint32_t>(w), p, 0, last_rlen, q[w].data());
    }
    return;
  }
  std::vector<std::uint32_t> anchors, by_anchor;
  if constexpr (requires { coder.truth(0); }) {
    std::vector<QPoint> points(n - nc);
    for (std::size_t w = nc; w < n; ++w) points[w - nc] = coder.truth(static_cast<std::uint32_t>(w));
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
      src = static_cast<std::uint32_t>(nc) + k;
      gap = static_cast<std::uint32_t>(anchors[k] - at);
    }
    coder.anchor(gaps, at, static_cast<std::uint32_t>(nc), gap);
    const QPoint p = q[static_cast<std::size_t>(at)];
    last_rlen = code(coder, src, p, 0, last_rlen, q[w].data());
    seq.push_back(src);
  }
}

}  // namespace geom::codec::detail
