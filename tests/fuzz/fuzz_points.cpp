// libFuzzer target for the point-set reader (text lines, or a mesh file's vertices when the
// content sniffs as one): malformed input may only end in ParseError, and an accepted set
// has finite points of the dimension it reports (2D: z = 0).

#include "fuzz_check.h"

#include <geom/core/errors.h>
#include <geom/io/points.h>

#include <cstddef>
#include <cstdint>
#include <span>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  geom::PointSet s;
  try {
    s = geom::read_points(std::span<const std::byte>(reinterpret_cast<const std::byte*>(data), size), "fuzz");
  } catch (const geom::ParseError&) {
    return 0;
  }
  FUZZ_CHECK(s.dimension == 2 || s.dimension == 3);
  for (const auto& p : s.points)
    FUZZ_CHECK(p.allFinite() && (s.dimension == 3 || p.z() == 0));
  return 0;
}
