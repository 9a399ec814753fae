#pragma once
/// \file
/// SurfaceMesh: a half-edge polygon mesh (triangles, quads and n-gons mixed) with strongly
/// typed 32-bit handles and structure-of-arrays storage.
///
/// Memory (measured by tests/core/test_memory.cpp): per vertex 4 B connectivity + 1 B flag +
/// 24 B position; per edge 2 × 16 B halfedge connectivity + 1 B flag; per face 4 B + 1 B. A
/// closed triangle mesh (E ≈ 3V, F ≈ 2V) therefore takes about 138 B per vertex with
/// positions, before user properties.
///
/// Ref: Botsch, Kobbelt, Pauly, Alliez, Lévy, "Polygon Mesh Processing", 2010, ch. 2.

#include <geom/core/errors.h>
#include <geom/core/handles.h>
#include <geom/core/properties.h>
#include <geom/core/ranges.h>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <initializer_list>
#include <span>
#include <string>
#include <vector>

namespace geom {

using Point = Eigen::Vector3d;
using Normal = Eigen::Vector3d;
using TexCoord = Eigen::Vector2d;
using Color = Eigen::Vector3d;  ///< linear RGB in [0, 1]

/// The O(1) winged-edge view of one edge: its two vertices, its two faces (invalid on the
/// boundary side) and the four wing edges (prev/next on each side; invalid where a side has
/// no face).
struct EdgeWings {
  Vertex v0, v1;               ///< v0 = from(halfedge(e, 0)), v1 = to(halfedge(e, 0))
  Face f0, f1;                 ///< face(halfedge(e, 0)), face(halfedge(e, 1))
  Edge prev0, next0;           ///< wings on the f0 side
  Edge prev1, next1;           ///< wings on the f1 side
};

/// The old → new handle maps that compact() returns; deleted elements map to invalid.
struct CompactRemap {
  std::vector<Vertex> vertices;
  std::vector<Halfedge> halfedges;
  std::vector<Edge> edges;
  std::vector<Face> faces;
};

class SurfaceMesh {
 public:
  SurfaceMesh();
  SurfaceMesh(const SurfaceMesh& other);
  SurfaceMesh& operator=(const SurfaceMesh& other);
  SurfaceMesh(SurfaceMesh&& other) noexcept;
  SurfaceMesh& operator=(SurfaceMesh&& other) noexcept;
  ~SurfaceMesh() = default;

  // ---- sizes --------------------------------------------------------------------------
  /// Live elements (deleted ones not counted).
  std::size_t n_vertices() const { return vconn_.size() - deleted_vertices_; }
  std::size_t n_halfedges() const { return 2 * n_edges(); }
  std::size_t n_edges() const { return edeleted_.size() - deleted_edges_; }
  std::size_t n_faces() const { return fconn_.size() - deleted_faces_; }
  bool is_empty() const { return n_vertices() == 0; }
  /// Array sizes, counting deleted elements (the valid index range).
  std::size_t vertices_size() const { return vconn_.size(); }
  std::size_t halfedges_size() const { return hconn_.size(); }
  std::size_t edges_size() const { return edeleted_.size(); }
  std::size_t faces_size() const { return fconn_.size(); }
  bool has_garbage() const { return deleted_vertices_ + deleted_edges_ + deleted_faces_ > 0; }

  void reserve(std::size_t vertices, std::size_t edges, std::size_t faces);
  /// Bulk allocation for builders that compute whole connectivity arrays (subdivision,
  /// indexed formats): grow the arrays to exactly `vertices`, `edges` and `faces` elements in
  /// one step, as `vertices - vertices_size()` calls of new_vertex() and so on would, at the
  /// cost of a memory fill. The new elements are live and unlinked (every handle they hold is
  /// invalid, every property at its default); the caller links them with set_vertex,
  /// set_next, set_face and set_halfedge, and the mesh is valid again once every new
  /// halfedge has a vertex, next and prev, every new face a halfedge and every vertex an
  /// outgoing halfedge that is a boundary one if it has any (validate() checks all that).
  /// Throws: InvalidArgument when a count is below the current size (elements are removed
  /// with delete_* and compact()); Error when it exceeds 32-bit handles.
  void resize(std::size_t vertices, std::size_t edges, std::size_t faces);
  /// Remove everything, properties included (positions are re-added).
  void clear();

