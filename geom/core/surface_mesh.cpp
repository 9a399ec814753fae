#include <geom/core/surface_mesh.h>

#include <geom/core/huge_pages.h>

#include <algorithm>
#include <string>

namespace geom {
namespace {

template <class H>
std::string name(H h) {
  return std::string(kind_name<H>()) + " " + std::to_string(h.idx());
}

}  // namespace

// ---- lifetime -----------------------------------------------------------------------------

SurfaceMesh::SurfaceMesh() { points_ = add_property<Vertex, Point>(kPositions, Point::Zero()); }

SurfaceMesh::SurfaceMesh(const SurfaceMesh& other) { *this = other; }

SurfaceMesh& SurfaceMesh::operator=(const SurfaceMesh& other) {
  if (this == &other) return *this;
  vconn_ = other.vconn_;
  hconn_ = other.hconn_;
  fconn_ = other.fconn_;
  vdeleted_ = other.vdeleted_;
  edeleted_ = other.edeleted_;
  fdeleted_ = other.fdeleted_;
  deleted_vertices_ = other.deleted_vertices_;
  deleted_edges_ = other.deleted_edges_;
  deleted_faces_ = other.deleted_faces_;
  vprops_ = other.vprops_;
  hprops_ = other.hprops_;
  eprops_ = other.eprops_;
  fprops_ = other.fprops_;
  // The copied container holds new arrays; the cached handle must point at ours.
  points_ = get_property<Vertex, Point>(kPositions);
  return *this;
}

// Moving a PropertyContainer moves the owning pointers, so cached handles stay valid.
SurfaceMesh::SurfaceMesh(SurfaceMesh&& other) noexcept = default;
SurfaceMesh& SurfaceMesh::operator=(SurfaceMesh&& other) noexcept = default;

void SurfaceMesh::reserve(std::size_t vertices, std::size_t edges, std::size_t faces) {
  vconn_.reserve(vertices);
  vdeleted_.reserve(vertices);
  vprops_.reserve(vertices);
  hconn_.reserve(2 * edges);
  hprops_.reserve(2 * edges);
  edeleted_.reserve(edges);
  eprops_.reserve(edges);
  fconn_.reserve(faces);
  fdeleted_.reserve(faces);
  fprops_.reserve(faces);
}

void SurfaceMesh::resize(std::size_t vertices, std::size_t edges, std::size_t faces) {
  if (vertices < vertices_size() || edges < edges_size() || faces < faces_size())
    throw InvalidArgument("SurfaceMesh::resize cannot remove elements (asked for " +
                          std::to_string(vertices) + " vertices, " + std::to_string(edges) +
                          " edges, " + std::to_string(faces) + " faces; the mesh has " +
                          std::to_string(vertices_size()) + ", " + std::to_string(edges_size()) +
                          ", " + std::to_string(faces_size()) + ")");
  // The same limits as new_vertex, new_edge and new_face.
  if (vertices > Vertex::kInvalid || 2 * edges + 1 >= Halfedge::kInvalid ||
      faces > Face::kInvalid)
    throw Error("too many elements for 32-bit handles");
  // Builders (subdivision's last level) grow a mesh by hundreds of megabytes here; mapping
  // the fresh pages in one call is cheaper than faulting them in one by one while filling.
  detail::resize_prefaulted(vconn_, vertices);
  detail::resize_prefaulted(vdeleted_, vertices, std::uint8_t{0});
  vprops_.resize(vertices);
  detail::resize_prefaulted(hconn_, 2 * edges);
  hprops_.resize(2 * edges);
  detail::resize_prefaulted(edeleted_, edges, std::uint8_t{0});
  eprops_.resize(edges);
  detail::resize_prefaulted(fconn_, faces);
  detail::resize_prefaulted(fdeleted_, faces, std::uint8_t{0});
  fprops_.resize(faces);
}

void SurfaceMesh::clear() { *this = SurfaceMesh(); }

std::size_t SurfaceMesh::connectivity_bytes() const {
  static_assert(sizeof(HalfedgeConnectivity) == 16, "halfedge record grew");
  return vconn_.capacity() * sizeof(Halfedge) + hconn_.capacity() * sizeof(HalfedgeConnectivity) +
         fconn_.capacity() * sizeof(Halfedge) + vdeleted_.capacity() + edeleted_.capacity() +
         fdeleted_.capacity();
}

// ---- element creation ---------------------------------------------------------------------

Vertex SurfaceMesh::new_vertex() {
  if (vconn_.size() >= Vertex::kInvalid) throw Error("too many vertices for 32-bit handles");
  vconn_.push_back(Halfedge());
  vdeleted_.push_back(0);
  vprops_.push_back();
  return Vertex(static_cast<std::uint32_t>(vconn_.size() - 1));
}

Vertex SurfaceMesh::add_vertex(const Point& p) {
  Vertex v = new_vertex();
  points_[v] = p;
  return v;
}

Halfedge SurfaceMesh::new_edge(Vertex a, Vertex b) {
  if (hconn_.size() + 2 >= Halfedge::kInvalid) throw Error("too many edges for 32-bit handles");
  hconn_.push_back({b, Halfedge(), Halfedge(), Face()});
  hconn_.push_back({a, Halfedge(), Halfedge(), Face()});
  hprops_.push_back();
  hprops_.push_back();
  edeleted_.push_back(0);
  eprops_.push_back();
  return Halfedge(static_cast<std::uint32_t>(hconn_.size() - 2));
}

Face SurfaceMesh::new_face() {
  if (fconn_.size() >= Face::kInvalid) throw Error("too many faces for 32-bit handles");
  fconn_.push_back(Halfedge());
  fdeleted_.push_back(0);
  fprops_.push_back();
  return Face(static_cast<std::uint32_t>(fconn_.size() - 1));
}

// ---- queries ------------------------------------------------------------------------------

bool SurfaceMesh::is_boundary(Face f) const {
  for (Halfedge h : halfedges(f))
    if (is_boundary(opposite(h))) return true;
  return false;
}

bool SurfaceMesh::is_manifold(Vertex v) const {
  int gaps = 0;
  for (Halfedge h : outgoing(v)) gaps += is_boundary(h) ? 1 : 0;
  return gaps < 2;
}

bool SurfaceMesh::is_triangle_mesh() const {
  for (Face f : faces())
    if (valence(f) != 3) return false;
  return true;
}

bool SurfaceMesh::is_quad_mesh() const {
  for (Face f : faces())
    if (valence(f) != 4) return false;
  return true;
}

std::size_t SurfaceMesh::valence(Vertex v) const {
  std::size_t n = 0;
  for ([[maybe_unused]] Halfedge h : outgoing(v)) ++n;
  return n;
}

std::size_t SurfaceMesh::valence(Face f) const {
  std::size_t n = 0;
  for ([[maybe_unused]] Halfedge h : halfedges(f)) ++n;
  return n;
}

Halfedge SurfaceMesh::find_halfedge(Vertex a, Vertex b) const {
  for (Halfedge h : outgoing(a))
    if (to_vertex(h) == b) return h;
  return Halfedge();
}

Edge SurfaceMesh::find_edge(Vertex a, Vertex b) const {
  Halfedge h = find_halfedge(a, b);
  return h.is_valid() ? edge(h) : Edge();
}

EdgeWings SurfaceMesh::wings(Edge e) const {
  Halfedge h0 = halfedge(e, 0), h1 = halfedge(e, 1);
  EdgeWings w;
  w.v0 = to_vertex(h1);
  w.v1 = to_vertex(h0);
  w.f0 = face(h0);
  w.f1 = face(h1);
  if (w.f0.is_valid()) {
    w.prev0 = edge(prev(h0));
    w.next0 = edge(next(h0));
  }
  if (w.f1.is_valid()) {
    w.prev1 = edge(prev(h1));
    w.next1 = edge(next(h1));
  }
  return w;
}

// ---- add_face -----------------------------------------------------------------------------

std::string SurfaceMesh::check_face(std::span<const Vertex> vs) const {
  const std::size_t n = vs.size();
  if (n < 3) return "a face needs at least 3 vertices, got " + std::to_string(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_valid(vs[i]) || is_deleted(vs[i])) return "corner " + std::to_string(i) + " is not a live vertex";
    for (std::size_t j = i + 1; j < n; ++j)
      if (vs[i] == vs[j]) return name(vs[i]) + " appears twice in the face";
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_boundary(vs[i])) return "complex vertex: " + name(vs[i]) + " has no free boundary gap";
    Halfedge h = find_halfedge(vs[i], vs[(i + 1) % n]);
    if (h.is_valid() && !is_boundary(h))
      return "complex edge: " + name(vs[i]) + " -> " + name(vs[(i + 1) % n]) +
             " already has a face on this side";
  }
  // Two consecutive existing edges whose boundary loops cannot be re-linked: the vertex
  // between them would need a second gap that does not exist.
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t ii = (i + 1) % n;
    Halfedge in = find_halfedge(vs[i], vs[ii]), out = find_halfedge(vs[ii], vs[(ii + 1) % n]);
    if (!in.is_valid() || !out.is_valid() || next(in) == out) continue;
    bool other_gap = false;
    for (Halfedge h : incoming(vs[ii]))
      if (h != in && is_boundary(h)) other_gap = true;
    if (!other_gap) return "complex vertex: cannot re-link the boundary at " + name(vs[ii]);
  }
  return {};
}

