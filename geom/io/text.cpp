#include <geom/io/text.h>

#include <cmath>
#include <limits>

namespace geom::io_detail {
namespace {

constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                             1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                             1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

bool is_digit(char c) { return static_cast<unsigned>(c - '0') < 10u; }

}  // namespace

const char* parse_double(const char* p, const char* end, double& out) {
  const char* start = p;
  bool negative = false;
  if (p < end && (*p == '-' || *p == '+')) {
    negative = *p == '-';
    ++p;
  }
  const char* digits_start = p;
  std::uint64_t mantissa = 0;
  int significant = 0;  // digits accumulated into mantissa (leading zeros excluded)
  int exponent = 0;     // decimal exponent to apply to mantissa
  bool truncated = false;
  bool any_digit = false;
  while (p < end && is_digit(*p)) {
    any_digit = true;
    if (significant < 19) {
      mantissa = mantissa * 10 + static_cast<unsigned>(*p - '0');
      if (mantissa) ++significant;
    } else {
      ++exponent;
      if (*p != '0') truncated = true;
    }
    ++p;
  }
  if (p < end && *p == '.') {
    ++p;
    while (p < end && is_digit(*p)) {
      any_digit = true;
      if (significant < 19) {
        mantissa = mantissa * 10 + static_cast<unsigned>(*p - '0');
        if (mantissa) ++significant;
        --exponent;
      } else if (*p != '0') {
        truncated = true;
      }
      ++p;
    }
  }
  if (!any_digit) {
    // "nan", "inf", "infinity" and anything else unusual: let the library decide.
    p = digits_start;
    if (p < end && (*p == 'n' || *p == 'N' || *p == 'i' || *p == 'I')) {
      auto r = std::from_chars(p, end, out);
      if (r.ec != std::errc()) return nullptr;
      if (negative) out = -out;
      return r.ptr;
    }
    return nullptr;
  }
  if (p < end && (*p == 'e' || *p == 'E')) {
    const char* q = p + 1;
    bool eneg = false;
    if (q < end && (*q == '-' || *q == '+')) {
      eneg = *q == '-';
      ++q;
    }
    if (q < end && is_digit(*q)) {
      int e = 0;
      while (q < end && is_digit(*q)) {
        if (e < 100000) e = e * 10 + (*q - '0');
        ++q;
      }
      exponent += eneg ? -e : e;
      p = q;
    }
  }
  if (!truncated && mantissa <= (std::uint64_t{1} << 53) && exponent >= -22 && exponent <= 22) {
    double v = static_cast<double>(mantissa);
    v = exponent < 0 ? v / kPow10[-exponent] : v * kPow10[exponent];
    out = negative ? -v : v;
    return p;
  }
#if (defined(__x86_64__) || defined(__i386__)) && __LDBL_MANT_DIG__ == 64
  // Up to 19 digits (what shortest round-trip output of float data needs): the x87 64-bit
  // significand holds the mantissa and 10^|e| (e <= 27) exactly, so one correctly rounded
  // extended operation has error <= 1/2 ulp(extended). Rounding that to double is then
  // correct unless it landed exactly on a halfway point between two doubles (low 11 bits
  // of the significand == 0x400), which the slow path settles.
  if (!truncated && exponent >= -27 && exponent <= 27 && mantissa != 0) {
    static constexpr long double kPow10L[] = {
        1e0L,  1e1L,  1e2L,  1e3L,  1e4L,  1e5L,  1e6L,  1e7L,  1e8L,  1e9L,
        1e10L, 1e11L, 1e12L, 1e13L, 1e14L, 1e15L, 1e16L, 1e17L, 1e18L, 1e19L,
        1e20L, 1e21L, 1e22L, 1e23L, 1e24L, 1e25L, 1e26L, 1e27L};
    const long double m = static_cast<long double>(mantissa);
    const long double r = exponent < 0 ? m / kPow10L[-exponent] : m * kPow10L[exponent];
    std::uint64_t significand;
    std::memcpy(&significand, &r, sizeof significand);
    if ((significand & 0x7ff) != 0x400) {
      const double v = static_cast<double>(r);
      out = negative ? -v : v;
      return p;
    }
  }
#endif
  // Slow but correctly rounded path for long mantissas and large exponents.
  const char* s = start;
  if (s < end && *s == '+') ++s;
  auto r = std::from_chars(s, p, out);
  if (r.ec == std::errc::result_out_of_range) {
    // Overflow becomes infinity (rejected by callers that need finite values); underflow 0.
    out = exponent > 0 ? std::numeric_limits<double>::infinity() : 0.0;
    if (negative) out = -out;
    return p;
  }
  if (r.ec != std::errc() || r.ptr != p) return nullptr;
  return p;
}

const char* parse_int(const char* p, const char* end, std::int64_t& out) {
  bool negative = false;
  if (p < end && (*p == '-' || *p == '+')) {
    negative = *p == '-';
    ++p;
  }
  if (p >= end || !is_digit(*p)) return nullptr;
  std::uint64_t v = 0;
  while (p < end && is_digit(*p)) {
    v = v * 10 + static_cast<unsigned>(*p - '0');
    if (v > (std::uint64_t{1} << 62)) return nullptr;
    ++p;
  }
  out = negative ? -static_cast<std::int64_t>(v) : static_cast<std::int64_t>(v);
  return p;
}

void append_double(std::string& out, double v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

void append_float(std::string& out, float v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

void append_int(std::string& out, std::int64_t v) {
  char buf[24];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}

}  // namespace geom::io_detail
