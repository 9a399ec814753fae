// libFuzzer target for the progressive-mesh stream reader (geom/lod/FORMAT.md): any byte
// string must decode or throw DecodeError, whole or cut short (allow_partial). A stream
// that decodes must move between its coarsest and finest levels with every face indexing
// a vertex of its level, and survive encode() and decode() with the same counts and faces.

#include "fuzz_check.h"

#include <geom/lod/progressive_mesh.h>

#include <cstddef>
#include <cstdint>
#include <span>

namespace {

void check_level(const geom::ProgressiveMesh& pm) {
  FUZZ_CHECK(pm.positions().size() == pm.n_vertices());
  FUZZ_CHECK(pm.n_faces() == pm.faces_at(pm.n_vertices()));
  for (const auto& f : pm.faces())
    for (std::uint32_t v : f) FUZZ_CHECK(v < pm.n_vertices());
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::byte> bytes(reinterpret_cast<const std::byte*>(data), size);
  for (bool partial : {false, true}) {
    geom::ProgressiveMesh pm;
    try {
      pm = geom::ProgressiveMesh::decode(bytes, partial);
    } catch (const geom::DecodeError&) {
      continue;
    }
    FUZZ_CHECK(pm.n_vertices() == pm.max_vertices());
    check_level(pm);
    pm.coarsen_to(pm.base_vertices());
    FUZZ_CHECK(pm.n_vertices() == pm.base_vertices() && pm.n_faces() == pm.base_faces());
    check_level(pm);
    pm.refine_to(pm.max_vertices());
    check_level(pm);
    const geom::ProgressiveMesh again = geom::ProgressiveMesh::decode(pm.encode());
    FUZZ_CHECK(again.max_vertices() == pm.max_vertices() && again.n_faces() == pm.n_faces());
    for (std::size_t t = 0; t < pm.n_faces(); ++t) FUZZ_CHECK(again.faces()[t] == pm.faces()[t]);
  }
  return 0;
}
