// Smooth face-varying data through the mesh cut along its UV seams (see face_varying.h).

#include <geom/subdivision/face_varying.h>

#include <geom/core/errors.h>
#include <geom/core/soup.h>
#include <geom/subdivision/creases.h>
#include <geom/subdivision/union_find.h>

#include <algorithm>
#include <numeric>
#include <string>

namespace geom::detail::subdiv {

std::vector<double> refine_face_varying_smooth(const SurfaceMesh& mesh, const double* rows,
                                               int w, const SubdivideOptions& options,
                                               const SurfaceMesh& refined) {
  // OpenSubdiv's face-varying limit of an unrefined control mesh keeps values that its
  // refined levels move; rather than pick one of the two, ask for a level.
  if (options.levels == 0 && options.limit)
    throw InvalidArgument(
        "subdivision: smooth face-varying data (corner UVs) is taken to the limit from "
        "refined levels only; use levels >= 1 or linear face-varying interpolation");
  auto row = [&](Halfedge h) { return rows + static_cast<std::size_t>(h.idx()) * w; };
  auto same = [&](Halfedge a, Halfedge b) { return std::equal(row(a), row(a) + w, row(b)); };

  // A seam edge is one whose two faces disagree at either end; its ends and every boundary
  // vertex keep their values (OpenSubdiv tags them mismatched, hence corners).
  UnionFind corners(mesh.halfedges_size());
  std::vector<char> on_seam(mesh.vertices_size(), 0);
  for (Edge e : mesh.edges()) {
    const Halfedge h = mesh.halfedge(e, 0), o = mesh.halfedge(e, 1);
    if (!mesh.is_boundary(h) && !mesh.is_boundary(o) && same(h, mesh.prev(o)) &&
        same(mesh.prev(h), o)) {
      corners.unite(h.idx(), mesh.prev(o).idx());
      corners.unite(mesh.prev(h).idx(), o.idx());
    } else {
      on_seam[mesh.vertex(e, 0).idx()] = on_seam[mesh.vertex(e, 1).idx()] = 1;
    }
  }

  // The cut mesh: one vertex per group of joined corners, the faces in the same order and
  // from the same first corner.
  SurfaceMesh cut;
  std::vector<std::uint32_t> id(mesh.halfedges_size(), 0xffffffffu);
  std::vector<Halfedge> first_corner;
  std::vector<Vertex> face;
  for (Face f : mesh.faces())
    for (Halfedge h : mesh.halfedges(f)) {
      std::uint32_t& slot = id[corners.find(h.idx())];
      if (slot != 0xffffffffu) continue;
      slot = static_cast<std::uint32_t>(first_corner.size());
      first_corner.push_back(h);
      cut.add_vertex(mesh.position(mesh.to_vertex(h)));
    }
  auto cut_vertex = [&](Halfedge h) { return Vertex(id[corners.find(h.idx())]); };
  for (Face f : mesh.faces()) {
    face.clear();
    for (Halfedge h : mesh.halfedges(f)) face.push_back(cut_vertex(h));
    cut.add_face(face);
  }

  std::vector<std::string> names;
  for (int k = 0; k < w; ++k) {
    names.push_back("fv:" + std::to_string(k));
    auto p = cut.add_property<Vertex, double>(names.back(), 0.0);
    for (std::size_t i = 0; i < first_corner.size(); ++i)
      p[Vertex(static_cast<std::uint32_t>(i))] = row(first_corner[i])[k];
  }
  if (auto es = mesh.get_property<Edge, double>(prop::kEdgeSharpness)) {
    auto cut_es = cut.add_property<Edge, double>(prop::kEdgeSharpness, 0.0);
    for (Face f : mesh.faces())
      for (Halfedge h : mesh.halfedges(f))
        if (es[SurfaceMesh::edge(h)] != 0.0)
          cut_es[SurfaceMesh::edge(cut.find_halfedge(cut_vertex(mesh.prev(h)), cut_vertex(h)))] =
              es[SurfaceMesh::edge(h)];
  }
  auto vs = mesh.get_property<Vertex, double>(prop::kVertexSharpness);
  auto cut_vs = cut.add_property<Vertex, double>(prop::kVertexSharpness, 0.0);
  for (std::size_t i = 0; i < first_corner.size(); ++i) {
    const Vertex v = mesh.to_vertex(first_corner[i]);
    cut_vs[Vertex(static_cast<std::uint32_t>(i))] =
        on_seam[v.idx()] ? kInfinite : (vs ? vs[v] : 0.0);
  }

  SubdivideOptions o = options;
  o.crease_angle.reset();
  o.progress = nullptr;
  o.face_varying = FaceVaryingInterpolation::kLinearAll;
  const SubdivideResult r = subdivide(cut, o);

  std::vector<double> out(refined.halfedges_size() * static_cast<std::size_t>(w), 0.0);
  for (int k = 0; k < w; ++k) {
    auto p = r.mesh.get_property<Vertex, double>(names[k]);
    for (Face f : refined.faces()) {
      Halfedge h = refined.halfedge(f), hc = r.mesh.halfedge(f);
      do {
        out[static_cast<std::size_t>(h.idx()) * w + k] = p[r.mesh.to_vertex(hc)];
        h = refined.next(h);
        hc = r.mesh.next(hc);
      } while (h != refined.halfedge(f));
    }
  }
  return out;
}

}  // namespace geom::detail::subdiv
