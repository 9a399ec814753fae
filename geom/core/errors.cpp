#include <geom/core/errors.h>

namespace geom {
namespace {

std::string locate(const std::string& file, ParseError::Unit unit, std::uint64_t where,
                   const std::string& what) {
  std::string out = file.empty() ? std::string("<input>") : file;
  if (unit == ParseError::Unit::kLine) out.append(":").append(std::to_string(where));
  if (unit == ParseError::Unit::kByte) out.append(": byte ").append(std::to_string(where));
  out.append(": ").append(what);
  return out;
}

}  // namespace

ParseError::ParseError(std::string file, Unit unit, std::uint64_t where, const std::string& what)
    : Error(locate(file, unit, where, what)), file_(std::move(file)), unit_(unit), where_(where) {}

DecodeError::DecodeError(std::uint64_t offset, const std::string& what)
    : Error("byte " + std::to_string(offset) + ": " + what), offset_(offset) {}

}  // namespace geom
