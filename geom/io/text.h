#pragma once
/// \file
/// Internal to geom/io: a bounds-checked text scanner with line tracking, a fast decimal
/// parser (exact fast path, std::from_chars for everything else) and shortest round-trip
/// formatting. Not installed API; readers include it from their .cpp files.

#include <geom/core/errors.h>

#include <charconv>
#include <cstdio>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <string_view>

namespace geom::io_detail {

/// Parse a decimal floating-point number starting at p (no leading blanks). On success
/// returns the end of the number and stores the value; on failure returns nullptr.
/// Correctly rounded: the fast path is taken only when the result is exact (Clinger).
const char* parse_double(const char* p, const char* end, double& out);
/// Parse an optionally signed decimal integer; nullptr on failure or overflow.
const char* parse_int(const char* p, const char* end, std::int64_t& out);

/// Append the shortest decimal string that reads back as exactly `v`.
void append_double(std::string& out, double v);
void append_float(std::string& out, float v);
void append_int(std::string& out, std::int64_t v);

/// True when v is exactly a float (NaN and infinities count as floats). Decided on the bit
/// pattern: GCC 12's SLP vectoriser at -O2/-O3 folds (double)(float)x back to x, so the
/// obvious cast round trip cannot be trusted.
inline bool is_float_exact(double v) {
  std::uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  const int exp = static_cast<int>((bits >> 52) & 0x7ff);
  const std::uint64_t mant = bits & ((std::uint64_t{1} << 52) - 1);
  if (exp == 0x7ff) return true;
  if (exp == 0) return mant == 0;  // double subnormals are far below the float range
  const int e = exp - 1023;
  if (e > 127 || e < -149) return false;
  const int kept = e >= -126 ? 23 : 23 - (-126 - e);  // float subnormals keep fewer bits
  return (mant & ((std::uint64_t{1} << (52 - kept)) - 1)) == 0;
}

/// v rounded to the nearest float, as a double; opaque to the optimiser (see above).
inline double round_to_float(double v) {
  volatile float f = static_cast<float>(v);
  return static_cast<double>(f);
}

inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

/// A cursor over text with the current 1-based line number, for error messages.
class TextCursor {
 public:
  TextCursor(std::span<const std::byte> data, const std::string& name)
      : p_(reinterpret_cast<const char*>(data.data())), end_(p_ + data.size()), name_(name) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw ParseError(name_, ParseError::Unit::kLine, line_, what);
  }
  [[noreturn]] void fail_at(std::uint64_t line, const std::string& what) const {
    throw ParseError(name_, ParseError::Unit::kLine, line, what);
  }

  bool at_end() const { return p_ >= end_; }
  std::uint64_t line() const { return line_; }
  const char* pos() const { return p_; }
  const char* end() const { return end_; }
  void set_pos(const char* p) { p_ = p; }
  void set_line(std::uint64_t line) { line_ = line; }
  const std::string& name() const { return name_; }

