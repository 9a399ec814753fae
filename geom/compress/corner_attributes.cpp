#include <geom/compress/corner_attributes.h>

#include <algorithm>
#include <bit>
#include <string>
#include <type_traits>

namespace geom::codec::detail {

namespace {

constexpr unsigned kLengthClasses = 12;
// How a wedge was predicted: parallelogram(s) in its chart, a corner of one of its
// triangles, another wedge of its vertex, or nothing nearby. Each has its own residual
// statistics (parallelograms are tight, the vertex's other wedge lies across a seam).
constexpr unsigned kKinds = 4;

struct Models {
  AdaptiveModel seam[3] = {AdaptiveModel(2), AdaptiveModel(2), AdaptiveModel(2)};
  std::vector<AdaptiveModel> length =
      std::vector<AdaptiveModel>(kKinds * 2 * kLengthClasses, AdaptiveModel(33));
  std::vector<AdaptiveModel> top;
  Models() {
    top.reserve(2 * 33);
    for (unsigned i = 0; i < 2 * 33; ++i) top.emplace_back(i % 33 <= 2 ? 2 : 4);
  }
};

// The two sides share one walk; the encoder passes the value it knows and gets it back, the
// decoder ignores the argument and returns what it reads.
struct Writer {
  RansEncoder& rans;
  BitWriter& raw;
  unsigned symbol(AdaptiveModel& m, unsigned s) {
    rans.encode(m, s);
    return s;
  }
  std::uint32_t bits(std::uint32_t v, unsigned n) {
    raw.put(v, n);
    return v;
  }
  std::uint64_t offset() const { return 0; }
};

struct Reader {
  RansDecoder& rans;
  BitReader& raw;
  unsigned symbol(AdaptiveModel& m, unsigned) { return rans.decode(m); }
  std::uint32_t bits(std::uint32_t, unsigned n) { return raw.get(n); }
  std::uint64_t offset() const { return rans.offset(); }
};

std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]];
    x = parent[x];
  }
  return x;
}

/// The walk over seams, wedges and values, shared by encoder and decoder.
template <class Io>
class Walk {
 public:
  Walk(const CornerTable& t, unsigned bits, Io& io, std::vector<Grid2>& q)
      : t_(t), io_(io), q_(q), top_(static_cast<std::uint32_t>((std::uint64_t{1} << bits) - 1)) {}

  std::size_t run() {
    code_seams();
    build_wedges();
    code_values();
    return n_wedges_;
  }

 private:
  bool diagonal(std::uint32_t c) const { return !t_.diagonal.empty() && t_.diagonal[c]; }

  void code_seams() {
    const auto nc = static_cast<std::uint32_t>(t_.vertex.size());
    seam_.assign(nc, 1);  // boundary edges join nothing
    for (std::uint32_t c = 0; c < nc; ++c) {
      const std::uint32_t o = t_.opposite[c];
      if (o == kNone || o < c) continue;
      if (diagonal(c)) {
        seam_[c] = seam_[o] = 0;
        continue;
      }
      // Seams run in chains: count the seams already known on the other edges of both
      // triangles.
      unsigned near = 0;
      for (std::uint32_t k : {next_corner(c), prev_corner(c), next_corner(o), prev_corner(o)}) {
        const std::uint32_t ko = t_.opposite[k];
        if (ko != kNone && std::min(k, ko) < c && seam_[k]) ++near;
      }
      unsigned s = 0;
      if constexpr (std::is_same_v<Io, Writer>)
        s = q_[next_corner(c)] != q_[prev_corner(o)] || q_[prev_corner(c)] != q_[next_corner(o)];
      s = io_.symbol(models_.seam[std::min(near, 2u)], s);
      seam_[c] = seam_[o] = static_cast<std::uint8_t>(s);
    }
  }

  void build_wedges() {
    const auto nc = static_cast<std::uint32_t>(t_.vertex.size());
    std::vector<std::uint32_t> parent(nc);
    for (std::uint32_t c = 0; c < nc; ++c) parent[c] = c;
    auto join = [&](std::uint32_t a, std::uint32_t b) {
      a = find_root(parent, a);
      b = find_root(parent, b);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    };
    for (std::uint32_t c = 0; c < nc; ++c) {
      const std::uint32_t o = t_.opposite[c];
      if (o == kNone || o < c || seam_[c]) continue;
      join(next_corner(c), prev_corner(o));
      join(prev_corner(c), next_corner(o));
    }
    // Wedges are numbered by their first corner, the order the decoder meets them.
    wedge_.assign(nc, kNone);
    std::vector<std::uint32_t> id(nc, kNone);
    n_wedges_ = 0;
    for (std::uint32_t c = 0; c < nc; ++c) {
      const std::uint32_t r = find_root(parent, c);
      if (id[r] == kNone) id[r] = n_wedges_++;
      wedge_[c] = id[r];
    }
    offset_.assign(n_wedges_ + 1, 0);
    for (std::uint32_t w : wedge_) ++offset_[w + 1];
    for (std::size_t i = 1; i < offset_.size(); ++i) offset_[i] += offset_[i - 1];
    corners_.resize(nc);
    std::vector<std::uint32_t> fill(offset_.begin(), offset_.end() - 1);
    for (std::uint32_t c = 0; c < nc; ++c) corners_[fill[wedge_[c]]++] = c;
  }

