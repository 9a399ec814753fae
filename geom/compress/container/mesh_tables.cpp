#include <geom/compress/container/mesh_tables.h>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <string>
#include <unordered_set>

namespace geom::codec::detail {

namespace {

std::uint64_t pair_key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t{a} << 32) | b;
}

// flatten() when every face is a triangle and none is deleted: corner 3f + j belongs to face
// f, so the faces fill the arrays in parallel (their halfedges are scattered over the mesh:
// the loads, not the arithmetic, are the cost). Returns false, having left t's arrays and
// the face arrays empty, at the first face that is not a triangle.
bool flatten_triangles(const SurfaceMesh& mesh, const std::vector<std::uint32_t>& dense, FlatMesh& flat) {
  if (mesh.faces_size() != mesh.n_faces()) return false;
  const auto nf = static_cast<std::uint32_t>(mesh.n_faces());
  const std::size_t nc = 3 * std::size_t{nf};
  CornerTable& t = flat.table;
  t.vertex.resize(nc);
  flat.triangle_face.resize(nf);
  flat.face_first_vertex.resize(nf);
  std::vector<std::uint32_t> corner_halfedge(nc), halfedge_corner(mesh.halfedges_size(), kNone);
  std::atomic<bool> polygon{false};
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, nf, 4096), [&](const tbb::blocked_range<std::uint32_t>& r) {
    for (std::uint32_t f = r.begin(); f != r.end(); ++f) {
      const Halfedge h0 = mesh.halfedge(Face(f)), h1 = mesh.next(h0), h2 = mesh.next(h1);
      if (mesh.next(h2) != h0) {
        polygon = true;
        return;
      }
      // As flatten()'s fan with apex 0: corner j faces the halfedge two after its own.
      const std::uint32_t c = 3 * f, v0 = dense[mesh.to_vertex(h0).idx()];
      t.vertex[c] = v0;
      t.vertex[c + 1] = dense[mesh.to_vertex(h1).idx()];
      t.vertex[c + 2] = dense[mesh.to_vertex(h2).idx()];
      corner_halfedge[c] = h2.idx(), halfedge_corner[h2.idx()] = c;
      corner_halfedge[c + 1] = h0.idx(), halfedge_corner[h0.idx()] = c + 1;
      corner_halfedge[c + 2] = h1.idx(), halfedge_corner[h1.idx()] = c + 2;
      flat.triangle_face[f] = f;
      flat.face_first_vertex[f] = v0;
    }
  });
  if (polygon) {
    t.vertex.clear();
    flat.triangle_face.clear();
    flat.face_first_vertex.clear();
    return false;
  }
  // A boundary halfedge faces no corner, so its entry is kNone: no need to ask the mesh.
  t.opposite.resize(nc);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nc, 16384), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t c = r.begin(); c != r.end(); ++c)
      t.opposite[c] = halfedge_corner[SurfaceMesh::opposite(Halfedge(corner_halfedge[c])).idx()];
  });
  flat.n_faces = nf;
  return true;
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
  if (flatten_triangles(mesh, dense, flat)) return flat;
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
  // A boundary halfedge faces no corner, so its entry is kNone: no need to ask the mesh.
  for (std::uint32_t c = 0; c < nc; ++c) {
    const std::uint32_t h = corner_halfedge[c];
    if (h != kNone) t.opposite[c] = halfedge_corner[SurfaceMesh::opposite(Halfedge(h)).idx()];
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
    out.vertex.assign(t.vertex.begin(), t.vertex.end());
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

namespace {

/// What link_triangles knows about each vertex once the faces are linked.
struct VertexFans {
  std::span<const std::uint32_t> vertex, twin, degree, any_corner;
  std::span<const Halfedge> first_in;  // valid for boundary vertices
};

/// Whether rotating around v meets every corner there once (else some fan is a second,
/// closed one: a complex vertex) and every neighbour once (else two edges join the same
/// vertices); stamp[x] == v marks neighbour x as met. Interior vertices rotate on the corner
/// arrays; the few boundary ones on the mesh, whose rotation hops between their fans. With
/// `why`, says what is wrong. Reads only, so vertices are checked in parallel.
bool fans_ok(const SurfaceMesh& mesh, const VertexFans& f, std::uint32_t v,
             std::vector<std::uint32_t>& stamp, std::string* why) {
  const std::uint32_t degree = f.degree[v];
  if (degree == 0) return true;
  std::uint32_t corners = 0;
  bool twice = false;
  auto meet = [&](std::uint32_t to_vertex) {
    if (stamp[to_vertex] == v && !twice) {
      twice = true;
      if (why)
        *why = "vertices " + std::to_string(v) + " and " + std::to_string(to_vertex) +
               " share two edges";
    }
    stamp[to_vertex] = v;
  };
  bool one_fan = true;
  if (!f.first_in[v].is_valid()) {
    const std::uint32_t start = f.any_corner[v];
    std::uint32_t x = start;
    do {
      meet(f.vertex[next_corner(x)]);
      ++corners;
      x = f.twin[prev_corner(x)];
    } while (!twice && x != kNone && x != start && corners < degree);
    one_fan = twice || (x == start && corners == degree);
  } else {
    const Halfedge start = mesh.halfedge(Vertex(v));
    Halfedge h = start;
    std::uint32_t steps = 0;
    do {
      meet(mesh.to_vertex(h).idx());
      corners += !mesh.is_boundary(h);
      h = mesh.ccw_rotated(h);
    } while (!twice && h != start && ++steps <= 2 * degree);
    one_fan = twice || (corners == degree && h == start);
  }
  if (!one_fan && why)
    *why = "vertex " + std::to_string(v) + " is shared by faces that do not form one fan";
  return one_fan && !twice;
}

}  // namespace

void link_triangles(SurfaceMesh& mesh, std::span<const std::uint32_t> vertex,
                    std::span<const std::uint32_t> twin, std::uint64_t where) {
  const std::size_t nv = mesh.vertices_size(), nc = vertex.size(), nf = nc / 3;
  auto fail = [&](const std::string& what) {
    throw DecodeError(where, "decoded faces do not form a valid mesh: " + what);
  };
  // Corner i is the halfedge vertex[i] → vertex[next(i)].
  auto to = [&](std::uint32_t i) { return vertex[next_corner(i)]; };
  std::vector<std::uint32_t> degree(nv, 0), any_corner(nv);
  std::size_t n_edges = 0;
  for (std::uint32_t i = 0; i < nc; ++i) {
    const std::uint32_t a = vertex[i], t = twin[i];
    if (a == to(i)) fail("face " + std::to_string(i / 3) + " repeats a vertex");
    if (t != kNone && (t >= nc || twin[t] != i || vertex[t] != to(i)))
      fail("corner " + std::to_string(i) + " has an inconsistent opposite");
    ++degree[a];
    any_corner[a] = i;
    n_edges += t == kNone || t > i;
  }
  mesh.resize(nv, n_edges, nf);
  // Corner i's halfedge; a corner without a twin has a boundary halfedge as its opposite.
  std::vector<Halfedge> he(nc);
  for (std::uint32_t i = 0, e = 0; i < nc; ++i) {
    if (twin[i] != kNone && twin[i] < i) continue;
    he[i] = Halfedge(2 * e);
    if (twin[i] != kNone) he[twin[i]] = Halfedge(2 * e + 1);
    ++e;
  }
  // Each corner writes its own halfedge (and its face's): the corners link on all cores.
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(nc), 3 * 4096),
                    [&](const tbb::blocked_range<std::uint32_t>& r) {
                      for (std::uint32_t i = r.begin(); i < r.end(); ++i) {
                        mesh.set_vertex(he[i], Vertex(to(i)));
                        mesh.set_face(he[i], Face(i / 3));
                        mesh.set_next(he[i], he[next_corner(i)]);
                        if (i % 3 == 2) mesh.set_halfedge(Face(i / 3), he[i]);  // ends at corner 0
                      }
                    });
  for (std::uint32_t v = 0; v < nv; ++v)
    if (degree[v] > 0) mesh.set_halfedge(Vertex(v), he[any_corner[v]]);
  // Around a vertex a, its corners form fans: from corner x (a → b) the next one is
  // twin(prev(x)). A boundary fan runs from a corner i without a twin to a corner p
  // (y → a) without one. The boundary halfedges link the fans of a vertex in a cycle (b → a
  // of each fan is followed by a → y of the fan found before it, the first fan's by the
  // last one's), so rotating around a vertex visits all of them.
  std::vector<Halfedge> first_in(nv), last_out(nv);
  for (std::uint32_t i = 0; i < nc; ++i) {
    if (twin[i] != kNone) continue;
    const std::uint32_t a = vertex[i];
    std::uint32_t x = i;
    for (std::uint32_t size = 1; twin[prev_corner(x)] != kNone; ++size) {
      if (size >= degree[a]) fail("vertex " + std::to_string(a) + " has tangled fans");
      x = twin[prev_corner(x)];
    }
    const Halfedge in = SurfaceMesh::opposite(he[i]),
                   out = SurfaceMesh::opposite(he[prev_corner(x)]);
    mesh.set_vertex(in, Vertex(a));
    if (!first_in[a].is_valid())
      first_in[a] = in;
    else
      mesh.set_next(in, last_out[a]);
    last_out[a] = out;
  }
  for (std::uint32_t v = 0; v < nv; ++v)
    if (first_in[v].is_valid()) {
      mesh.set_next(first_in[v], last_out[v]);
      mesh.set_halfedge(Vertex(v), last_out[v]);
    }
  // The fan check on all cores (a random walk over the corners per vertex); the error names
  // the lowest bad vertex, as a serial check would, whatever the scheduling.
  const VertexFans fans{vertex, twin, degree, any_corner, first_in};
  tbb::enumerable_thread_specific<std::vector<std::uint32_t>> stamps(
      [&] { return std::vector<std::uint32_t>(nv, kNone); });
  std::atomic<std::uint32_t> first_bad{kNone};
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(nv), 4096),
                    [&](const tbb::blocked_range<std::uint32_t>& r) {
                      std::vector<std::uint32_t>& stamp = stamps.local();
                      for (std::uint32_t v = r.begin(); v < r.end(); ++v)
                        if (!fans_ok(mesh, fans, v, stamp, nullptr)) {
                          std::uint32_t seen = first_bad.load();
                          while (v < seen && !first_bad.compare_exchange_weak(seen, v)) {}
                          break;
                        }
                    });
  if (const std::uint32_t v = first_bad.load(); v != kNone) {
    std::vector<std::uint32_t> stamp(nv, kNone);
    std::string why;
    fans_ok(mesh, fans, v, stamp, &why);
    fail(why);
  }
}