Face SurfaceMesh::add_face(std::span<const Vertex> vs) {
  if (std::string why = check_face(vs); !why.empty()) throw TopologyError("add_face: " + why);
  const std::size_t n = vs.size();

  // Existing halfedges along the face; invalid where the edge is new.
  std::vector<Halfedge> hs(n);
  std::vector<std::uint8_t> is_new(n);
  for (std::size_t i = 0; i < n; ++i) {
    hs[i] = find_halfedge(vs[i], vs[(i + 1) % n]);
    is_new[i] = !hs[i].is_valid();
  }

  // Where two consecutive edges exist but are not consecutive on the boundary, the patch of
  // boundary between them is moved to another gap of the shared vertex so they can be.
  std::vector<std::pair<Halfedge, Halfedge>> links;
  links.reserve(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t ii = (i + 1) % n;
    if (is_new[i] || is_new[ii]) continue;
    Halfedge inner_prev = hs[i], inner_next = hs[ii];
    if (next(inner_prev) == inner_next) continue;
    Halfedge boundary_prev = opposite(inner_next);
    do {
      boundary_prev = opposite(next(boundary_prev));
    } while (!is_boundary(boundary_prev) || boundary_prev == inner_prev);
    Halfedge boundary_next = next(boundary_prev);
    Halfedge patch_start = next(inner_prev), patch_end = prev(inner_next);
    set_next(boundary_prev, patch_start);
    set_next(patch_end, boundary_next);
    set_next(inner_prev, inner_next);
  }

  for (std::size_t i = 0; i < n; ++i)
    if (is_new[i]) hs[i] = new_edge(vs[i], vs[(i + 1) % n]);

  Face f = new_face();
  set_halfedge(f, hs[n - 1]);  // ends at the first corner: vertices(f) yields vs in order

  std::vector<Vertex> needs_adjust;
  for (std::size_t i = 0; i < n; ++i) {
    std::size_t ii = (i + 1) % n;
    Vertex v = vs[ii];
    Halfedge inner_prev = hs[i], inner_next = hs[ii];
    Halfedge outer_prev = opposite(inner_next), outer_next = opposite(inner_prev);
    const int id = (is_new[i] ? 1 : 0) | (is_new[ii] ? 2 : 0);
    if (id == 1) {  // new edge arrives, existing edge leaves
      Halfedge boundary_prev = prev(inner_next);
      links.emplace_back(boundary_prev, outer_next);
      set_halfedge(v, outer_next);
    } else if (id == 2) {  // existing edge arrives, new edge leaves
      Halfedge boundary_next = next(inner_prev);
      links.emplace_back(outer_prev, boundary_next);
      set_halfedge(v, boundary_next);
    } else if (id == 3) {  // both new
      if (!halfedge(v).is_valid()) {
        set_halfedge(v, outer_next);
        links.emplace_back(outer_prev, outer_next);
      } else {
        Halfedge boundary_next = halfedge(v), boundary_prev = prev(boundary_next);
        links.emplace_back(boundary_prev, outer_next);
        links.emplace_back(outer_prev, boundary_next);
      }
    } else if (halfedge(v) == inner_next) {
      needs_adjust.push_back(v);
    }
    links.emplace_back(inner_prev, inner_next);
    set_face(hs[i], f);
  }
  for (auto [h, nx] : links) set_next(h, nx);
  for (Vertex v : needs_adjust) adjust_outgoing_halfedge(v);
  return f;
}