  // ---- construction -------------------------------------------------------------------
  Vertex add_vertex(const Point& p);
  /// Add a face through the given vertices in order (counter-clockwise seen from outside).
  /// Pre: at least 3 distinct valid vertices.
  /// Throws: TopologyError when the face would create a complex edge (an edge with three
  /// faces, or one already used in the same direction) or a complex vertex (a vertex that
  /// is not on the boundary); the mesh is unchanged then.
  /// Complexity: O(sum of valences of the face's vertices).
  Face add_face(std::span<const Vertex> vertices);
  Face add_face(std::initializer_list<Vertex> vertices) {
    return add_face(std::span<const Vertex>(vertices.begin(), vertices.size()));
  }
  Face add_triangle(Vertex a, Vertex b, Vertex c) { return add_face({a, b, c}); }
  Face add_quad(Vertex a, Vertex b, Vertex c, Vertex d) { return add_face({a, b, c, d}); }
  /// Why add_face would throw for these vertices, or an empty string when it would not.
  std::string check_face(std::span<const Vertex> vertices) const;

  // ---- navigation (all O(1)) ----------------------------------------------------------
  Halfedge halfedge(Vertex v) const { return vconn_[v.idx()]; }
  Halfedge halfedge(Face f) const { return fconn_[f.idx()]; }
  static Halfedge halfedge(Edge e, unsigned i) { return Halfedge(2 * e.idx() + (i & 1)); }
  Vertex to_vertex(Halfedge h) const { return hconn_[h.idx()].to; }
  Vertex from_vertex(Halfedge h) const { return to_vertex(opposite(h)); }
  Halfedge next(Halfedge h) const { return hconn_[h.idx()].next; }
  Halfedge prev(Halfedge h) const { return hconn_[h.idx()].prev; }
  static Halfedge opposite(Halfedge h) { return Halfedge(h.idx() ^ 1u); }
  static Edge edge(Halfedge h) { return Edge(h.idx() >> 1); }
  Face face(Halfedge h) const { return hconn_[h.idx()].face; }
  Vertex vertex(Edge e, unsigned i) const { return to_vertex(halfedge(e, i)); }
  Face face(Edge e, unsigned i) const { return face(halfedge(e, i)); }
  /// Next outgoing halfedge counter-clockwise around from_vertex(h).
  Halfedge ccw_rotated(Halfedge h) const { return opposite(prev(h)); }
  /// Next outgoing halfedge clockwise around from_vertex(h).
  Halfedge cw_rotated(Halfedge h) const { return next(opposite(h)); }

  bool is_boundary(Halfedge h) const { return !face(h).is_valid(); }
  bool is_boundary(Edge e) const {
    return is_boundary(halfedge(e, 0)) || is_boundary(halfedge(e, 1));
  }
  /// A vertex is on the boundary when it is isolated or has a boundary outgoing halfedge
  /// (the vertex's stored halfedge is a boundary one whenever it has any).
  bool is_boundary(Vertex v) const {
    Halfedge h = halfedge(v);
    return !h.is_valid() || is_boundary(h);
  }
  bool is_boundary(Face f) const;
  bool is_isolated(Vertex v) const { return !halfedge(v).is_valid(); }
  /// At most one boundary gap around v (a single fan); isolated vertices count as manifold.
  bool is_manifold(Vertex v) const;
  bool is_triangle_mesh() const;
  bool is_quad_mesh() const;