void link_decoded_triangles(SurfaceMesh& mesh, const CornerTable& t,
                            std::span<const std::uint32_t> face_of_slot,
                            std::span<const std::uint32_t> rotation,
                            std::span<const std::uint32_t> vertex_slot, std::uint64_t where) {
  const std::size_t nc = 3 * face_of_slot.size();
  // Table corner c is the halfedge vertex(c) → vertex(next(c)): the edge opposite prev(c),
  // whose reverse starts at next(opposite(prev(c))).
  auto twin_of = [&](std::uint32_t c) {
    const std::uint32_t o = t.opposite[prev_corner(c)];
    return o == kNone ? kNone : next_corner(o);
  };
  auto is_identity = [](std::span<const std::uint32_t> p) {
    for (std::uint32_t i = 0; i < p.size(); ++i)
      if (p[i] != i) return false;
    return true;
  };
  std::vector<std::uint32_t> twin(nc, kNone);
  if (is_identity(face_of_slot) && is_identity(vertex_slot) &&
      std::all_of(rotation.begin(), rotation.end(), [](std::uint32_t r) { return r == 0; })) {
    // The decoder's own order (no order section): the table is the mesh's corners as they are.
    tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, static_cast<std::uint32_t>(nc), 3 * 4096),
                      [&](const tbb::blocked_range<std::uint32_t>& r) {
                        for (std::uint32_t c = r.begin(); c < r.end(); ++c) twin[c] = twin_of(c);
                      });
    link_triangles(mesh, t.vertex, twin, where);
    return;
  }
  std::vector<std::uint32_t> vertex(nc), out_corner(nc);
  for (std::uint32_t s = 0; s < face_of_slot.size(); ++s) {
    const std::uint32_t j = face_of_slot[s];
    for (std::uint32_t i = 0; i < 3; ++i) {
      const std::uint32_t c = 3 * j + (i + rotation[j]) % 3;
      vertex[3 * s + i] = vertex_slot[t.vertex[c]];
      out_corner[c] = 3 * s + i;
    }
  }
  for (std::uint32_t c = 0; c < nc; ++c)
    if (const std::uint32_t o = twin_of(c); o != kNone) twin[out_corner[c]] = out_corner[o];
  link_triangles(mesh, vertex, twin, where);
}

}  // namespace geom::codec::detail