void SurfaceMesh::adjust_outgoing_halfedge(Vertex v) {
  Halfedge start = halfedge(v);
  if (!start.is_valid()) return;
  Halfedge h = start;
  do {
    if (is_boundary(h)) {
      set_halfedge(v, h);
      return;
    }
    h = ccw_rotated(h);
  } while (h != start);
}

// ---- deletion -----------------------------------------------------------------------------

void SurfaceMesh::delete_edge_links(Halfedge h0) {
  Halfedge h1 = opposite(h0);
  Vertex v0 = to_vertex(h0), v1 = to_vertex(h1);
  Halfedge next0 = next(h0), prev0 = prev(h0), next1 = next(h1), prev1 = prev(h1);
  set_next(prev0, next1);
  set_next(prev1, next0);
  if (halfedge(v0) == h1) {
    if (next0 == h1) {
      vdeleted_[v0.idx()] = 1;
      ++deleted_vertices_;
      set_halfedge(v0, Halfedge());
    } else {
      set_halfedge(v0, next0);
    }
  }
  if (halfedge(v1) == h0) {
    if (next1 == h0) {
      vdeleted_[v1.idx()] = 1;
      ++deleted_vertices_;
      set_halfedge(v1, Halfedge());
    } else {
      set_halfedge(v1, next1);
    }
  }
  edeleted_[edge(h0).idx()] = 1;
  ++deleted_edges_;
}

