#include <geom/compress/rans.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <string>

namespace geom::codec {

AdaptiveModel::AdaptiveModel(unsigned n_symbols) : n_(n_symbols), groups_((n_symbols + 14) / 16) {
  if (n_symbols < 2 || n_symbols > kMaxSymbols)
    throw InvalidArgument("AdaptiveModel: alphabet size must be in [2, 64], got " +
                          std::to_string(n_symbols));
  for (unsigned s = 0; s < n_; ++s) counts_[s] = 1;
  // Symbol n_ − 1 ends at 2^15, and so do the symbols past the alphabet: find() may read
  // whole groups of boundaries. rebuild() writes only the boundaries that move.
  bound_.fill(static_cast<std::int16_t>(kProbScale - 1));
  // Start with frequent rebuilds so the model learns quickly, then back off to keep the
  // per-symbol cost of rebuilding small.
  interval_ = 8;
  rebuild();
}

void AdaptiveModel::rebuild() {
  detail::rebuild_cumulative(counts_.data(), n_, cum_.data());
  for (unsigned s = 0; s + 1 < n_; ++s) bound_[s] = static_cast<std::int16_t>(cum_[s + 1] - 1);
  interval_ = std::min<std::uint32_t>(interval_ * 2, detail::kModelMaxInterval);
  until_rebuild_ = interval_;
}

namespace {
constexpr std::uint32_t kRansLow = 1u << 23;
constexpr std::uint32_t kFlatTag = 0x8000;
}  // namespace

void RansEncoder::encode_flat(std::uint32_t value, unsigned bits) {
  entries_.push_back((value << 16) | kFlatTag | bits);
}

std::vector<std::uint8_t> RansEncoder::finish() const {
  std::vector<std::uint8_t> out;
  out.reserve(entries_.size() / 2 + 16);
  // Backwards, so that the decoder reads each symbol's renormalisation bytes right after
  // decoding it on its lane.
  std::uint32_t lane[2] = {kRansLow, kRansLow};
  for (std::size_t i = entries_.size(); i-- > 0;) {
    const std::uint32_t e = entries_[i];
    std::uint32_t& x = lane[i & 1];
    const std::uint32_t start = e >> 16;
    if (e & kFlatTag) {
      const unsigned bits = e & 0xff;
      const std::uint32_t x_max = (kRansLow >> bits) << 8;
      while (x >= x_max) {
        out.push_back(static_cast<std::uint8_t>(x));
        x >>= 8;
      }
      x = (x << bits) | start;
    } else {
      const std::uint32_t freq = e & 0xffff;
      const std::uint32_t x_max = ((kRansLow >> kProbBits) << 8) * freq;
      while (x >= x_max) {
        out.push_back(static_cast<std::uint8_t>(x));
        x >>= 8;
      }
      x = ((x / freq) << kProbBits) + (x % freq) + start;
    }
  }
  for (int l = 1; l >= 0; --l)
    for (int i = 0; i < 4; ++i) {
      out.push_back(static_cast<std::uint8_t>(lane[l]));
      lane[l] >>= 8;
    }
  std::reverse(out.begin(), out.end());
  return out;
}

RansDecoder::RansDecoder(std::span<const std::uint8_t> bytes, std::uint64_t base, unsigned lanes)
    : data_(bytes.data()), next_(data_), end_(data_ + bytes.size()), last_quad_(data_),
      base_(base), two_lanes_(lanes == 2) {
  if (lanes != 1 && lanes != 2)
    throw InvalidArgument("RansDecoder: 1 or 2 lanes, got " + std::to_string(lanes));
  const std::size_t state_bytes = two_lanes_ ? 8 : 4;
  if (bytes.size() < state_bytes)
    fail(two_lanes_ ? "rANS stream shorter than its two 4-byte states"
                    : "rANS stream shorter than its 4-byte state");
  last_quad_ = end_ - 4;
  x_ = load_be32(data_);
  y_ = two_lanes_ ? load_be32(data_ + 4) : kLow;
  next_ = data_ + state_bytes;
  // An encoder's states stay in [2^23, 2^31); the fast renormalisation counts on it.
  constexpr std::uint32_t kHigh = 1u << 31;
  if (x_ < kLow || y_ < kLow || x_ >= kHigh || y_ >= kHigh) fail("rANS initial state out of range");
}

std::uint32_t RansDecoder::decode_flat(unsigned bits) {
  const std::uint32_t x = x_, v = x & ((1u << bits) - 1);
  next_state(renormalised(x >> bits));
  return v;
}

void RansDecoder::finish() const {
  if (next_ != end_ || x_ != kLow || y_ != kLow) fail("rANS stream does not end where the encoder finished");
}

void RansDecoder::fail_at(std::uint64_t offset, const char* what) {
  throw DecodeError(offset, std::string(what) + " at byte " + std::to_string(offset));
}

void BitReader::fail_at(std::uint64_t offset) {
  throw DecodeError(offset, "raw bit stream ends early at byte " + std::to_string(offset));
}

void GammaModel::encode(RansEncoder& rans, BitWriter& raw, std::uint32_t value) {
  const unsigned len = static_cast<unsigned>(std::bit_width(value));
  rans.encode(lengths_, len);
  if (len >= 2) raw.put(value & ((1u << (len - 1)) - 1), len - 1);
}

std::uint32_t GammaModel::decode(RansDecoder& rans, BitReader& raw) {
  const unsigned len = rans.decode(lengths_);
  if (len < 2) return len;
  return (1u << (len - 1)) | raw.get(len - 1);
}

void ByteWriter::u32(std::uint32_t v) {
  for (int i = 0; i < 4; ++i) bytes_.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

void ByteWriter::f64(double v) {
  std::uint64_t b;
  std::memcpy(&b, &v, 8);
  for (int i = 0; i < 8; ++i) bytes_.push_back(static_cast<std::uint8_t>(b >> (8 * i)));
}

void ByteWriter::varint(std::uint64_t v) {
  while (v >= 0x80) {
    bytes_.push_back(static_cast<std::uint8_t>(v | 0x80));
    v >>= 7;
  }
  bytes_.push_back(static_cast<std::uint8_t>(v));
}

std::uint8_t ByteReader::u8() {
  if (remaining() < 1) fail("unexpected end of stream (need 1 byte)");
  return bytes_[pos_++];
}

std::uint32_t ByteReader::u32() {
  if (remaining() < 4) fail("unexpected end of stream (need 4 bytes)");
  std::uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= std::uint32_t{bytes_[pos_ + i]} << (8 * i);
  pos_ += 4;
  return v;
}

double ByteReader::f64() {
  if (remaining() < 8) fail("unexpected end of stream (need 8 bytes)");
  std::uint64_t b = 0;
  for (int i = 0; i < 8; ++i) b |= std::uint64_t{bytes_[pos_ + i]} << (8 * i);
  pos_ += 8;
  double v;
  std::memcpy(&v, &b, 8);
  return v;
}

std::uint64_t ByteReader::varint() {
  std::uint64_t v = 0;
  for (unsigned shift = 0; shift < 64; shift += 7) {
    const std::uint8_t b = u8();
    v |= static_cast<std::uint64_t>(b & 0x7f) << shift;
    if (!(b & 0x80)) return v;
  }
  fail("varint longer than 10 bytes");
}

std::span<const std::uint8_t> ByteReader::take(std::uint64_t n) {
  if (n > remaining())
    fail("section of " + std::to_string(n) + " bytes exceeds the " +
         std::to_string(remaining()) + " bytes left");
  auto s = bytes_.subspan(pos_, static_cast<std::size_t>(n));
  pos_ += static_cast<std::size_t>(n);
  return s;
}

}  // namespace geom::codec
