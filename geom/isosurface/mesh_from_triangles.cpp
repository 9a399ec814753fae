#include <geom/isosurface/marching_cubes.h>

#include <string>

namespace geom {

// Halfedges are paired through a per-vertex list of outgoing triangle corners (counting
// sort), not a hash map: marching cubes vertices have valence ~6, so the scan is short.
SurfaceMesh mesh_from_triangles(const std::vector<Point>& positions,
                                const std::vector<std::array<std::uint32_t, 3>>& triangles) {
  const std::size_t nv = positions.size(), nf = triangles.size();
  constexpr std::uint32_t kNone = ~std::uint32_t(0);
  if (nv >= kNone / 2 || 3 * nf >= kNone / 2)
    throw InvalidArgument("mesh_from_triangles: too many elements for 32-bit handles");
  for (std::size_t f = 0; f < nf; ++f)
    for (int k = 0; k < 3; ++k)
      if (triangles[f][k] >= nv)
        throw InvalidArgument("triangle " + std::to_string(f) + " uses vertex " +
                              std::to_string(triangles[f][k]) + ", but there are " +
                              std::to_string(nv) + " vertices");

  // Corner h = 3f + k is the halfedge triangles[f][k] → triangles[f][(k+1)%3].
  auto from = [&](std::size_t h) { return triangles[h / 3][h % 3]; };
  auto to = [&](std::size_t h) { return triangles[h / 3][(h % 3 + 1) % 3]; };
  const std::size_t nh = 3 * nf;
  std::vector<std::uint32_t> start(nv + 1, 0), out(nh);
  for (std::size_t h = 0; h < nh; ++h) ++start[from(h) + 1];
  for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t h = 0; h < nh; ++h) out[fill[from(h)]++] = static_cast<std::uint32_t>(h);
  }
  std::vector<std::uint32_t> twin(nh, kNone);
  for (std::size_t h = 0; h < nh; ++h) {
    const std::uint32_t a = from(h), b = to(h);
    if (a == b)
      throw TopologyError("triangle " + std::to_string(h / 3) + " repeats vertex " +
                          std::to_string(a));
    int same = 0;
    for (std::uint32_t i = start[a]; i < start[a + 1]; ++i) same += to(out[i]) == b;
    if (same > 1)
      throw TopologyError("edge " + std::to_string(a) + "→" + std::to_string(b) +
                          " is used twice in the same direction (triangle " +
                          std::to_string(h / 3) + ")");
    for (std::uint32_t i = start[b]; i < start[b + 1]; ++i)
      if (to(out[i]) == a) twin[h] = out[i];
  }

  SurfaceMesh mesh;
  std::size_t n_edges = 0;
  for (std::size_t h = 0; h < nh; ++h) n_edges += twin[h] == kNone || h < twin[h];
  mesh.reserve(nv, n_edges, nf);
  for (std::size_t v = 0; v < nv; ++v) mesh.position(mesh.new_vertex()) = positions[v];

  std::vector<Halfedge> he(nh);
  std::vector<Halfedge> boundary_out(nv);
  for (std::size_t h = 0; h < nh; ++h) {
    if (twin[h] != kNone && twin[h] < h) continue;
    Halfedge fwd = mesh.new_edge(Vertex(from(h)), Vertex(to(h)));
    he[h] = fwd;
    if (twin[h] != kNone) {
      he[twin[h]] = SurfaceMesh::opposite(fwd);
    } else {
      Halfedge back = SurfaceMesh::opposite(fwd);  // to(h) → from(h), no face
      mesh.set_face(back, Face());
      if (boundary_out[to(h)].is_valid())
        throw TopologyError("vertex " + std::to_string(to(h)) +
                            " has two boundary gaps (not manifold)");
      boundary_out[to(h)] = back;
    }
  }
  for (std::size_t f = 0; f < nf; ++f) {
    Face face = mesh.new_face();
    mesh.set_halfedge(face, he[3 * f]);
    for (int k = 0; k < 3; ++k) {
      Halfedge h = he[3 * f + k];
      mesh.set_face(h, face);
      mesh.set_next(h, he[3 * f + (k + 1) % 3]);
      mesh.set_halfedge(Vertex(triangles[f][k]), h);
    }
  }
  for (std::size_t v = 0; v < nv; ++v) {
    Halfedge b = boundary_out[v];
    if (!b.is_valid()) continue;
    const Vertex target = mesh.to_vertex(b);
    if (!boundary_out[target.idx()].is_valid())
      throw TopologyError("vertex " + std::to_string(target.idx()) +
                          " has an incoming boundary edge but no outgoing one (not manifold)");
    mesh.set_next(b, boundary_out[target.idx()]);
    mesh.set_halfedge(Vertex(static_cast<std::uint32_t>(v)), b);
  }
  return mesh;
}

}  // namespace geom
