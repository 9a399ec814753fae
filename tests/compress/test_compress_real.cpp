// Round trips over the real meshes in $GEOM_DATA_DIR (skipped when absent): connectivity
// identical up to the encoder's permutation, positions within the grid bound, and exact
// order in preserve_order mode. Large meshes run at one level to keep the runtime modest.

#include "compress/round_trip.h"
#include "support/data.h"

#include <geom/compress/container/codec.h>
#include <geom/core/validate.h>
#include <geom/io/io.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace geom {
namespace {

using test::canonical;
using test::faces_of;

void check(const SurfaceMesh& in, const CompressOptions& opt, const std::string& name) {
  SCOPED_TRACE(name);
  const CompressResult c = compress(in, opt);
  const DecompressResult d = decompress(c.bytes);
  ASSERT_TRUE(validate(d.mesh).ok());
  ASSERT_EQ(d.mesh.n_vertices(), in.n_vertices());
  ASSERT_EQ(d.mesh.n_faces(), in.n_faces());
  const auto fin = faces_of(in), fout = faces_of(d.mesh);
  for (std::size_t j = 0; j < fout.size(); ++j) {
    std::vector<std::uint32_t> mapped;
    for (auto v : fout[j]) mapped.push_back(c.vertex_permutation[v]);
    const auto& orig = fin[c.face_permutation[j]];
    if (opt.preserve_order) ASSERT_EQ(mapped, orig) << "face " << j;
    else ASSERT_EQ(canonical(mapped), canonical(orig)) << "face " << j;
  }
  std::vector<Point> pin;
  for (Vertex v : in.vertices()) pin.push_back(in.position(v));
  std::size_t i = 0;
  const double tol = c.stats.max_error * (1 + 1e-9) + 1e-12;
  for (Vertex v : d.mesh.vertices()) {
    const Point& p = pin[c.vertex_permutation[i++]];
    ASSERT_LE((d.mesh.position(v) - p).cwiseAbs().maxCoeff(), tol + 1e-14 * p.norm());
  }
}

TEST(CompressReal, RoundTripsEveryCorpusMesh) {
  GEOM_REQUIRE_DATA_DIR(dir);
  std::size_t tested = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(dir)) {
    const auto ext = entry.path().extension().string();
    if (!entry.is_regular_file() || (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl"))
      continue;
    SurfaceMesh mesh;
    try {
      mesh = load_mesh(entry.path()).mesh;
    } catch (const Error& e) {
      ADD_FAILURE() << entry.path() << ": " << e.what();
      continue;
    }
    const bool small = mesh.n_faces() < 30000;
    const std::string name = entry.path().filename().string();
    check(mesh, {.level = small ? 9 : 3}, name);
    check(mesh, {.bits = 14, .level = 1, .preserve_order = true}, name + " ordered");
    if (small) check(mesh, {.precision = 1e-4, .level = 5}, name + " precision");
    ++tested;
  }
  EXPECT_GT(tested, 20u);
}

// Corner normals (suzanne) and corner UVs (the rook) made level 6 larger than level 5 when
// the search ignored the attributes' size.
TEST(CompressReal, LevelsAreMonotonicWithCornerAttributes) {
  GEOM_REQUIRE_DATA_DIR(dir);
  for (const char* name : {"suzanne.obj", "opensubdiv/catmark_rook.obj"}) {
    const SurfaceMesh mesh = load_mesh(dir / name).mesh;
    std::size_t prev = SIZE_MAX;
    for (int level = 0; level <= 9; ++level) {
      const std::size_t size = compress(mesh, {.level = level}).bytes.size();
      EXPECT_LE(size, prev) << name << ", level " << level;
      prev = size;
    }
  }
}

}  // namespace
}  // namespace geom
