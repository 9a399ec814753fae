#pragma once
/// \file
/// Entropy coding for the geom mesh codec: a byte-wise rANS coder driven by adaptive
/// frequency models, a raw bit stream for the bits no model can predict, and bounds-checked
/// byte readers that throw DecodeError with the absolute byte offset.
///
/// Ref: J. Duda, "Asymmetric numeral systems: entropy coding combining speed of Huffman
/// coding with compression rate of arithmetic coding", arXiv:1311.2540, 2013.
/// F. Giesen, "Interleaved entropy coders", arXiv:1402.0765, 2014 (byte-wise renormalisation).

#include <geom/core/errors.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstring>
#include <cstdint>
#include <span>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace geom::codec {

/// Probabilities are 15-bit fixed point: every model's frequencies sum to 2^15.
inline constexpr unsigned kProbBits = 15;
inline constexpr std::uint32_t kProbScale = 1u << kProbBits;
/// Smallest frequency any symbol gets after a rebuild. It bounds the most likely symbol's
/// probability by 1 − (n−1)·kMinFreq/2^15, so every symbol costs a positive number of bits and
/// a stream of B bytes holds a bounded number of symbols (the decoder's allocation bound).
inline constexpr std::uint32_t kMinFreq = 32;
/// Largest alphabet an AdaptiveModel accepts.
inline constexpr unsigned kMaxSymbols = 64;

namespace detail {
inline constexpr std::uint32_t kModelIncrement = 32;
inline constexpr std::uint32_t kModelCountLimit = 1u << 16;
inline constexpr std::uint32_t kModelMaxInterval = 1024;

/// The rebuild every adaptive model shares: counts[0..n) (halved first when their total
/// passes kModelCountLimit) become frequencies of at least kMinFreq summing to 2^15, the
/// most frequent symbol taking the rounding slack; cum[0..n] receives their running sums.
template <class Cum>
void rebuild_cumulative(std::uint32_t* counts, unsigned n, Cum* cum) {
  std::uint32_t total = 0;
  for (unsigned s = 0; s < n; ++s) total += counts[s];
  if (total > kModelCountLimit) {
    // Halving keeps the model responsive to drift and keeps products below 2^32.
    total = 0;
    for (unsigned s = 0; s < n; ++s) {
      counts[s] = (counts[s] + 1) / 2;
      total += counts[s];
    }
  }
  const std::uint32_t spread = kProbScale - n * kMinFreq;
  std::uint32_t sum = 0;
  unsigned best = 0;
  std::array<std::uint32_t, kMaxSymbols> f{};
  for (unsigned s = 0; s < n; ++s) {
    f[s] = kMinFreq +
           static_cast<std::uint32_t>(static_cast<std::uint64_t>(counts[s]) * spread / total);
    sum += f[s];
    if (counts[s] > counts[best]) best = s;
  }
  f[best] += kProbScale - sum;
  cum[0] = 0;
  for (unsigned s = 0; s < n; ++s) cum[s + 1] = static_cast<Cum>(cum[s] + f[s]);
}
}  // namespace detail

/// An adaptive frequency model over symbols 0..n−1. Counts grow as symbols are coded and the
/// 15-bit cumulative table is rebuilt at fixed, doubling intervals, so encoder and decoder
/// stay in lock step without per-symbol renormalisation.
class AdaptiveModel {
 public:
  /// Pre: 2 ≤ n_symbols ≤ kMaxSymbols. Throws: InvalidArgument otherwise.
  explicit AdaptiveModel(unsigned n_symbols = 2);

