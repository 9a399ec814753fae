// Random edits over the small meshes of the corpus, with validate() after every single
// mutation (geometry-central's habit): flips, edge splits, vertex insertions, face splits,
// collapses that pass the link condition, deletions, and a final compact(). Topology-
// preserving edits must keep χ, boundary loops and components; seeded, so reproducible.

#include <geom/core/build.h>
#include <geom/core/topology.h>
#include <geom/core/validate.h>
#include <geom/io/io.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

#include "support/data.h"

namespace geom {
namespace {

// Small meshes only: validate() is O(n) after each of a few hundred edits.
const char* const kSmall[] = {
    "TinyTorus.obj",      "cube_quads.off",           "cube_tris.obj",
    "chamfer-cube.off",   "cylinder.obj",             "icosahedron_binary.stl",
    "suzanne.obj",        "fandisk_quads.off",        "halftunnel.off",
    "spot_control_mesh.obj", "opensubdiv/catmark_torus.obj", "opensubdiv/catmark_nonquads.obj",
    "opensubdiv/catmark_flap.obj", "opensubdiv/catmark_toroidal_tet.obj",
    "opensubdiv/bilinear_nonquads1.obj", "opensubdiv/loop_toroidal_tet.obj",
    "opensubdiv/loop_saddle_edgecorner.obj", "opensubdiv/catmark_car.obj",
    "opensubdiv/catmark_val2_interior.obj", "opensubdiv/loop_pole64.obj",
};

template <class H>
H random_live(const SurfaceMesh& m, std::mt19937& rng, std::size_t size) {
  for (int tries = 0; tries < 64; ++tries) {
    H h(static_cast<std::uint32_t>(rng() % size));
    if (!m.is_deleted(h)) return h;
  }
  for (std::uint32_t i = 0; i < size; ++i)
    if (!m.is_deleted(H(i))) return H(i);
  return H();
}

// A collapse that makes a triangle vanish merges the apex's two edges of it into one; an
// apex with no other edge would be left dangling inside the neighbouring polygon (a face
// that visits a vertex twice). can_collapse must refuse it (regression: catmark_nonquads,
// this seed, step 106).
bool leaves_dangling_apex(const SurfaceMesh& m, Halfedge h) {
  for (Halfedge s : {h, SurfaceMesh::opposite(h)}) {
    if (m.is_boundary(s) || m.valence(m.face(s)) != 3) continue;
    if (m.valence(m.to_vertex(m.next(s))) <= 2) return true;
  }
  return false;
}

bool some_face_repeats_a_vertex(const SurfaceMesh& m) {
  std::vector<std::uint32_t> vs;
  for (Face f : m.faces()) {
    vs.clear();
    for (Vertex v : m.vertices(f)) vs.push_back(v.idx());
    std::sort(vs.begin(), vs.end());
    if (std::adjacent_find(vs.begin(), vs.end()) != vs.end()) return true;
  }
  return false;
}

struct Shape {
  long chi;
  std::size_t loops, components;
};
Shape shape(const SurfaceMesh& m) {
  auto t = analyze(m);
  return {t.euler_characteristic, t.boundary_loops, t.components};
}

class EditCorpus : public ::testing::TestWithParam<const char*> {};

TEST_P(EditCorpus, EveryMutationKeepsTheMeshValid) {
  GEOM_REQUIRE_DATA_DIR(dir);
  SurfaceMesh m = build(read_soup(dir / GetParam())).mesh;
  ASSERT_TRUE(validate(m).ok());
  const Shape before = shape(m);
  std::mt19937 rng(20261122);
  std::size_t done[6] = {};
  for (int step = 0; step < 300 && m.n_faces() > 8; ++step) {
    const int op = static_cast<int>(rng() % 6);
    std::string what;
    if (op == 0) {
      Edge e = random_live<Edge>(m, rng, m.edges_size());
      if (!e.is_valid() || !m.can_flip(e)) continue;
      m.flip(e);
      what = "flip";
    } else if (op == 1) {
      Edge e = random_live<Edge>(m, rng, m.edges_size());
      if (!e.is_valid()) continue;
      Point mid = 0.5 * (m.position(m.vertex(e, 0)) + m.position(m.vertex(e, 1)));
      bool tris = (m.is_boundary(SurfaceMesh::halfedge(e, 0)) || m.valence(m.face(e, 0)) == 3) &&
                  (m.is_boundary(SurfaceMesh::halfedge(e, 1)) || m.valence(m.face(e, 1)) == 3);
      if (tris) {
        m.split_edge(e, mid);
        what = "split_edge";
      } else {
        m.insert_vertex(e, mid);
        what = "insert_vertex";
      }
    } else if (op == 2) {
      Face f = random_live<Face>(m, rng, m.faces_size());
      if (!f.is_valid()) continue;
      Point c = Point::Zero();
      double n = 0;
      for (Vertex v : m.vertices(f)) c += m.position(v), n += 1;
      m.split_face(f, c / n);
      what = "split_face";
    } else if (op <= 4) {
      Halfedge h = random_live<Halfedge>(m, rng, m.halfedges_size());
      if (!h.is_valid() || !m.can_collapse(h)) continue;
      EXPECT_FALSE(leaves_dangling_apex(m, h)) << "can_collapse allowed a dangling apex";
      m.collapse(h);
      what = "collapse";
    } else {
      Face f = random_live<Face>(m, rng, m.faces_size());
      if (!f.is_valid() || (rng() % 4) != 0) continue;
      m.delete_face(f);
      auto v = validate(m);
      ASSERT_TRUE(v.ok()) << GetParam() << " step " << step << " delete_face\n" << v.to_string();
      ++done[5];
      continue;
    }
    ++done[op];
    auto v = validate(m);
    ASSERT_TRUE(v.ok()) << GetParam() << " step " << step << " " << what << "\n" << v.to_string();
    ASSERT_FALSE(some_face_repeats_a_vertex(m)) << GetParam() << " step " << step << " " << what;
    if (done[5] == 0) {
      // Before any deletion every edit so far preserved the topology.
      Shape now = shape(m);
      ASSERT_EQ(now.chi, before.chi) << what << " at step " << step;
      ASSERT_EQ(now.loops, before.loops) << what << " at step " << step;
      ASSERT_EQ(now.components, before.components) << what << " at step " << step;
    }
  }
  m.compact();
  auto v = validate(m);
  ASSERT_TRUE(v.ok()) << v.to_string();
  EXPECT_FALSE(m.has_garbage());
  // The edited mesh survives a trip through a soup.
  auto again = build(to_soup(m));
  EXPECT_TRUE(validate(again.mesh).ok());
  EXPECT_EQ(again.mesh.n_faces() + again.report.dropped_degenerate + again.report.dropped_duplicate, m.n_faces());
}

INSTANTIATE_TEST_SUITE_P(Small, EditCorpus, ::testing::ValuesIn(kSmall),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string s = info.param;
                           for (char& c : s)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return s;
                         });

}  // namespace
}  // namespace geom
