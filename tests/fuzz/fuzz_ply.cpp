// libFuzzer target for the PLY reader (and, for accepted input, the PLY writer).

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace geom;
  const FileFormat format = FileFormat::kPly;
  const std::optional<PolygonSoup> soup = fuzz::read(data, size, format);
  if (!soup) return 0;
  fuzz::round_trip(*soup, format, true, true);
  fuzz::round_trip(*soup, format, false, true);
  return 0;
}
