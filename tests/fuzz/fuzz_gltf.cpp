// libFuzzer target for the glTF reader, as .gltf (JSON, buffers as data URIs) and as .glb
// (binary chunks) from the same bytes. Malformed input may only end in ParseError; a soup
// that is accepted is written as GLB and read back: same faces, and the positions as the
// writer's floats hold them (node transforms are applied in double, so they need not have
// been floats before).

#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace geom;
  for (FileFormat format : {FileFormat::kGltf, FileFormat::kGlb}) {
    const std::optional<PolygonSoup> soup = fuzz::read(data, size, format);
    if (!soup) continue;
    const std::vector<std::byte> bytes = write_soup(*soup, FileFormat::kGlb);  // must not throw
    // glTF has no mesh without triangles: a soup of points alone goes out empty, and a file
    // without geometry is refused on reading.
    if (soup->n_faces() == 0) {
      FUZZ_CHECK(!fuzz::read(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(),
                             FileFormat::kGlb));
      continue;
    }
    const PolygonSoup r = read_soup(bytes, FileFormat::kGlb, "round-trip");  // must not throw
    FUZZ_CHECK(r.face_offsets == soup->face_offsets && r.face_indices == soup->face_indices);
    FUZZ_CHECK(r.positions.size() == soup->positions.size());
    for (std::size_t i = 0; i < r.positions.size(); ++i)
      for (int k = 0; k < 3; ++k)
        FUZZ_CHECK(r.positions[i][k] == static_cast<double>(static_cast<float>(soup->positions[i][k])));
  }
  return 0;
}
