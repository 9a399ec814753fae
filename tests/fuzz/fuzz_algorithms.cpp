// libFuzzer target for the algorithms on hard input: the bytes are an OBJ file (at most 400
// vertices and faces), built into a mesh with the usual repairs, then simplified, subdivided
// and compressed. Degenerate, duplicate, collinear, huge-coordinate and non-manifold input
// all come this way; none may crash, hang or break the mesh invariants (validate()), and the
// codec must give back what it was given (element counts).

#include "fuzz_check.h"

#include <geom/compress/container/codec.h>
#include <geom/core/build.h>
#include <geom/core/errors.h>
#include <geom/core/validate.h>
#include <geom/io/io.h>
#include <geom/lod/simplify.h>
#include <geom/subdivision/subdivision.h>

#include <cstddef>
#include <cstdint>
#include <span>

namespace {

bool all_triangles(const geom::SurfaceMesh& m) {
  for (geom::Face f : m.faces())
    if (m.valence(f) != 3) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  geom::PolygonSoup soup;
  try {
    soup = geom::read_soup(std::span<const std::byte>(reinterpret_cast<const std::byte*>(data + 1), size - 1),
                           geom::FileFormat::kObj, "fuzz.obj");
  } catch (const geom::ParseError&) {
    return 0;
  }
  if (soup.positions.size() > 400 || soup.n_faces() > 400) return 0;
  const geom::SurfaceMesh mesh = geom::build(soup).mesh;
  FUZZ_CHECK(geom::validate(mesh).ok());
  if (mesh.n_faces() == 0) return 0;

  // The first byte picks the target: 0 … 100% of the triangles.
  geom::SimplifyResult s;
  try {
    s = geom::simplify(mesh, {.ratio = (data[0] % 101) / 100.0});
  } catch (const geom::InvalidArgument&) {
    return 0;  // documented refusal: a polygon no fan triangulates into a manifold mesh
  }
  FUZZ_CHECK(geom::validate(s.mesh).ok());
  FUZZ_CHECK(s.faces_after <= s.faces_before);
  for (geom::Vertex v : s.mesh.vertices()) FUZZ_CHECK(s.mesh.position(v).allFinite());  // the input's are

  const auto scheme = all_triangles(mesh) && (data[0] & 1) ? geom::SubdivisionScheme::kLoop
                                                          : geom::SubdivisionScheme::kCatmullClark;
  const geom::SubdivideResult d = geom::subdivide(mesh, {.scheme = scheme, .levels = 1});
  FUZZ_CHECK(geom::validate(d.mesh).ok());

  geom::CompressResult c;
  try {
    c = geom::compress(mesh, {.bits = 14});
  } catch (const geom::InvalidArgument&) {
    return 0;  // documented refusal (e.g. a polygon with no valid fan corner)
  }
  const geom::DecompressResult back = geom::decompress(c.bytes);
  FUZZ_CHECK(back.mesh.n_vertices() == mesh.n_vertices() && back.mesh.n_faces() == mesh.n_faces());
  return 0;
}