  unsigned size() const { return n_; }
  std::uint32_t start(unsigned s) const { return cum_[s]; }
  std::uint32_t freq(unsigned s) const { return cum_[s + 1] - cum_[s]; }
  /// The symbol whose interval holds slot (slot < 2^15): the number of boundaries at or
  /// below it, counted branch-free (a scan's exit branch would mispredict often).
  unsigned find(std::uint32_t slot) const {
#if defined(__SSE2__)
    // Sixteen boundaries per step: the comparisons' byte mask is a run of ones from bit 0
    // (boundaries ascend), so the symbol is the run's length. The lane past the last real
    // boundary never compares true, so the complement has a set bit.
    const __m128i s = _mm_set1_epi16(static_cast<short>(slot));
    const auto* b = reinterpret_cast<const __m128i*>(bound_.data());
    auto group = [&](unsigned g) {
      const __m128i lo = _mm_cmpgt_epi16(s, _mm_load_si128(b + 2 * g));
      const __m128i hi = _mm_cmpgt_epi16(s, _mm_load_si128(b + 2 * g + 1));
      return static_cast<unsigned>(_mm_movemask_epi8(_mm_packs_epi16(lo, hi)));
    };
    if (groups_ == 1) [[likely]]  // up to 17 symbols: every alphabet but 33-symbol lengths
      return static_cast<unsigned>(__builtin_ctz(~group(0)));  // ~: bit 16 up are set
    if (groups_ == 2)  // up to 33 symbols; 64 bits, so that the complement has a set bit
      return static_cast<unsigned>(
          __builtin_ctzll(~(std::uint64_t{group(1)} << 16 | group(0))));
    std::uint64_t below = 0;
    for (unsigned g = 0; g < groups_; ++g) below |= std::uint64_t{group(g)} << (16 * g);
    return static_cast<unsigned>(std::countr_one(below));
#else
    unsigned s = 0;
    for (unsigned i = 0; i < 16 * groups_; ++i) s += unsigned(bound_[i] < std::int32_t(slot));
    return s;
#endif
  }
  /// Account for one coded symbol.
  void update(unsigned s) {
    counts_[s] += detail::kModelIncrement;
    if (--until_rebuild_ == 0) rebuild();
  }

 private:
  void rebuild();

  /// bound_[i] = cum_[i + 1] − 1, the last slot of symbol i, for the decoder's find (not part
  /// of the format). Entries from n_ − 1 on are 2^15 − 1, above every slot; 16-bit signed, so
  /// that SSE2 compares eight at once.
  alignas(16) std::array<std::int16_t, kMaxSymbols> bound_{};
  unsigned n_;
  unsigned groups_;  // 16-entry groups of bound_ that find() reads: ceil((n_ − 1) / 16)
  std::uint32_t until_rebuild_;
  std::uint32_t interval_;
  std::array<std::uint32_t, kMaxSymbols + 1> cum_{};
  std::array<std::uint32_t, kMaxSymbols> counts_{};
};

/// An AdaptiveModel of a fixed, small alphabet (N ≤ 8) that codes exactly the same: the
/// same counts, rebuilds and frequencies. Its hot state fits one cache line, so a coder with
/// hundreds of contexts (the connectivity gates) keeps them all in L1.
template <unsigned N>
class alignas(64) SmallModel {
  static_assert(N >= 2 && N <= 8);
  static_assert(2 + 16 <= 2 * (N + 1) + 4 + 4 * N, "find() reads 16 bytes from cum_[1]");

 public:
  SmallModel() {
    counts_.fill(1);
    rebuild();
  }
  static constexpr unsigned size() { return N; }
  std::uint32_t start(unsigned s) const { return cum_[s]; }
  std::uint32_t freq(unsigned s) const { return std::uint32_t{cum_[s + 1]} - cum_[s]; }
  unsigned find(std::uint32_t slot) const {
#if defined(__SSE2__)
    if constexpr (N >= 6) {
      // One compare of cum_[1 … 8] (boundaries ascend, so the lanes at or below slot are
      // a run from lane 0; lane N − 1 holds 2^15, which ends the run before the lanes past
      // cum_, the next members' bytes). cum ≤ slot ⇔ the saturating cum − slot is 0.
      __m128i cum;
      std::memcpy(&cum, reinterpret_cast<const unsigned char*>(this) + 2, 16);
      const __m128i left = _mm_subs_epu16(cum, _mm_set1_epi16(static_cast<short>(slot)));
      const auto below = static_cast<unsigned>(
          _mm_movemask_epi8(_mm_cmpeq_epi16(left, _mm_setzero_si128())));
      return static_cast<unsigned>(__builtin_ctz(~below)) / 2;
    }
#endif
    unsigned s = 0;
    for (unsigned i = 1; i < N; ++i) s += cum_[i] <= slot;
    return s;
  }
  void update(unsigned s) {
    counts_[s] += detail::kModelIncrement;
    if (--until_rebuild_ == 0) rebuild();
  }

 private:
  void rebuild() {
    detail::rebuild_cumulative(counts_.data(), N, cum_.data());
    interval_ = static_cast<std::uint16_t>(
        std::min<std::uint32_t>(interval_ * 2u, detail::kModelMaxInterval));
    until_rebuild_ = interval_;
  }
  std::array<std::uint16_t, N + 1> cum_{};  // ≤ 2^15; first, at offset 0, for find()
  std::uint16_t until_rebuild_ = 0;
  std::uint16_t interval_ = 8;
  std::array<std::uint32_t, N> counts_{};
};