  /// Prediction of wedge w from wedges < w; returns its kind.
  unsigned predict(std::uint32_t w, Grid2& out) const {
    std::int64_t sum[2] = {0, 0};
    unsigned count = 0;
    std::uint32_t neighbour = kNone;
    for (std::uint32_t i = offset_[w]; i < offset_[w + 1]; ++i) {
      const std::uint32_t k = corners_[i];
      const std::uint32_t a = wedge_[next_corner(k)], b = wedge_[prev_corner(k)];
      if (neighbour == kNone) neighbour = a < w ? a : (b < w ? b : kNone);
      const std::uint32_t o = t_.opposite[k];
      if (a >= w || b >= w || o == kNone || seam_[k] || wedge_[o] >= w) continue;
      for (int x = 0; x < 2; ++x)
        sum[x] += std::int64_t{value_[a][x]} + std::int64_t{value_[b][x]} -
                  std::int64_t{value_[wedge_[o]][x]};
      ++count;
    }
    if (count > 0) {
      for (int x = 0; x < 2; ++x) {
        // Rounded mean with floor division, the same on both sides for negative sums.
        const std::int64_t num = 2 * sum[x] + count, den = 2 * std::int64_t{count};
        std::int64_t m = num / den;
        if (num % den != 0 && num < 0) --m;
        out[x] = static_cast<std::uint32_t>(std::clamp<std::int64_t>(m, 0, top_));
      }
      return 0;
    }
    if (neighbour != kNone) {
      out = value_[neighbour];
      return 1;
    }
    const std::uint32_t other = last_at_vertex_[t_.vertex[corners_[offset_[w]]]];
    if (other != kNone) {
      out = value_[other];
      return 2;
    }
    out = w > 0 ? value_[w - 1] : Grid2{0, 0};
    return 3;
  }

  void code_values() {
    value_.assign(n_wedges_, Grid2{0, 0});
    last_at_vertex_.assign(t_.n_vertices, kNone);
    unsigned last_len[kKinds] = {0, 0, 0, 0};
    for (std::uint32_t w = 0; w < n_wedges_; ++w) {
      Grid2 p;
      const unsigned kind = predict(w, p);
      unsigned prev = last_len[kind], widest = 0;
      for (unsigned x = 0; x < 2; ++x) {
        std::uint32_t z = 0;
        if constexpr (std::is_same_v<Io, Writer>) {
          const std::int64_t r = std::int64_t{q_[corners_[offset_[w]]][x]} - std::int64_t{p[x]};
          z = static_cast<std::uint32_t>(r >= 0 ? 2 * r : -2 * r - 1);
        }
        const unsigned blend = x == 0 ? prev : (prev + last_len[kind] + 1) / 2;
        const unsigned ctx = (kind * 2 + x) * kLengthClasses + std::min(blend, kLengthClasses - 1);
        const unsigned len = code_residual(ctx, x, z);
        const std::int64_t r =
            (z & 1u) ? -static_cast<std::int64_t>((z >> 1) + 1) : static_cast<std::int64_t>(z >> 1);
        const std::int64_t v = std::int64_t{p[x]} + r;
        if (v < 0 || v > top_)
          throw DecodeError(io_.offset(), "corner attribute off its grid near byte " +
                                              std::to_string(io_.offset()));
        value_[w][x] = static_cast<std::uint32_t>(v);
        prev = len;
        widest = std::max(widest, len);
      }
      last_len[kind] = widest;
      last_at_vertex_[t_.vertex[corners_[offset_[w]]]] = w;
    }
    if constexpr (std::is_same_v<Io, Reader>) {
      q_.resize(t_.vertex.size());
      for (std::size_t c = 0; c < q_.size(); ++c) q_[c] = value_[wedge_[c]];
    }
  }

  /// The residual's bit length (modelled), the bits below the leading one (the first two
  /// modelled, the rest raw), as the position coder does. Updates z on the decoding side.
  unsigned code_residual(unsigned ctx, unsigned axis, std::uint32_t& z) {
    const unsigned len = io_.symbol(models_.length[ctx], static_cast<unsigned>(std::bit_width(z)));
    if (len <= 1) {
      z = len;
      return len;
    }
    const unsigned mb = len == 2 ? 1 : 2, rb = len - 1 - mb;
    const std::uint32_t high =
        io_.symbol(models_.top[axis * 33 + len], (z >> rb) & ((1u << mb) - 1));
    const std::uint32_t low = io_.bits(rb > 0 ? z & ((1u << rb) - 1) : 0, rb);
    z = static_cast<std::uint32_t>((((std::uint64_t{1} << mb) | high) << rb) | low);
    return len;
  }

  const CornerTable& t_;
  Io& io_;
  std::vector<Grid2>& q_;
  std::uint32_t top_;
  Models models_;
  std::vector<std::uint8_t> seam_;    // per corner: the edge opposite is a seam or boundary
  std::vector<std::uint32_t> wedge_;  // per corner
  std::vector<std::uint32_t> offset_, corners_;  // wedge → corners (ascending)
  std::vector<Grid2> value_;                     // per wedge
  std::vector<std::uint32_t> last_at_vertex_;
  std::uint32_t n_wedges_ = 0;
};

}  // namespace

std::size_t encode_corner_values(const CornerTable& table, std::span<const Grid2> q, unsigned bits,
                                 RansEncoder& rans, BitWriter& raw) {
  std::vector<Grid2> values(q.begin(), q.end());
  Writer io{rans, raw};
  return Walk<Writer>(table, bits, io, values).run();
}

void decode_corner_values(const CornerTable& table, unsigned bits, RansDecoder& rans,
                          BitReader& raw, std::vector<Grid2>& q) {
  Reader io{rans, raw};
  q.clear();
  Walk<Reader>(table, bits, io, q).run();
}

}  // namespace geom::codec::detail