void SurfaceMesh::delete_face(Face f) {
  if (is_deleted(f)) return;
  std::vector<Halfedge> dead_edges;
  std::vector<Vertex> corners;
  for (Halfedge h : halfedges(f)) {
    set_face(h, Face());
    if (is_boundary(opposite(h))) dead_edges.push_back(h);
    corners.push_back(to_vertex(h));
  }
  for (Halfedge h : dead_edges) delete_edge_links(h);
  for (Vertex v : corners)
    if (!is_deleted(v)) adjust_outgoing_halfedge(v);
  fdeleted_[f.idx()] = 1;
  ++deleted_faces_;
}

void SurfaceMesh::delete_edge(Edge e) {
  if (is_deleted(e)) return;
  Face f0 = face(halfedge(e, 0)), f1 = face(halfedge(e, 1));
  if (f0.is_valid()) delete_face(f0);
  if (f1.is_valid()) delete_face(f1);
}

void SurfaceMesh::delete_vertex(Vertex v) {
  if (is_deleted(v)) return;
  std::vector<Face> around;
  for (Face f : faces(v))
    if (f.is_valid()) around.push_back(f);
  for (Face f : around) delete_face(f);
  if (!is_deleted(v)) {  // it was isolated
    vdeleted_[v.idx()] = 1;
    ++deleted_vertices_;
  }
}

CompactRemap SurfaceMesh::compact() {
  CompactRemap map;
  std::vector<std::uint32_t> keep_v, keep_h, keep_e, keep_f;
  map.vertices.assign(vertices_size(), Vertex());
  for (std::uint32_t i = 0; i < vertices_size(); ++i)
    if (!vdeleted_[i]) {
      map.vertices[i] = Vertex(static_cast<std::uint32_t>(keep_v.size()));
      keep_v.push_back(i);
    }
  map.edges.assign(edges_size(), Edge());
  map.halfedges.assign(halfedges_size(), Halfedge());
  for (std::uint32_t i = 0; i < edges_size(); ++i)
    if (!edeleted_[i]) {
      auto e = static_cast<std::uint32_t>(keep_e.size());
      map.edges[i] = Edge(e);
      map.halfedges[2 * i] = Halfedge(2 * e);
      map.halfedges[2 * i + 1] = Halfedge(2 * e + 1);
      keep_e.push_back(i);
      keep_h.push_back(2 * i);
      keep_h.push_back(2 * i + 1);
    }
  map.faces.assign(faces_size(), Face());
  for (std::uint32_t i = 0; i < faces_size(); ++i)
    if (!fdeleted_[i]) {
      map.faces[i] = Face(static_cast<std::uint32_t>(keep_f.size()));
      keep_f.push_back(i);
    }

  auto hmap = [&](Halfedge h) { return h.is_valid() ? map.halfedges[h.idx()] : h; };
  std::vector<Halfedge> vconn(keep_v.size());
  for (std::size_t i = 0; i < keep_v.size(); ++i) vconn[i] = hmap(vconn_[keep_v[i]]);
  std::vector<HalfedgeConnectivity> hconn(keep_h.size());
  for (std::size_t i = 0; i < keep_h.size(); ++i) {
    const HalfedgeConnectivity& c = hconn_[keep_h[i]];
    hconn[i] = {map.vertices[c.to.idx()], hmap(c.next), hmap(c.prev),
                c.face.is_valid() ? map.faces[c.face.idx()] : Face()};
  }
  std::vector<Halfedge> fconn(keep_f.size());
  for (std::size_t i = 0; i < keep_f.size(); ++i) fconn[i] = hmap(fconn_[keep_f[i]]);

  vconn_.swap(vconn);
  hconn_.swap(hconn);
  fconn_.swap(fconn);
  vprops_.gather(keep_v);
  hprops_.gather(keep_h);
  eprops_.gather(keep_e);
  fprops_.gather(keep_f);
  vdeleted_.assign(keep_v.size(), 0);
  edeleted_.assign(keep_e.size(), 0);
  fdeleted_.assign(keep_f.size(), 0);
  deleted_vertices_ = deleted_edges_ = deleted_faces_ = 0;
  return map;
}

