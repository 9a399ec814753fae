// libFuzzer target for the .npy grid reader: malformed input may only end in ParseError
// (never a crash, a huge allocation or a read past the data); a grid that is accepted holds
// exactly nx·ny·nz samples in the one array its type selects.

#include "fuzz_check.h"

#include <geom/core/errors.h>
#include <geom/io/grid.h>

#include <cstddef>
#include <cstdint>
#include <span>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  geom::GridData g;
  try {
    g = geom::read_npy(std::span<const std::byte>(reinterpret_cast<const std::byte*>(data), size), "fuzz");
  } catch (const geom::ParseError&) {
    return 0;
  }
  const std::size_t n = g.nx * g.ny * g.nz;
  FUZZ_CHECK((g.is_double ? g.doubles.size() : g.floats.size()) == n);
  FUZZ_CHECK((g.is_double ? g.floats.size() : g.doubles.size()) == 0);
  return 0;
}
