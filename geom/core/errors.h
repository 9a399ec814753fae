#pragma once
/// \file
/// The error types geom throws. Every message says what was expected and what was found.

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace geom {

/// Base of every error geom throws on purpose.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Malformed input data. Carries where: the file, and a line (text formats) or byte offset
/// (binary formats); zero means "not known".
class ParseError : public Error {
 public:
  enum class Unit { kNone, kLine, kByte };
  ParseError(std::string file, Unit unit, std::uint64_t where, const std::string& what);
  const std::string& file() const { return file_; }
  Unit unit() const { return unit_; }
  /// 1-based line or 0-based byte offset, per unit().
  std::uint64_t where() const { return where_; }

 private:
  std::string file_;
  Unit unit_;
  std::uint64_t where_;
};

/// An edit or input that would break mesh invariants; the message names the element.
class TopologyError : public Error {
 public:
  using Error::Error;
};

/// A caller passed an argument outside the documented domain.
class InvalidArgument : public Error {
 public:
  using Error::Error;
};

/// A compressed or streamed buffer that is truncated or corrupt; carries the byte offset.
class DecodeError : public Error {
 public:
  DecodeError(std::uint64_t offset, const std::string& what);
  std::uint64_t offset() const { return offset_; }

 private:
  std::uint64_t offset_;
};

}  // namespace geom