/// An adaptive model of 1, 2 or 4 symbols chosen at run time that codes exactly as
/// SmallModel<2> or SmallModel<4> (same counts, rebuilds and frequencies). One type for
/// the alphabets lets a decoder pick the model by a decoded value without a branch on it.
/// With one symbol, which is certain (frequency 2^15), coding leaves the rANS state as it
/// was and costs no byte; it still takes its lane's turn, so the encoder codes it wherever
/// the decoder runs it.
class alignas(32) TinyModel {
 public:
  /// Pre: n_symbols is 1, 2 or 4.
  explicit TinyModel(unsigned n_symbols = 1) : n_(static_cast<std::uint8_t>(n_symbols)) {
    cum_.fill(kProbScale);  // the boundaries past the alphabet: above every slot
    counts_.fill(1);
    rebuild();
  }
  unsigned size() const { return n_; }
  std::uint32_t start(unsigned s) const { return cum_[s]; }
  std::uint32_t freq(unsigned s) const { return std::uint32_t{cum_[s + 1]} - cum_[s]; }
  unsigned find(std::uint32_t slot) const {
    return unsigned{cum_[1] <= slot} + unsigned{cum_[2] <= slot} + unsigned{cum_[3] <= slot};
  }
  void update(unsigned s) {
    counts_[s] += detail::kModelIncrement;
    if (--until_rebuild_ == 0) rebuild();
  }

 private:
  void rebuild() {  // as SmallModel's
    detail::rebuild_cumulative(counts_.data(), n_, cum_.data());
    interval_ = static_cast<std::uint16_t>(
        std::min<std::uint32_t>(interval_ * 2u, detail::kModelMaxInterval));
    until_rebuild_ = interval_;
  }
  std::array<std::uint16_t, 5> cum_{};
  std::uint16_t until_rebuild_ = 0;
  std::uint16_t interval_ = 8;
  std::uint8_t n_;
  std::array<std::uint32_t, 4> counts_{};
};

/// Collects symbols in coding order and writes them as one rANS stream at finish(). rANS is
/// last-in first-out, so symbols are buffered and coded in reverse; the models adapt in
/// forward order on both sides. Symbol i is coded on state (lane) i mod 2, both lanes
/// renormalising into the one byte stream (Giesen's interleaving), so that the decoder can
/// overlap consecutive symbols.
class RansEncoder {
 public:
  template <class Model>  // AdaptiveModel, SmallModel or TinyModel
  void encode(Model& model, unsigned s) {
    // A certain symbol (frequency 2^15) reads as a flat symbol of 0 bits: the same step,
    // which leaves the state as it is and still takes its lane's turn.
    entries_.push_back((model.start(s) << 16) | model.freq(s));
    model.update(s);
  }
  /// Code a value below 2^bits (bits ≤ 15) with a flat distribution.
  void encode_flat(std::uint32_t value, unsigned bits);
  std::size_t symbols() const { return entries_.size(); }
  /// Room for n symbols, so a long stream does not copy its buffer as it grows.
  void reserve(std::size_t n) { entries_.reserve(n); }
  /// Forget the symbols, keeping the buffer (an encoder reused for several trial codings).
  void clear() { entries_.clear(); }
  /// The coded bytes: the two lanes' final states (lane 0 first, 4 bytes each, big-endian)
  /// followed by the renormalisation bytes.
  std::vector<std::uint8_t> finish() const;

 private:
  // start << 16 | freq; flat symbols use freq < 2^15 with a tag in bit 15 of freq.
  std::vector<std::uint32_t> entries_;
};

/// Reads a stream written by RansEncoder. Every byte read is checked against the end of the
/// buffer; `base` is the stream's offset in the whole buffer, for error messages.
class RansDecoder {
 public:
  /// lanes: 2 for the streams RansEncoder writes, 1 for those of encoders before two-lane
  /// streams (FORMAT.md, flag TWO_LANES). Throws: DecodeError when the buffer cannot hold the
  /// initial states or one is outside [2^23, 2^31); InvalidArgument for other lane counts.
  RansDecoder(std::span<const std::uint8_t> bytes, std::uint64_t base, unsigned lanes = 2);

