#pragma once
// The .gmc stream's constants and the small helpers that its writer (encode.cpp) and its
// reader (codec.cpp) share. FORMAT.md is the specification.

#include <geom/compress/predict.h>
#include <geom/compress/rans.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace geom::codec::detail {

inline constexpr std::uint8_t kMagic[4] = {'G', 'M', 'C', 0x1A};
// Version 2 adds the attribute flags and fields; streams without attributes stay version 1.
// Encoders since TWO_LANES set it in every stream, so decoders from before reject their
// streams by that flag rather than misreading them.
inline constexpr std::uint8_t kVersion = 1;
inline constexpr std::uint8_t kVersionAttributes = 2;
inline constexpr std::uint8_t kFlagPreserveOrder = 1;
inline constexpr std::uint8_t kFlagPolygons = 2;
inline constexpr std::uint8_t kFlagLeftFirst = 4;
inline constexpr std::uint8_t kFlagNormals = 8;
inline constexpr std::uint8_t kFlagTexcoords = 16;
// Per-corner and generic attributes, a block after every other section (extension.h).
inline constexpr std::uint8_t kFlagExtension = 128;
// Every rANS section of the stream interleaves two states (rans.h, FORMAT.md); without it,
// one (the streams of earlier encoders).
inline constexpr std::uint8_t kFlagTwoLanes = 32;
inline constexpr std::uint8_t kKnownFlags = 31 | kFlagTwoLanes | kFlagExtension;
// The flags a version 1 stream may have.
inline constexpr std::uint8_t kKnownFlagsV1 = 7 | kFlagTwoLanes;
/// The rANS lanes of a stream with these flags.
inline unsigned rans_lanes(std::uint8_t flags) { return (flags & kFlagTwoLanes) ? 2 : 1; }
// Conforming streams cannot hold more than this many triangles per connectivity byte or
// vertices per geometry byte (kMinFreq bounds every symbol's cost from below; FORMAT.md).
inline constexpr std::uint64_t kMaxTrianglesPerByte = 2048;
inline constexpr std::uint64_t kMaxVerticesPerByte = 64;

struct Streams {
  std::vector<std::uint8_t> rans, raw;
  std::size_t size() const { return rans.size() + raw.size(); }
};

/// A section: its byte length (varint), then its bytes.
inline void write_section(ByteWriter& w, const std::vector<std::uint8_t>& s) {
  w.varint(s.size());
  w.append(s);
}

inline std::uint32_t zigzag(std::int64_t d) {
  return static_cast<std::uint32_t>(d >= 0 ? 2 * d : -2 * d - 1);
}
inline std::int64_t unzigzag(std::uint32_t z) {
  return (z & 1u) ? -static_cast<std::int64_t>(z >> 1) - 1 : static_cast<std::int64_t>(z >> 1);
}

/// Predictors 4–7 weigh the blend byte and have bits + 2 length symbols.
inline bool blended(Predictor p) {
  return p == Predictor::kMultiParallelogramBlend || p == Predictor::kMultiParallelogramSelect ||
         p == Predictor::kGrowthBlend || p == Predictor::kGrowthSelect;
}
/// Predictors 5 and 7 code a subset of the parallelograms (and have the isolated byte).
inline bool selecting(Predictor p) {
  return p == Predictor::kMultiParallelogramSelect || p == Predictor::kGrowthSelect;
}
/// Predictors 6 and 7 code in growth order (and have the deadline byte).
inline bool growth(Predictor p) {
  return p == Predictor::kGrowthBlend || p == Predictor::kGrowthSelect;
}
/// Predictors 3–5 renumber the vertices by the degree order.
inline bool by_degree(Predictor p) {
  return p == Predictor::kMultiParallelogramDegree || p == Predictor::kMultiParallelogramBlend ||
         p == Predictor::kMultiParallelogramSelect;
}

}  // namespace geom::codec::detail