  /// Skip blanks within the line; a backslash before the newline continues the line.
  void skip_blanks() {
    for (;;) {
      while (p_ < end_ && is_blank(*p_)) ++p_;
      if (p_ < end_ && *p_ == '\\') {
        const char* q = p_ + 1;
        while (q < end_ && *q == '\r') ++q;
        if (q < end_ && *q == '\n') {
          p_ = q + 1;
          ++line_;
          continue;
        }
      }
      return;
    }
  }
  /// Blanks and newlines (and '#' comments when `comments`).
  void skip_space(bool comments) {
    for (;;) {
      while (p_ < end_ && (is_blank(*p_) || *p_ == '\n')) {
        if (*p_ == '\n') ++line_;
        ++p_;
      }
      if (comments && p_ < end_ && *p_ == '#') {
        skip_line();
        continue;
      }
      return;
    }
  }
  /// True at end of line, end of input or a '#' comment.
  bool at_eol() const { return p_ >= end_ || *p_ == '\n' || *p_ == '#'; }
  /// Move past the next newline.
  void skip_line() {
    const void* nl = p_ < end_ ? std::memchr(p_, '\n', static_cast<std::size_t>(end_ - p_)) : nullptr;
    if (!nl) {
      p_ = end_;
      return;
    }
    p_ = static_cast<const char*>(nl) + 1;
    ++line_;
  }
  /// The next blank-delimited word on this line (empty at end of line).
  std::string_view word() {
    skip_blanks();
    const char* s = p_;
    while (p_ < end_ && !is_blank(*p_) && *p_ != '\n') ++p_;
    return {s, static_cast<std::size_t>(p_ - s)};
  }
  /// The next token as a double; fails naming `what` when it is absent or not a number.
  double number(const char* what) {
    skip_blanks();
    double v;
    const char* q = parse_double(p_, end_, v);
    if (!q || (q < end_ && !is_delim(*q))) bad_token(what);
    p_ = q;
    return v;
  }
  /// Like number() but returns false at end of line instead of failing.
  bool try_number(double& v, const char* what) {
    skip_blanks();
    if (at_eol()) return false;
    v = number(what);
    return true;
  }
  std::int64_t integer(const char* what) {
    skip_blanks();
    std::int64_t v;
    const char* q = parse_int(p_, end_, v);
    if (!q || (q < end_ && !is_delim(*q))) bad_token(what);
    p_ = q;
    return v;
  }
  [[noreturn]] void bad_token(const char* what) const {
    const char* s = p_;
    const char* e = s;
    while (e < end_ && !is_blank(*e) && *e != '\n' && e - s < 40) ++e;
    if (s == e) fail(std::string("expected ") + what + ", found end of line");
    fail(std::string("expected ") + what + ", found '" + printable(std::string_view(s, e - s)) + "'");
  }
  static std::string printable(std::string_view s) {
    std::string out;
    for (char c : s) {
      if (static_cast<unsigned char>(c) >= 32 && static_cast<unsigned char>(c) < 127) {
        out += c;
      } else {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\x%02x", static_cast<unsigned char>(c));
        out += buf;
      }
    }
    return out;
  }

 private:
  static bool is_delim(char c) { return is_blank(c) || c == '\n' || c == '#'; }
  const char* p_;
  const char* end_;
  std::uint64_t line_ = 1;
  const std::string& name_;
};

/// Binary reading with byte offsets in errors.
class ByteCursor {
 public:
  ByteCursor(std::span<const std::byte> data, const std::string& name)
      : data_(reinterpret_cast<const unsigned char*>(data.data())), size_(data.size()), name_(name) {}
  [[noreturn]] void fail(const std::string& what) const { fail_at(pos_, what); }
  [[noreturn]] void fail_at(std::uint64_t at, const std::string& what) const {
    throw ParseError(name_, ParseError::Unit::kByte, at, what);
  }
  std::size_t pos() const { return pos_; }
  std::size_t size() const { return size_; }
  std::size_t remaining() const { return size_ - pos_; }
  void seek(std::size_t p) { pos_ = p; }
  const unsigned char* ptr() const { return data_ + pos_; }
  void need(std::size_t n, const char* what) const {
    if (remaining() < n)
      fail("file ends inside " + std::string(what) + " (" + std::to_string(n) + " bytes needed, " +
           std::to_string(remaining()) + " left)");
  }
  void skip(std::size_t n) { pos_ += n; }

 private:
  const unsigned char* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
  const std::string& name_;
};

template <class T>
inline T load_le(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}
template <class T>
inline T load_be(const unsigned char* p) {
  unsigned char b[sizeof(T)];
  for (std::size_t i = 0; i < sizeof(T); ++i) b[i] = p[sizeof(T) - 1 - i];
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}
template <class T>
inline void store_le(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

/// Checked conversion of a header count: fails unless count × min_bytes fits in what is left.
inline bool count_fits(std::uint64_t count, std::uint64_t min_bytes_each, std::uint64_t remaining) {
  if (min_bytes_each == 0) return count <= remaining + 1;
  return count <= remaining / min_bytes_each;
}

}  // namespace geom::io_detail
