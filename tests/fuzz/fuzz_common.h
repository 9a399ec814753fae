#pragma once
// Shared body of the reader fuzzers: malformed input may only end in ParseError; anything a
// reader accepts must survive a write and a read back with identical geometry.

#include "fuzz_check.h"

#include <geom/io/io.h>

#include <cstdint>
#include <cstring>
#include <optional>
#include <span>

namespace geom::fuzz {

inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

inline void round_trip(const PolygonSoup& s, FileFormat format, bool binary, bool exact_faces) {
  WriteOptions o;
  o.binary = binary;
  const std::vector<std::byte> bytes = write_soup(s, format, o);  // must not throw
  const PolygonSoup r = read_soup(bytes, format, "round-trip");    // must not throw
  FUZZ_CHECK(r.positions.size() == s.positions.size());
  for (std::size_t i = 0; i < s.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) FUZZ_CHECK(same_bits(r.positions[i][k], s.positions[i][k]));
  if (exact_faces) {
    FUZZ_CHECK(r.face_offsets == s.face_offsets);
    FUZZ_CHECK(r.face_indices == s.face_indices);
  }
}

/// The reader's soup, or nullopt after a ParseError (the only failure allowed). A soup
/// that is returned must satisfy what the writers require.
inline std::optional<PolygonSoup> read(const std::uint8_t* data, std::size_t size, FileFormat format) {
  PolygonSoup soup;
  try {
    soup = read_soup(std::span<const std::byte>(reinterpret_cast<const std::byte*>(data), size), format, "fuzz");
  } catch (const ParseError&) {
    return std::nullopt;
  }
  FUZZ_CHECK(soup.face_offsets.empty() || soup.face_offsets.back() == soup.face_indices.size());
  for (std::uint32_t i : soup.face_indices) FUZZ_CHECK(i < soup.positions.size());
  for (const auto& p : soup.positions) FUZZ_CHECK(p.allFinite());
  return soup;
}

}  // namespace geom::fuzz
