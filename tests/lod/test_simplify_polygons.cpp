// Polygon input: simplify() fan-triangulates it, which can double an edge (a valence-2
// interior vertex), and its output triangles come in an order that incremental add_face
// refuses on some meshes. Both used to throw "add_face: complex edge / complex vertex".

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
}  // namespace geom