  template <class Model>  // AdaptiveModel, SmallModel or TinyModel
  unsigned decode(Model& model) {
    return decode_on<0>(model);
  }
  /// Continues from where `copy`, a copy of this decoder, stopped (a caller decodes a run of
  /// symbols through a local copy, whose states the compiler can keep in registers).
  void resume(const RansDecoder& copy) {
    next_ = copy.next_;
    x_ = copy.x_;
    y_ = copy.y_;
  }
  /// Lanes in use: 1 or 2 (see the constructor).
  unsigned lanes() const { return two_lanes_ ? 2 : 1; }
  /// decode() with the lane count known at compile time (kLanes = lanes(); 0: read it per
  /// symbol), for a caller that tests it once for many symbols.
  template <unsigned kLanes, class Model>
  unsigned decode_on(Model& model) {
    const std::uint32_t x = x_, slot = x & (kProbScale - 1);
    const unsigned s = model.find(slot);
    const std::uint32_t freq = model.freq(s), start = model.start(s);
    // The model's update first: its stores could alias the states, which then stay in
    // registers through the renormalisation.
    model.update(s);
    next_state<kLanes>(renormalised(freq * (x >> kProbBits) + slot - start));
    return s;
  }
  std::uint32_t decode_flat(unsigned bits);
  /// Throws: DecodeError unless the stream ended exactly where the encoder finished (every
  /// byte consumed and every state back at its initial value): catches most corruption.
  void finish() const;
  /// Absolute byte offset of the next unread byte (for error messages).
  std::uint64_t offset() const { return base_ + static_cast<std::uint64_t>(next_ - data_); }

 private:
  static constexpr std::uint32_t kLow = 1u << 23;
  // After a symbol x ≥ 2^8 (x ≥ 2^23 before, freq ≥ 32, flat bits ≤ 15), so at most two
  // bytes are due. Whether one is due is a coin toss to the branch predictor, so away from
  // the end of the stream the next four bytes are appended below x, shifted up by the bytes
  // due, and all but those dropped again, instead of looping byte by byte.
  // x is the state after the symbol; returns it renormalised.
  std::uint32_t renormalised(std::uint32_t x) {
    if (next_ <= last_quad_) [[likely]] {
      // x − 2^23 and x − 2^15 are negative (top bit set) exactly when a byte is due: x < 2^31.
      const unsigned n = ((x - kLow) >> 31) + ((x - (kLow >> 8)) >> 31);
      const std::uint64_t wide = (std::uint64_t{x} << 32) | load_be32(next_);
      next_ += n;
      return static_cast<std::uint32_t>((wide << (8 * n)) >> 32);
    }
    while (x < kLow) {
      if (next_ >= end_) fail_at(offset(), "rANS stream ends early");
      x = (x << 8) | *next_++;
    }
    return x;
  }
  // Symbols take turns on the lanes: x_ decodes this one, y_ the next. With two, a symbol's
  // decode waits for its own lane's state only, not for the renormalisation of the symbol
  // before it, so consecutive symbols overlap (decode CPU 5-8% lower on the 1M mesh). The
  // branch goes the same way for a whole stream.
  template <unsigned kLanes = 0>
  void next_state(std::uint32_t x) {
    if (kLanes == 2 || (kLanes == 0 && two_lanes_)) {
      x_ = y_;
      y_ = x;
    } else {
      x_ = x;
    }
  }
  static std::uint32_t load_be32(const std::uint8_t* p) {
    std::uint32_t v;
    std::memcpy(&v, p, 4);  // one load; the bytes are big-endian on the wire
    if constexpr (std::endian::native == std::endian::little) v = __builtin_bswap32(v);
    return v;
  }
  [[noreturn]] void fail(const char* what) const { fail_at(offset(), what); }
  // Static, so that a decoder copied into a local (see ResidualReader::read) keeps its
  // address to itself and its members in registers.
  [[noreturn]] static void fail_at(std::uint64_t offset, const char* what);

  const std::uint8_t* data_;  // the stream's first byte (offsets are counted from it)
  const std::uint8_t* next_;  // the next unread byte
  const std::uint8_t* end_;
  const std::uint8_t* last_quad_;  // end_ − 4: the last place four bytes can be read from
  std::uint64_t base_;
  std::uint32_t x_ = 0, y_ = 0;
  bool two_lanes_;
};

