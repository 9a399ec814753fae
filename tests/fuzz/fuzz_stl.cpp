// libFuzzer target for the STL reader (and, for accepted input, the STL writer).

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace geom;
  const FileFormat format = FileFormat::kStl;
  const std::optional<PolygonSoup> soup = fuzz::read(data, size, format);
  if (!soup) return 0;
  // ascii STL keeps doubles exactly; welding renumbers by first use, which the reader
  // already did, so positions come back in the same order.
  fuzz::round_trip(*soup, format, false, false);
  return 0;
}