// ---- flip, splits -------------------------------------------------------------------------

bool SurfaceMesh::can_flip(Edge e) const {
  if (is_deleted(e) || is_boundary(e)) return false;
  Halfedge h0 = halfedge(e, 0), h1 = halfedge(e, 1);
  if (next(next(next(h0))) != h0 || next(next(next(h1))) != h1) return false;
  Vertex a = to_vertex(next(h0)), b = to_vertex(next(h1));
  if (a == b) return false;
  return !find_halfedge(a, b).is_valid();
}

void SurfaceMesh::flip(Edge e) {
  if (!can_flip(e)) throw TopologyError("flip: " + name(e) + " cannot be flipped");
  Halfedge a0 = halfedge(e, 0), b0 = halfedge(e, 1);
  Halfedge a1 = next(a0), a2 = next(a1);
  Halfedge b1 = next(b0), b2 = next(b1);
  Vertex va0 = to_vertex(a0), va1 = to_vertex(a1);
  Vertex vb0 = to_vertex(b0), vb1 = to_vertex(b1);
  Face fa = face(a0), fb = face(b0);

  set_vertex(a0, va1);
  set_vertex(b0, vb1);
  set_next(a0, a2);
  set_next(a2, b1);
  set_next(b1, a0);
  set_next(b0, b2);
  set_next(b2, a1);
  set_next(a1, b0);
  set_face(a1, fb);
  set_face(b1, fa);
  set_halfedge(fa, a0);
  set_halfedge(fb, b0);
  if (halfedge(va0) == b0) set_halfedge(va0, a1);
  if (halfedge(vb0) == a0) set_halfedge(vb0, b1);
}

Halfedge SurfaceMesh::insert_vertex(Edge e, const Point& p) {
  // h0: v0 -> v1 becomes h0: v0 -> v and new: v -> v1, with its opposite pair.
  Halfedge h0 = halfedge(e, 0), o0 = opposite(h0);
  Vertex v1 = to_vertex(h0);
  Vertex v = add_vertex(p);
  Halfedge h1 = new_edge(v, v1), o1 = opposite(h1);
  Face fh = face(h0), fo = face(o0);
  Halfedge hn = next(h0), op = prev(o0);

  set_vertex(h0, v);
  set_next(h1, hn);
  set_next(h0, h1);
  set_face(h1, fh);
  // o0: v1 -> v0 becomes o1: v1 -> v followed by o0: v -> v0.
  set_next(op, o1);
  set_next(o1, o0);
  set_face(o1, fo);
  set_halfedge(v, h1);
  adjust_outgoing_halfedge(v);
  if (halfedge(v1) == o0) set_halfedge(v1, o1);
  // Keep the face's first corner: halfedge(f) ends at it.
  if (fh.is_valid() && halfedge(fh) == h0) set_halfedge(fh, h1);
  return h1;
}