  /// Number of edges at v. Complexity: O(valence).
  std::size_t valence(Vertex v) const;
  /// Number of corners of f. Complexity: O(valence).
  std::size_t valence(Face f) const;
  /// The halfedge from a to b, or invalid. Complexity: O(valence(a)).
  Halfedge find_halfedge(Vertex a, Vertex b) const;
  Edge find_edge(Vertex a, Vertex b) const;
  /// The winged-edge record of e. Complexity: O(1).
  EdgeWings wings(Edge e) const;

  // ---- ranges -------------------------------------------------------------------------
  ElementRange<Vertex> vertices() const { return {this, static_cast<std::uint32_t>(vertices_size())}; }
  ElementRange<Halfedge> halfedges() const { return {this, static_cast<std::uint32_t>(halfedges_size())}; }
  ElementRange<Edge> edges() const { return {this, static_cast<std::uint32_t>(edges_size())}; }
  ElementRange<Face> faces() const { return {this, static_cast<std::uint32_t>(faces_size())}; }

  struct CcwStep { Halfedge operator()(const SurfaceMesh& m, Halfedge h) const { return m.ccw_rotated(h); } };
  struct NextStep { Halfedge operator()(const SurfaceMesh& m, Halfedge h) const { return m.next(h); } };
  struct SameHalfedge { Halfedge operator()(const SurfaceMesh&, Halfedge h) const { return h; } };
  struct ToVertex { Vertex operator()(const SurfaceMesh& m, Halfedge h) const { return m.to_vertex(h); } };
  struct FaceOf { Face operator()(const SurfaceMesh& m, Halfedge h) const { return m.face(h); } };
  struct EdgeOf { Edge operator()(const SurfaceMesh&, Halfedge h) const { return edge(h); } };
  struct OppositeOf { Halfedge operator()(const SurfaceMesh&, Halfedge h) const { return opposite(h); } };

  /// Outgoing halfedges of v, counter-clockwise, starting at halfedge(v).
  CirculatorRange<Halfedge, CcwStep, SameHalfedge> outgoing(Vertex v) const { return {this, halfedge(v)}; }
  /// Incoming halfedges of v (the opposites of outgoing(v)).
  CirculatorRange<Halfedge, CcwStep, OppositeOf> incoming(Vertex v) const { return {this, halfedge(v)}; }
  /// The one-ring neighbours of v, counter-clockwise.
  CirculatorRange<Vertex, CcwStep, ToVertex> vertices(Vertex v) const { return {this, halfedge(v)}; }
  CirculatorRange<Edge, CcwStep, EdgeOf> edges(Vertex v) const { return {this, halfedge(v)}; }
  /// Faces around v; yields an invalid Face for each boundary gap (check with is_valid()).
  CirculatorRange<Face, CcwStep, FaceOf> faces(Vertex v) const { return {this, halfedge(v)}; }
  /// The halfedges of f in order; the first ends at the face's first corner.
  CirculatorRange<Halfedge, NextStep, SameHalfedge> halfedges(Face f) const { return {this, halfedge(f)}; }
  /// The corners of f in order (counter-clockwise).
  CirculatorRange<Vertex, NextStep, ToVertex> vertices(Face f) const { return {this, halfedge(f)}; }

  // ---- positions and properties -------------------------------------------------------
  Point& position(Vertex v) { return points_[v]; }
  const Point& position(Vertex v) const { return points_[v]; }
  Property<Vertex, Point> positions() { return points_; }
  Property<Vertex, const Point> positions() const { return points_; }