/// Little-endian bit stream for raw bits (least significant first).
class BitWriter {
 public:
  /// Pre: bits ≤ 32 and value < 2^bits.
  void put(std::uint32_t value, unsigned bits) {
    if (bits == 0) return;
    acc_ |= static_cast<std::uint64_t>(value) << fill_;
    fill_ += bits;
    while (fill_ >= 8) {
      bytes_.push_back(static_cast<std::uint8_t>(acc_));
      acc_ >>= 8;
      fill_ -= 8;
    }
  }
  std::vector<std::uint8_t> finish() {
    if (fill_ > 0) bytes_.push_back(static_cast<std::uint8_t>(acc_));
    acc_ = 0;
    fill_ = 0;
    return std::move(bytes_);
  }

 private:
  std::vector<std::uint8_t> bytes_;
  std::uint64_t acc_ = 0;
  unsigned fill_ = 0;
};

class BitReader {
 public:
  BitReader(std::span<const std::uint8_t> bytes, std::uint64_t base)
      : data_(bytes.data()), size_(bytes.size()), base_(base) {}
  /// Continues from where `copy`, a copy of this reader, stopped (see RansDecoder::resume).
  void resume(const BitReader& copy) {
    pos_ = copy.pos_;
    acc_ = copy.acc_;
    fill_ = copy.fill_;
  }
  /// Throws: DecodeError when the stream has fewer than `bits` bits left.
  /// No test for bits = 0, which reads nothing as it is: the residual reader asks for 0 or
  /// more bits without a branch on which.
  std::uint32_t get(unsigned bits) {
    if (fill_ < bits) refill(bits);
    const std::uint32_t v = static_cast<std::uint32_t>(acc_ & ((std::uint64_t{1} << bits) - 1));
    acc_ >>= bits;
    fill_ -= bits;
    return v;
  }

 private:
  // Away from the end, eight bytes are loaded at once and as many whole ones kept as fit:
  // a byte-at-a-time loop's exit is unpredictable (residual widths vary vertex to vertex).
  void refill(unsigned bits) {
    if (pos_ + 8 <= size_) [[likely]] {
      std::uint64_t word = 0;
      for (unsigned i = 0; i < 8; ++i) word |= std::uint64_t{data_[pos_ + i]} << (8 * i);
      acc_ |= word << fill_;
      pos_ += (63 - fill_) >> 3;
      fill_ |= 56;
      return;
    }
    while (fill_ < bits) {
      if (pos_ >= size_) fail_at(base_ + pos_);
      acc_ |= static_cast<std::uint64_t>(data_[pos_++]) << fill_;
      fill_ += 8;
    }
  }
  [[noreturn]] static void fail_at(std::uint64_t offset);  // static: see RansDecoder::fail_at
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  std::uint64_t base_;
  // fill_ valid bits; any above them are copies of the next bytes (refill ORs them again).
  std::uint64_t acc_ = 0;
  unsigned fill_ = 0;
};

/// An unsigned integer of any size coded as its bit length (adaptive, 33 symbols) followed
/// by the bits below the leading one (raw). Cheap for the small values the codec expects,
/// bounded (≤ 15 + 31 bits) for any value.
class GammaModel {
 public:
  GammaModel() : lengths_(33) {}
  void encode(RansEncoder& rans, BitWriter& raw, std::uint32_t value);
  std::uint32_t decode(RansDecoder& rans, BitReader& raw);

 private:
  AdaptiveModel lengths_;
};

/// Byte-level writer: little-endian integers and LEB128 varints.
class ByteWriter {
 public:
  void u8(std::uint8_t v) { bytes_.push_back(v); }
  void u32(std::uint32_t v);
  void f64(double v);
  void varint(std::uint64_t v);
  void append(std::span<const std::uint8_t> b) { bytes_.insert(bytes_.end(), b.begin(), b.end()); }
  std::vector<std::uint8_t>& bytes() { return bytes_; }

 private:
  std::vector<std::uint8_t> bytes_;
};

/// Byte-level reader over a whole buffer; every read is checked and failures name the offset.
class ByteReader {
 public:
  explicit ByteReader(std::span<const std::uint8_t> bytes) : bytes_(bytes) {}
  std::uint8_t u8();
  std::uint32_t u32();
  double f64();
  std::uint64_t varint();
  /// The next n bytes as a span. Throws: DecodeError when fewer remain.
  std::span<const std::uint8_t> take(std::uint64_t n);
  std::size_t offset() const { return pos_; }
  std::size_t remaining() const { return bytes_.size() - pos_; }
  [[noreturn]] void fail(const std::string& what) const { throw DecodeError(pos_, what); }

 private:
  std::span<const std::uint8_t> bytes_;
  std::size_t pos_ = 0;
};

}  // namespace geom::codec
