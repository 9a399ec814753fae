#pragma once
#include <algorithm>
// Helpers shared by the io tests: reading from string literals and exact soup comparison.

#include <geom/io/io.h>

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <string_view>

namespace geom::test {

/// Append v's bytes to s, big-endian when `big` (for hand-made binary files).
template <class T>
void put(std::string& s, T v, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big) std::reverse(b, b + sizeof(T));
  s.append(b, sizeof(T));
}

inline std::span<const std::byte> bytes(std::string_view s) {
  return {reinterpret_cast<const std::byte*>(s.data()), s.size()};
}

inline PolygonSoup parse(std::string_view text, FileFormat format, const std::string& name = "test") {
  return read_soup(bytes(text), format, name);
}

inline std::string write_string(const PolygonSoup& soup, FileFormat format, const WriteOptions& options = {}) {
  auto b = write_soup(soup, format, options);
  return std::string(reinterpret_cast<const char*>(b.data()), b.size());
}

/// Bitwise equality of doubles (distinguishes -0 and +0, equates identical NaNs).
inline bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

template <class V>
::testing::AssertionResult same_vectors(const std::vector<V>& a, const std::vector<V>& b, const char* what) {
  if (a.size() != b.size())
    return ::testing::AssertionFailure() << what << ": sizes " << a.size() << " vs " << b.size();
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < V::SizeAtCompileTime; ++k)
      if (!same_bits(a[i][k], b[i][k]))
        return ::testing::AssertionFailure() << what << "[" << i << "][" << k << "]: " << a[i][k] << " vs "
                                             << b[i][k];
  return ::testing::AssertionSuccess();
}

/// Positions bit-exact, faces identical.
inline ::testing::AssertionResult same_geometry(const PolygonSoup& a, const PolygonSoup& b) {
  auto r = same_vectors(a.positions, b.positions, "positions");
  if (!r) return r;
  if (a.face_offsets != b.face_offsets) return ::testing::AssertionFailure() << "face_offsets differ";
  if (a.face_indices != b.face_indices) return ::testing::AssertionFailure() << "face_indices differ";
  return ::testing::AssertionSuccess();
}

/// Two small test meshes: a quad-and-triangle "house" with awkward coordinates.
inline PolygonSoup house() {
  PolygonSoup s;
  s.positions = {{0.1, 0.2, 0.3}, {1.0 / 3.0, -0.0, 1e-300}, {1e300, 2.5, -7.25},
                 {-0.1, 0.7, 123456789.123456789}, {5e-324, 0.5, 0.25}};
  s.add_face({0, 1, 2, 3});
  s.add_face({3, 2, 4});
  return s;
}

/// A float-exact tetrahedron (as a binary format would read it).
inline PolygonSoup tetra() {
  PolygonSoup s;
  s.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1.5}};
  s.add_face({0, 2, 1});
  s.add_face({0, 1, 3});
  s.add_face({1, 2, 3});
  s.add_face({2, 0, 3});
  return s;
}

}  // namespace geom::test
