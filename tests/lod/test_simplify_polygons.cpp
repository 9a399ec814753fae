// Polygon input: simplify() fan-triangulates it, which can double an edge (a valence-2
// interior vertex), and its output triangles come in an order that incremental add_face
// refuses on some meshes. Both used to throw "add_face: complex edge / complex vertex".

#include <geom/core/build.h>
#include <geom/core/topology.h>
#include <geom/core/validate.h>
#include <geom/io/io.h>
#include <geom/lod/simplify.h>

#include "support/data.h"

#include <gtest/gtest.h>

namespace geom {
namespace {

TEST(SimplifyPolygons, RealPolygonMeshesGiveValidManifoldOutput) {
  GEOM_REQUIRE_DATA_DIR(dir);
  for (const char* name : {"opensubdiv/catmark_val2_interior.obj", "beast.obj"}) {
    SCOPED_TRACE(name);
    const SurfaceMesh mesh = load_mesh(dir / name).mesh;
    const SimplifyResult r = simplify(mesh, {.ratio = 0.5});
    EXPECT_TRUE(validate(r.mesh).ok()) << validate(r.mesh).to_string();
    EXPECT_TRUE(analyze(r.mesh).manifold);
    EXPECT_LE(r.faces_after, r.faces_before / 2 + 1);
    EXPECT_EQ(r.vertex_origin.size(), r.mesh.n_vertices());
  }
}

}  // namespace
// Found by fuzz_algorithms: build() of a non-manifold file left a quad whose two diagonals
// are both edges of the mesh. Every fan of it gives an edge a third face, so simplify() (at
// any ratio, even 1) ended in add_face's "complex edge" instead of a result; it now refuses
// the polygon by name before collapsing anything.
TEST(SimplifyPolygons, QuadWhoseDiagonalsAreBothEdgesIsRefusedByName) {
  const std::string obj =
      "v 0 1000 2\nv 1 0 0\nv 0 1 0\nv 1 5 2\nv 0 0 20\nv 0 0 0\n"
      "vt 1 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
      "f 1 3 2\nf 1 2 4\nf 1/1/1 2/2/1 3/3/1 4/4/1\nf 2 3 4\nf 2 5 3\nf 1 2 5\n"
      "f 1/1/1 6/2/1 3/3/1 4/4/1\nf 1/1/1 5/2/1 6/3/1 3/4/1\n";
  const PolygonSoup soup =
      read_soup(std::as_bytes(std::span(obj.data(), obj.size())), FileFormat::kObj, "quads.obj");
  const SurfaceMesh m = build(soup).mesh;
  ASSERT_TRUE(validate(m).ok());
  for (double ratio : {1.0, 0.33}) {
    try {
      simplify(m, {.ratio = ratio});
      ADD_FAILURE() << "no error at ratio " << ratio;
    } catch (const InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find("corners) has no fan whose diagonals are not already edges"),
                std::string::npos)
          << e.what();
    }
  }
}

}  // namespace geom