Halfedge SurfaceMesh::insert_edge(Halfedge h0, Halfedge h1) {
  Face f = face(h0);
  if (!f.is_valid() || face(h1) != f || h0 == h1 || next(h0) == h1 || next(h1) == h0)
    throw TopologyError("insert_edge: " + name(h0) + " and " + name(h1) +
                        " must be distinct, non-adjacent halfedges of one face");
  Vertex v0 = to_vertex(h0), v1 = to_vertex(h1);
  if (find_halfedge(v0, v1).is_valid())
    throw TopologyError("insert_edge: " + name(v0) + " and " + name(v1) + " are already connected");
  Halfedge h2 = next(h0), h3 = next(h1);
  Halfedge a = new_edge(v0, v1), b = opposite(a);  // a: v0 -> v1 stays in f
  Face g = new_face();
  set_next(h0, a);
  set_next(a, h3);
  set_face(a, f);
  set_halfedge(f, a);
  set_next(h1, b);
  set_next(b, h2);
  for (Halfedge h = b;; h = next(h)) {
    set_face(h, g);
    if (h == h1) break;
  }
  set_halfedge(g, b);
  return a;
}

Vertex SurfaceMesh::split_edge(Edge e, const Point& p) {
  for (unsigned i = 0; i < 2; ++i) {
    Halfedge h = halfedge(e, i);
    if (!is_boundary(h) && valence(face(h)) != 3)
      throw TopologyError("split_edge: " + name(face(h)) + " next to " + name(e) + " is not a triangle");
  }
  Halfedge h0 = halfedge(e, 0);
  Halfedge o0 = opposite(h0);
  Halfedge h1 = insert_vertex(e, p);  // h0: v0 -> v, h1: v -> v1
  Vertex v = to_vertex(h0);
  // Each side is now a quad; cut it from v to the far corner.
  if (!is_boundary(h1)) insert_edge(next(h1), h0);
  if (!is_boundary(o0)) insert_edge(prev(o0), next(o0));
  return v;
}

Vertex SurfaceMesh::split_face(Face f, const Point& p) {
  std::vector<Halfedge> ring;
  for (Halfedge h : halfedges(f)) ring.push_back(h);
  Vertex v = add_vertex(p);
  const std::size_t n = ring.size();
  // Spokes: spoke[i] runs from v to to_vertex(ring[i]).
  std::vector<Halfedge> spoke(n);
  for (std::size_t i = 0; i < n; ++i) spoke[i] = new_edge(v, to_vertex(ring[i]));
  for (std::size_t i = 0; i < n; ++i) {
    // Triangle i: ring[i] (a -> b), spoke to v reversed, spoke out to a.
    Halfedge in = ring[i];
    Halfedge back = opposite(spoke[i]);           // b -> v
    Halfedge out = spoke[(i + n - 1) % n];       // v -> a
    Face t = i == 0 ? f : new_face();
    set_next(in, back);
    set_next(back, out);
    set_next(out, in);
    set_face(in, t);
    set_face(back, t);
    set_face(out, t);
    set_halfedge(t, in);
  }
  set_halfedge(v, spoke[0]);
  return v;
}

// ---- collapse -----------------------------------------------------------------------------

bool SurfaceMesh::collapse_would_fold_tetrahedron(Halfedge h, Vertex vl, Vertex vr) const {
  // Triangles (v0, vl, vr) and (v1, vl, vr) both present: the collapse would glue them.
  if (!vl.is_valid() || !vr.is_valid()) return false;
  Halfedge lr = find_halfedge(vl, vr);
  if (!lr.is_valid()) return false;
  Vertex v0 = from_vertex(h), v1 = to_vertex(h);
  auto third = [&](Halfedge x) {
    return is_boundary(x) || next(next(next(x))) != x ? Vertex() : to_vertex(next(x));
  };
  Vertex a = third(lr), b = third(opposite(lr));
  return (a == v0 && b == v1) || (a == v1 && b == v0);
}

