#include <geom/compress/container/mesh_tables.h>

#include <algorithm>
#include <string>
#include <unordered_set>

namespace geom::codec::detail {

namespace {

std::uint64_t pair_key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t{a} << 32) | b;
}

}  // namespace

FlatMesh flatten(const SurfaceMesh& mesh) {
  FlatMesh flat;
  std::vector<std::uint32_t> dense(mesh.vertices_size(), kNone);
  flat.positions.reserve(mesh.n_vertices());
  for (Vertex v : mesh.vertices()) {
    dense[v.idx()] = static_cast<std::uint32_t>(flat.positions.size());
    flat.positions.push_back(mesh.position(v));
  }
  CornerTable& t = flat.table;
  t.n_vertices = static_cast<std::uint32_t>(flat.positions.size());
  // The input halfedge each corner faces (kNone for a diagonal), and each halfedge's corner.
  std::vector<std::uint32_t> corner_halfedge;
  std::vector<std::uint32_t> halfedge_corner(mesh.halfedges_size(), kNone);
  std::unordered_set<std::uint64_t> used_diagonals;
  t.vertex.reserve(3 * mesh.n_faces());
  corner_halfedge.reserve(3 * mesh.n_faces());
  std::vector<Vertex> cv;
  std::vector<Halfedge> ch;
  for (Face f : mesh.faces()) {
    cv.clear();
    ch.clear();
    // ch[j] runs from corner j to corner j+1.
    for (Halfedge h : mesh.halfedges(f)) {
      cv.push_back(mesh.to_vertex(h));
      ch.push_back(mesh.next(h));
    }
    const std::size_t k = cv.size();
    const auto face_id = static_cast<std::uint32_t>(flat.n_faces++);
    flat.face_first_vertex.push_back(dense[cv[0].idx()]);
    std::size_t apex = 0;
    if (k > 3) {
      flat.polygons = true;
      bool found = false;
      for (apex = 0; apex < k && !found; ++apex) {
        found = true;
        for (std::size_t i = 2; i + 1 < k && found; ++i) {
          const Vertex o = cv[(apex + i) % k];
          if (mesh.find_halfedge(cv[apex], o).is_valid() ||
              used_diagonals.count(pair_key(cv[apex].idx(), o.idx())))
            found = false;
        }
      }
      if (!found)
        throw InvalidArgument("compress: face " + std::to_string(f.idx()) +
                              " has no corner whose fan diagonals avoid existing edges");
      --apex;
      for (std::size_t i = 2; i + 1 < k; ++i)
        used_diagonals.insert(pair_key(cv[apex].idx(), cv[(apex + i) % k].idx()));
    }
    for (std::size_t i = 1; i + 1 < k; ++i) {
      const std::size_t a = apex, b = (apex + i) % k, c = (apex + i + 1) % k;
      t.vertex.insert(t.vertex.end(), {dense[cv[a].idx()], dense[cv[b].idx()], dense[cv[c].idx()]});
      flat.triangle_face.push_back(face_id);
      // Corner 0 faces b→c (a polygon edge); corner 1 faces c→a; corner 2 faces a→b.
      corner_halfedge.push_back(ch[b].idx());
      corner_halfedge.push_back(i + 2 == k ? ch[c].idx() : kNone);
      corner_halfedge.push_back(i == 1 ? ch[a].idx() : kNone);
    }
  }
  const std::size_t nc = t.vertex.size();
  for (std::uint32_t c = 0; c < nc; ++c)
    if (corner_halfedge[c] != kNone) halfedge_corner[corner_halfedge[c]] = c;
  t.opposite.assign(nc, kNone);
  t.diagonal.assign(flat.polygons ? nc : 0, 0);
  for (std::uint32_t c = 0; c < nc; ++c) {
    const std::uint32_t h = corner_halfedge[c];
    if (h == kNone) continue;
    const Halfedge o = SurfaceMesh::opposite(Halfedge(h));
    if (!mesh.is_boundary(o)) t.opposite[c] = halfedge_corner[o.idx()];
  }
  // A fan triangle's corner 1 faces the diagonal c→a unless it is the last of its fan; the
  // next triangle's corner 2 faces the same diagonal reversed.
  for (std::uint32_t c = 0; c < nc; ++c) {
    if (corner_halfedge[c] != kNone || c % 3 != 1) continue;
    const std::uint32_t partner = c + 4;  // next triangle's corner 2 (same fan)
    t.opposite[c] = partner;
    t.opposite[partner] = c;
    t.diagonal[c] = t.diagonal[partner] = 1;
  }
  return flat;
}

Polygons reassemble(const CornerTable& t, std::uint64_t where) {
  Polygons out;
  const std::size_t nt = t.n_triangles();
  out.offset.push_back(0);
  if (t.diagonal.empty()) {
    out.vertex = t.vertex;
    out.offset.resize(nt + 1);
    out.first_triangle.resize(nt);
    for (std::uint32_t i = 0; i < nt; ++i) {
      out.offset[i + 1] = 3 * (i + 1);
      out.first_triangle[i] = i;
    }
    return out;
  }
  std::vector<std::uint8_t> seen(nt, 0);
  std::vector<std::uint32_t> group, stack;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
  for (std::uint32_t t0 = 0; t0 < nt; ++t0) {
    if (seen[t0]) continue;
    group.clear();
    edges.clear();
    stack.push_back(t0);
    seen[t0] = 1;
    while (!stack.empty()) {
      const std::uint32_t tr = stack.back();
      stack.pop_back();
      group.push_back(tr);
      for (std::uint32_t j = 0; j < 3; ++j) {
        const std::uint32_t c = 3 * tr + j;
        if (t.diagonal[c]) {
          const std::uint32_t o = t.opposite[c];
          if (o == kNone) throw DecodeError(where, "polygon diagonal on a boundary edge");
          if (!seen[o / 3]) {
            seen[o / 3] = 1;
            stack.push_back(o / 3);
          }
        }
      }
    }
    std::sort(group.begin(), group.end());
    for (std::uint32_t tr : group)
      for (std::uint32_t j = 0; j < 3; ++j) {
        const std::uint32_t c = 3 * tr + j;
        if (!t.diagonal[c]) edges.push_back({t.vertex[next_corner(c)], t.vertex[prev_corner(c)]});
      }
    if (edges.size() != group.size() + 2)
      throw DecodeError(where, "polygon diagonals do not form a simple polygon");
    const std::uint32_t start = edges[0].first;
    std::sort(edges.begin(), edges.end());
    // Walk the cycle from the first triangle's first polygon edge.
    std::uint32_t v = start;
    for (std::size_t i = 0; i < edges.size(); ++i) {
      if (i > 0 && v == start) throw DecodeError(where, "polygon boundary closes early");
      out.vertex.push_back(v);
      auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(v, std::uint32_t{0}));
      if (it == edges.end() || it->first != v || (it + 1 != edges.end() && (it + 1)->first == v))
        throw DecodeError(where, "polygon boundary is not a simple cycle");
      v = it->second;
    }
    if (v != start) throw DecodeError(where, "polygon boundary does not close");
    out.offset.push_back(static_cast<std::uint32_t>(out.vertex.size()));
    out.first_triangle.push_back(group.front());
  }
  return out;
}

}  // namespace geom::codec::detail
