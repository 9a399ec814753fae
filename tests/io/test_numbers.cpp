// The decimal parser agrees bit for bit with std::from_chars (the correctly rounded
// reference) on numbers of every length, including the 17-digit shortest forms of floats,
// and shortest formatting round-trips.

#include <geom/io/text.h>

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

namespace {

double reference(const std::string& s) {
  double v = 0;
  std::from_chars(s.data(), s.data() + s.size(), v);
  return v;
}

double ours(const std::string& s) {
  double v = -1;
  const char* end = geom::io_detail::parse_double(s.data(), s.data() + s.size(), v);
  EXPECT_EQ(end, s.data() + s.size()) << s;
  return v;
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST(Numbers, MatchesFromCharsOnRandomDecimals) {
  std::mt19937_64 rng(12345);
  for (int i = 0; i < 200000; ++i) {
    const int digits = 1 + static_cast<int>(rng() % 21);
    std::string s = rng() % 2 ? "-" : "";
    std::string mant;
    for (int d = 0; d < digits; ++d) mant += static_cast<char>('0' + rng() % 10);
    const int dot = static_cast<int>(rng() % (digits + 1));
    const std::string whole = dot == 0 ? std::string("0") : mant.substr(0, static_cast<std::size_t>(dot));
    s += whole;
    if (dot < digits) {
      s += '.';
      s.append(mant, static_cast<std::size_t>(dot));
    }
    if (rng() % 3 == 0) {
      s += 'e';
      s += std::to_string(static_cast<int>(rng() % 80) - 40);
    }
    ASSERT_TRUE(same_bits(ours(s), reference(s))) << s;
  }
}

TEST(Numbers, ShortestFormsOfFloatsAndDoublesRoundTrip) {
  std::mt19937_64 rng(777);
  for (int i = 0; i < 200000; ++i) {
    std::uint64_t bits = rng();
    double d;
    std::memcpy(&d, &bits, sizeof d);
    if (!std::isfinite(d)) continue;
    if (i % 2) {
      volatile float f = static_cast<float>(std::ldexp(static_cast<double>(rng() % 100000000) / 1e4, -static_cast<int>(rng() % 40)));
      d = f;
    }
    std::string s;
    geom::io_detail::append_double(s, d);
    ASSERT_TRUE(same_bits(ours(s), d)) << s;
  }
}

TEST(Numbers, HalfwayCasesAndSpecials) {
  // 2^53 + 1 is exactly halfway between two doubles: ties to even.
  EXPECT_TRUE(same_bits(ours("9007199254740993"), 9007199254740992.0));
  EXPECT_TRUE(same_bits(ours("9007199254740995"), 9007199254740996.0));
  EXPECT_TRUE(same_bits(ours("-0"), -0.0));
  EXPECT_TRUE(same_bits(ours("0.000"), 0.0));
  EXPECT_TRUE(same_bits(ours("1e-400"), 0.0));
  EXPECT_TRUE(std::isinf(ours("1e400")));
  EXPECT_TRUE(std::isnan(ours("nan")));
  EXPECT_TRUE(same_bits(ours("+2.5"), 2.5));
  double v;
  for (const char* bad : {"", "-", ".", "e5", "+", "x1"})
    EXPECT_EQ(geom::io_detail::parse_double(bad, bad + std::strlen(bad), v), nullptr) << bad;
}