bool SurfaceMesh::can_collapse(Halfedge h) const {
  if (!is_valid(h) || is_deleted(h)) return false;
  Halfedge o = opposite(h);
  Vertex v0 = to_vertex(o), v1 = to_vertex(h);

  // The corner opposite h on a triangular side, else invalid.
  auto apex = [&](Halfedge x) -> Vertex {
    if (is_boundary(x) || next(next(next(x))) != x) return Vertex();
    return to_vertex(next(x));
  };
  Vertex vl = apex(h), vr = apex(o);

  // An interior edge between two boundary vertices would pinch the surface.
  if (is_boundary(v0) && is_boundary(v1) && !is_boundary(h) && !is_boundary(o)) return false;
  // A triangle whose two other edges are both on the boundary would dangle.
  for (Halfedge x : {h, o}) {
    if (is_boundary(x) || next(next(next(x))) != x) continue;
    if (is_boundary(opposite(next(x))) && is_boundary(opposite(prev(x)))) return false;
  }
  // Link condition: the common neighbours of v0 and v1 are exactly the apexes.
  for (Vertex w : vertices(v0)) {
    if (w == v1 || w == vl || w == vr) continue;
    if (find_halfedge(w, v1).is_valid()) return false;
  }
  if (vl.is_valid() && vl == vr) return false;
  // An apex with only the two edges of its vanishing triangle would be left hanging on a
  // single edge inside the neighbouring face (possible next to polygons).
  for (Vertex apex_vertex : {vl, vr})
    if (apex_vertex.is_valid() && valence(apex_vertex) <= 2) return false;
  return !collapse_would_fold_tetrahedron(h, vl, vr);
}

void SurfaceMesh::collapse(Halfedge h) {
  if (!can_collapse(h)) throw TopologyError("collapse: " + name(h) + " fails the link condition");
  Halfedge h0 = h, h1 = prev(h0), o0 = opposite(h0), o1 = next(o0);
  remove_edge_helper(h0);
  if (next(next(h1)) == h1) remove_loop_helper(h1);
  if (next(next(o1)) == o1) remove_loop_helper(o1);
}

void SurfaceMesh::remove_edge_helper(Halfedge h) {
  Halfedge hn = next(h), hp = prev(h);
  Halfedge o = opposite(h), on = next(o), op = prev(o);
  Face fh = face(h), fo = face(o);
  Vertex vh = to_vertex(h), vo = to_vertex(o);

  std::vector<Halfedge> in;
  for (Halfedge x : incoming(vo)) in.push_back(x);
  for (Halfedge x : in) set_vertex(x, vh);

  set_next(hp, hn);
  set_next(op, on);
  if (fh.is_valid()) set_halfedge(fh, hn);
  if (fo.is_valid()) set_halfedge(fo, on);
  if (halfedge(vh) == o) set_halfedge(vh, hn);
  adjust_outgoing_halfedge(vh);
  set_halfedge(vo, Halfedge());

  vdeleted_[vo.idx()] = 1;
  ++deleted_vertices_;
  edeleted_[edge(h).idx()] = 1;
  ++deleted_edges_;
}

void SurfaceMesh::remove_loop_helper(Halfedge h) {
  // h and next(h) bound a two-sided face left by a collapsed triangle: drop it and its edge h.
  Halfedge h0 = h, h1 = next(h0);
  Halfedge o0 = opposite(h0), o1 = opposite(h1);
  Vertex v0 = to_vertex(h0), v1 = to_vertex(h1);
  Face fh = face(h0), fo = face(o0);

  set_next(h1, next(o0));
  set_next(prev(o0), h1);
  set_face(h1, fo);
  set_halfedge(v0, h1);
  adjust_outgoing_halfedge(v0);
  set_halfedge(v1, o1);
  adjust_outgoing_halfedge(v1);
  if (fo.is_valid() && halfedge(fo) == o0) set_halfedge(fo, h1);

  if (fh.is_valid()) {
    fdeleted_[fh.idx()] = 1;
    ++deleted_faces_;
  }
  edeleted_[edge(h0).idx()] = 1;
  ++deleted_edges_;
}

namespace {

template <class H>
void add_missing(const SurfaceMesh& from, const SurfaceMesh& to, std::vector<std::string>& out) {
  for (const std::string& name : from.property_names<H>())
    if (!to.has_property<H>(name)) out.push_back(name);
}

}  // namespace

std::vector<std::string> missing_properties(const SurfaceMesh& from, const SurfaceMesh& to) {
  std::vector<std::string> out;
  add_missing<Vertex>(from, to, out);
  add_missing<Halfedge>(from, to, out);
  add_missing<Edge>(from, to, out);
  add_missing<Face>(from, to, out);
  return out;
}

}  // namespace geom