  /// Add a property named `name` on elements of kind H. Names by convention start with the
  /// kind: "v:", "h:", "e:", "f:". Throws: InvalidArgument if the name is taken.
  template <class H, class T>
  Property<H, T> add_property(const std::string& name, T default_value = detail::zero_value<T>()) {
    return Property<H, T>(props<H>().template add<T>(name, std::move(default_value)));
  }
  /// The property, or a null handle when absent (or of another type).
  template <class H, class T>
  Property<H, T> get_property(const std::string& name) {
    return Property<H, T>(props<H>().template get<T>(name));
  }
  template <class H, class T>
  Property<H, const T> get_property(const std::string& name) const {
    return Property<H, const T>(props<H>().template get<T>(name));
  }
  template <class H, class T>
  Property<H, T> get_or_add_property(const std::string& name,
                                     T default_value = detail::zero_value<T>()) {
    auto p = get_property<H, T>(name);
    return p ? p : add_property<H, T>(name, std::move(default_value));
  }
  template <class H>
  bool has_property(const std::string& name) const { return props<H>().exists(name); }
  /// Remove a property; positions ("v:point") cannot be removed.
  template <class H, class T>
  void remove_property(Property<H, T>& p) {
    remove_property<H>(p.name());
    p = Property<H, T>();
  }
  template <class H>
  void remove_property(const std::string& name) {
    if constexpr (std::is_same_v<H, Vertex>)
      if (name == kPositions) throw InvalidArgument("the positions property cannot be removed");
    props<H>().remove(name);
  }
  template <class H>
  std::vector<std::string> property_names() const { return props<H>().names(); }
  template <class H>
  PropertyContainer& props();
  template <class H>
  const PropertyContainer& props() const;

  static constexpr const char* kPositions = "v:point";
  /// Connectivity bytes per element (flags included, properties excluded); tested so the
  /// core structure does not creep.
  static constexpr std::size_t kBytesPerVertex = sizeof(Halfedge) + 1;
  static constexpr std::size_t kBytesPerEdge = 2 * (sizeof(Vertex) + 2 * sizeof(Halfedge) + sizeof(Face)) + 1;
  static constexpr std::size_t kBytesPerFace = sizeof(Halfedge) + 1;
  /// Bytes the connectivity arrays hold now (capacity, not size), properties excluded.
  std::size_t connectivity_bytes() const;

  // ---- deletion and garbage -----------------------------------------------------------
  bool is_deleted(Vertex v) const { return vdeleted_[v.idx()] != 0; }
  bool is_deleted(Halfedge h) const { return edeleted_[h.idx() >> 1] != 0; }
  bool is_deleted(Edge e) const { return edeleted_[e.idx()] != 0; }
  bool is_deleted(Face f) const { return fdeleted_[f.idx()] != 0; }
  bool is_valid(Vertex v) const { return v.idx() < vertices_size(); }
  bool is_valid(Halfedge h) const { return h.idx() < halfedges_size(); }
  bool is_valid(Edge e) const { return e.idx() < edges_size(); }
  bool is_valid(Face f) const { return f.idx() < faces_size(); }

  /// Delete a face; edges left without faces and vertices left isolated go with it.
  void delete_face(Face f);
  /// Delete an edge and its (up to two) faces.
  void delete_edge(Edge e);
  /// Delete a vertex and every face around it.
  void delete_vertex(Vertex v);
  /// Drop deleted elements from every array and property at once.
  /// Returns: old → new handle maps, so callers holding handles can translate them.
  /// Complexity: O(V + E + F) times the number of properties.
  CompactRemap compact();

  // ---- editing: check, then act --------------------------------------------------------
  /// True when flipping e keeps the mesh valid: both sides are triangles and the new edge
  /// does not exist yet.
  bool can_flip(Edge e) const;
  /// Throws: TopologyError when !can_flip(e).
  void flip(Edge e);

  /// Insert a new vertex at p on edge e (both faces gain a corner; no new edges besides
  /// the split). Returns the halfedge from the new vertex to the old to_vertex of
  /// halfedge(e, 0). Works on any polygon mesh.
  Halfedge insert_vertex(Edge e, const Point& p);
  /// Split e at p and connect the new vertex to the opposite corner of each adjacent
  /// triangle (2 → 4 triangles, 1 → 2 on the boundary). Returns the new vertex.
  /// Throws: TopologyError when an adjacent face is not a triangle.
  Vertex split_edge(Edge e, const Point& p);
  /// Split f into a fan of triangles around a new vertex at p. Returns the new vertex.
  Vertex split_face(Face f, const Point& p);
  /// Connect two corners of a face by a new edge, splitting the face in two. Returns the
  /// new halfedge from from_vertex(h0)'s ... see source. Pre: h0, h1 in the same face and
  /// not adjacent. Throws: TopologyError otherwise.
  Halfedge insert_edge(Halfedge h0, Halfedge h1);

