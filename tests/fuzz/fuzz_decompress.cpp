// libFuzzer target for the mesh codec's decoder: any byte string must decode to a valid
// mesh or throw DecodeError — no crash, no sanitizer report, no unbounded allocation. When
// the input decodes, the result is re-encoded and decoded again, and the round trip must
// preserve the element counts and the split vertices' groups (the codec's round-trip check,
// after meshoptimizer's habit).

#include "fuzz_check.h"

#include <geom/compress/container/codec.h>

#include <cstddef>
#include <cstdint>
#include <span>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  // The flat decoder (its own path for chunked streams) must hold up as well.
  try {
    geom::codec::decompress_flat(std::span<const std::uint8_t>(data, size));
  } catch (const geom::DecodeError&) {
  }
  geom::DecompressResult d;
  try {
    d = geom::decompress(std::span<const std::uint8_t>(data, size));
  } catch (const geom::DecodeError&) {
    return 0;
  }
  geom::CompressResult c;
  try {
    // Split vertices travel again: in preserved order each group's lowest vertex comes back.
    c = geom::compress(d.mesh, {.bits = 16, .level = 1, .preserve_order = true,
                                .vertex_origin = d.vertex_representative});
  } catch (const geom::InvalidArgument&) {
    return 0;  // documented refusal, e.g. a decoded polygon with no valid fan corner
  }
  const auto again = geom::decompress(c.bytes);
  FUZZ_CHECK(again.mesh.n_vertices() == d.mesh.n_vertices() && again.mesh.n_faces() == d.mesh.n_faces() &&
             again.vertex_representative == d.vertex_representative);
  return 0;
}