  /// The link condition for collapsing from_vertex(h) into to_vertex(h): the result stays a
  /// manifold mesh with no new non-manifold edge or vertex, no dangling triangle, and no
  /// tetrahedron flattened into two faces. Pure query.
  bool can_collapse(Halfedge h) const;
  /// Collapse from_vertex(h) into to_vertex(h); triangles on either side disappear, larger
  /// faces lose a corner. Throws: TopologyError when !can_collapse(h).
  void collapse(Halfedge h);

  // ---- low-level connectivity, for builders and algorithms that know what they do ---------
  // These break invariants in between; finish with validate() in tests.
  Vertex new_vertex();
  /// A new edge a→b: returns halfedge 2e (a→b); its opposite is b→a. No links set.
  Halfedge new_edge(Vertex a, Vertex b);
  Face new_face();
  void set_halfedge(Vertex v, Halfedge h) { vconn_[v.idx()] = h; }
  void set_halfedge(Face f, Halfedge h) { fconn_[f.idx()] = h; }
  void set_vertex(Halfedge h, Vertex v) { hconn_[h.idx()].to = v; }
  void set_face(Halfedge h, Face f) { hconn_[h.idx()].face = f; }
  /// Sets next(h) = n and prev(n) = h.
  void set_next(Halfedge h, Halfedge n) {
    hconn_[h.idx()].next = n;
    hconn_[n.idx()].prev = h;
  }
  /// Make halfedge(v) a boundary halfedge when v has one.
  void adjust_outgoing_halfedge(Vertex v);

 private:
  struct HalfedgeConnectivity {
    Vertex to;
    Halfedge next, prev;
    Face face;
  };

  void remove_edge_helper(Halfedge h);
  void remove_loop_helper(Halfedge h);
  bool collapse_would_fold_tetrahedron(Halfedge h, Vertex vl, Vertex vr) const;
  void delete_edge_links(Halfedge h0);

  std::vector<Halfedge> vconn_;
  std::vector<HalfedgeConnectivity> hconn_;
  std::vector<Halfedge> fconn_;
  std::vector<std::uint8_t> vdeleted_, edeleted_, fdeleted_;
  std::size_t deleted_vertices_ = 0, deleted_edges_ = 0, deleted_faces_ = 0;

  PropertyContainer vprops_, hprops_, eprops_, fprops_;
  Property<Vertex, Point> points_;
};

template <> inline PropertyContainer& SurfaceMesh::props<Vertex>() { return vprops_; }
template <> inline PropertyContainer& SurfaceMesh::props<Halfedge>() { return hprops_; }
template <> inline PropertyContainer& SurfaceMesh::props<Edge>() { return eprops_; }
template <> inline PropertyContainer& SurfaceMesh::props<Face>() { return fprops_; }
template <> inline const PropertyContainer& SurfaceMesh::props<Vertex>() const { return vprops_; }
template <> inline const PropertyContainer& SurfaceMesh::props<Halfedge>() const { return hprops_; }
template <> inline const PropertyContainer& SurfaceMesh::props<Edge>() const { return eprops_; }
template <> inline const PropertyContainer& SurfaceMesh::props<Face>() const { return fprops_; }

/// Names of the properties `from` has and `to` lacks (vertex, halfedge, edge, then face
/// ones), for saying what an operation that makes a new mesh did not carry over.
std::vector<std::string> missing_properties(const SurfaceMesh& from, const SurfaceMesh& to);

template <class H>
void ElementRange<H>::Iterator::skip() {
  while (i_ < end_ && mesh_->is_deleted(H(i_))) ++i_;
}

}  // namespace geom
