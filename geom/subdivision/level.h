#pragma once
/// \file
/// Internal: one refinement level as flat half-edge arrays, laid out like SurfaceMesh (the
/// halfedges of edge e are 2e and 2e + 1) so level 0 is a copy of the input's connectivity
/// and the last level is written straight into a SurfaceMesh (MeshSink).
///
/// Child numbering, shared by both schemes and equal to OpenSubdiv's (Vtr quad/tri
/// refinement with orderVerticesFromFacesFirst), so results compare index by index:
///  - vertices: [face-points (Catmull-Clark only), edge-points, vertex-points], each in its
///    parent's order;
///  - edges: first one per parent corner slot (interior edges, by slot), then two per parent
///    edge e at C + 2e + j, j = 0 at from(2e) and 1 at to(2e), oriented edge-point → vertex;
///    so the child edge at vertex from(h) has index C + h, where C = parent corner count;
///  - faces: the children of parent face f in corner order (Loop's middle one last), each
///    rotated so that the child of corner j is its corner j (quads and triangles).

#include <geom/core/huge_pages.h>
#include <geom/core/surface_mesh.h>
#include <geom/subdivision/creases.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <utility>
#include <vector>

namespace geom::detail::subdiv {

inline constexpr std::uint32_t kNone = 0xffffffffu;

/// An allocator whose resize() leaves new elements uninitialised (UninitialisedAllocator):
/// every array of a level is written in full right after it is sized, and zeroing hundreds
/// of megabytes first costs as much as the refinement itself.
template <class T>
struct NoInitAllocator : UninitialisedAllocator<T> {
  template <class U>
  struct rebind {
    using other = NoInitAllocator<U>;
  };
  NoInitAllocator() = default;
  template <class U>
  NoInitAllocator(const NoInitAllocator<U>&) noexcept {}
  // Big arrays ask for transparent huge pages: first-touch page faults of 4 KiB pages are a
  // third of the time of a large refinement otherwise.
  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kHugeThreshold) return std::allocator<T>::allocate(n);
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (!p) throw std::bad_alloc();
    advise_huge_pages(p, rounded);
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) {
    if (n * sizeof(T) < kHugeThreshold)
      std::allocator<T>::deallocate(p, n);
    else
      std::free(p);
  }
  static constexpr std::size_t kHugePage = kHugePageBytes;
  static constexpr std::size_t kHugeThreshold = std::size_t{8} << 20;
};

template <class T>
using Array = std::vector<T, NoInitAllocator<T>>;

struct Level {
  std::uint32_t nv = 0, ne = 0, nf = 0;
  std::uint32_t n_corners = 0;        ///< sum of face sizes = interior halfedges
  Array<std::uint32_t> to;      ///< per halfedge: target vertex
  Array<std::uint32_t> next;    ///< per halfedge: next halfedge in its loop
  Array<std::uint32_t> face;    ///< per halfedge: face, kNone on the boundary
  /// Per halfedge: corner slot, kNone on the boundary; empty on a last level (not needed).
  Array<std::uint32_t> slot;
  Array<std::uint32_t> vh;      ///< per vertex: outgoing halfedge, a boundary one if any
  Array<std::uint32_t> fh;      ///< per face: the halfedge ending at corner 0
  /// Per face: face of the previous level; empty unless Context::parent_faces.
  Array<std::uint32_t> parent_face;
  /// Per face: its first corner slot; empty when every face has `uniform_size` corners
  /// (then face f starts at slot uniform_size · f).
  std::vector<std::uint32_t> face_base;
  std::uint32_t uniform_size = 0;
  /// Sharpness per edge and vertex (boundary edges already infinite); both empty when
  /// nothing at all is sharp, which selects the smooth fast paths.
  std::vector<float> esharp, vsharp;

  bool has_sharpness() const { return !esharp.empty(); }
  std::uint32_t face_size(std::uint32_t f) const {
    if (face_base.empty()) return uniform_size;
    return (f + 1 < nf ? face_base[f + 1] : n_corners) - face_base[f];
  }
  /// Index of the corner that interior halfedge h ends at, within its face.
  std::uint32_t corner_of(std::uint32_t h) const {
    const std::uint32_t f = face[h];
    return slot[h] - (face_base.empty() ? uniform_size * f : face_base[f]);
  }
  std::uint32_t from(std::uint32_t h) const { return to[h ^ 1u]; }
  /// Clockwise successor among the outgoing halfedges of from(h).
  std::uint32_t cw(std::uint32_t h) const { return next[h ^ 1u]; }
};

struct Context {
  bool catmark = true;
  bool chaikin = false;
  bool parallel = true;
  bool parent_faces = false;  ///< fill Level::parent_face
  bool last = false;          ///< the level being built is the last one: no slots
};

/// The child halfedge from the child of from(h) to the edge-point of h (C: parent corners).
inline std::uint32_t first_half(std::uint32_t h, std::uint32_t C) { return 2 * (C + h) + 1; }
/// The child halfedge from the edge-point of h to the child of to(h).
inline std::uint32_t second_half(std::uint32_t h, std::uint32_t C) { return 2 * (C + (h ^ 1u)); }

/// Run f(begin, end) over [0, n), split across TBB workers when it pays.
template <class F>
void for_range(std::uint32_t n, bool parallel, const F& f) {
  constexpr std::uint32_t kGrain = 4096;
  if (!parallel || n < 4 * kGrain) {
    f(std::uint32_t{0}, n);
    return;
  }
  tbb::parallel_for(tbb::blocked_range<std::uint32_t>(0, n, kGrain),
                    [&](const tbb::blocked_range<std::uint32_t>& r) { f(r.begin(), r.end()); });
}

/// The part of a child level both schemes link alike once the interior faces are written:
/// the two halves of each parent boundary halfedge (in loop order), and the outgoing
/// halfedges of edge-points (child vertices from `edge_base`) and vertex-points (from
/// `vertex_base`).
template <class Sink>
void link_boundary_and_points(const Level& p, Sink& out, const Context& ctx,
                              std::uint32_t edge_base, std::uint32_t vertex_base) {
  const std::uint32_t E = p.ne, V = p.nv, C = p.n_corners;
  for_range(2 * E, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    for (std::uint32_t h = b; h < end; ++h) {
      if (p.face[h] != kNone) continue;
      const std::uint32_t fst = first_half(h, C), snd = second_half(h, C);
      out.to(fst, edge_base + (h >> 1));
      out.to(snd, vertex_base + p.to[h]);
      out.next(fst, snd);
      out.next(snd, first_half(p.next[h], C));
      out.face(fst, kNone);
      out.face(snd, kNone);
      if (!ctx.last) {
        out.slot(fst, kNone);
        out.slot(snd, kNone);
      }
    }
  });
  for_range(E, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    for (std::uint32_t e = b; e < end; ++e)
      out.vh(edge_base + e,
             p.face[2 * e + 1] == kNone ? second_half(2 * e + 1, C) : second_half(2 * e, C));
  });
  for_range(V, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    for (std::uint32_t v = b; v < end; ++v)
      out.vh(vertex_base + v, p.vh[v] == kNone ? kNone : first_half(p.vh[v], C));
  });
}

/// Child element counts of one refinement of `p` (face_base cleared, no arrays sized).
inline void set_child_counts(const Level& p, Level& c, bool catmark) {
  const std::uint32_t E = p.ne, F = p.nf, V = p.nv, C = p.n_corners;
  c.nv = catmark ? F + E + V : E + V;
  c.ne = 2 * E + C;
  c.nf = catmark ? C : 4 * F;
  c.n_corners = catmark ? 4 * C : 12 * F;
  c.face_base.clear();
  c.uniform_size = catmark ? 4 : 3;
}

/// Where a topology kernel writes child connectivity: the arrays of a Level …
struct LevelSink {
  Level& c;
  void to(std::uint32_t h, std::uint32_t v) { c.to[h] = v; }
  void next(std::uint32_t h, std::uint32_t n) { c.next[h] = n; }
  void face(std::uint32_t h, std::uint32_t f) { c.face[h] = f; }
  void slot(std::uint32_t h, std::uint32_t s) { c.slot[h] = s; }
  void vh(std::uint32_t v, std::uint32_t h) { c.vh[v] = h; }
  void fh(std::uint32_t f, std::uint32_t h) { c.fh[f] = h; }
  /// Size the arrays for the counts already in c.
  void allocate(const Context& ctx) {
    const std::size_t H = 2 * static_cast<std::size_t>(c.ne);
    c.to.resize(H);
    c.next.resize(H);
    c.face.resize(H);
    c.slot.resize(ctx.last ? 0 : H);
    c.vh.resize(c.nv);
    c.fh.resize(c.nf);
  }
};

/// … or, for the last level, a SurfaceMesh whose elements exist already (SurfaceMesh::resize
/// to the counts of the level), so the biggest level is written once, in place. Invalid
/// handles carry index kNone, which is what the kernels write.
struct MeshSink {
  SurfaceMesh& m;
  void to(std::uint32_t h, std::uint32_t v) { m.set_vertex(Halfedge(h), Vertex(v)); }
  void next(std::uint32_t h, std::uint32_t n) { m.set_next(Halfedge(h), Halfedge(n)); }
  void face(std::uint32_t h, std::uint32_t f) { m.set_face(Halfedge(h), Face(f)); }
  void slot(std::uint32_t, std::uint32_t) {}
  void vh(std::uint32_t v, std::uint32_t h) { m.set_halfedge(Vertex(v), Halfedge(h)); }
  void fh(std::uint32_t f, std::uint32_t h) { m.set_halfedge(Face(f), Halfedge(h)); }
  void allocate(const Context&) {}
};

/// Row operations on data of width W (W = 0: the runtime width w).
template <int W>
struct Row {
  static void set(double* d, const double* s, double a, int w) {
    const int n = W ? W : w;
    for (int k = 0; k < n; ++k) d[k] = a * s[k];
  }
  static void add(double* d, const double* s, double a, int w) {
    const int n = W ? W : w;
    for (int k = 0; k < n; ++k) d[k] += a * s[k];
  }
  static void zero(double* d, int w) {
    const int n = W ? W : w;
    for (int k = 0; k < n; ++k) d[k] = 0.0;
  }
};

/// Edge-point rule shared by both schemes, for parent edges e into dst rows
/// first_edge_child + e. Smooth: vw·(both ends) + fw·(both wings), where the wing on h's side
/// of the edge is row wing_row(h) of `wings` (Catmull-Clark: the face-point, already in dst;
/// Loop: the corner opposite the edge, in src). A boundary edge, or a crease whose two children stay sharp, gives the
/// midpoint; a crease whose sharpness decays to zero at this level blends the crease rule
/// and the smooth one by its sharpness s: vw = s/2 + (1 − s)·smooth_vw, fw = (1 − s)·smooth_fw.
template <int W, class WingRow>
void edge_points(const Level& p, const Level& c, const double* src, double* dst, int w,
                 std::uint32_t first_edge_child, double smooth_vw, double smooth_fw,
                 const double* wings, const WingRow& wing_row, const Context& ctx) {
  const int nw = W ? W : w;
  const bool sharp = p.has_sharpness();
  const bool child_sharp = c.has_sharpness();
  for_range(p.ne, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    for (std::uint32_t e = b; e < end; ++e) {
      const std::uint32_t h0 = 2 * e, h1 = 2 * e + 1;
      const double* v0 = src + static_cast<std::size_t>(p.to[h1]) * nw;
      const double* v1 = src + static_cast<std::size_t>(p.to[h0]) * nw;
      double* out = dst + (static_cast<std::size_t>(first_edge_child) + e) * nw;
      const float s = sharp ? p.esharp[e] : kSmooth;
      double vw = smooth_vw, fw = smooth_fw;
      if (is_sharp(s)) {
        const bool child_crease = child_sharp && is_sharp(c.esharp[p.n_corners + h0]) &&
                                  is_sharp(c.esharp[p.n_corners + h1]);
        if (child_crease || p.face[h0] == kNone || p.face[h1] == kNone) {
          for (int k = 0; k < nw; ++k) out[k] = 0.5 * v0[k] + 0.5 * v1[k];
          continue;
        }
        const double pw = s, cw = 1.0 - pw;
        vw = pw * 0.5 + cw * smooth_vw;
        fw = cw * smooth_fw;
      }
      const double* f0 = wings + static_cast<std::size_t>(wing_row(h0)) * nw;
      const double* f1 = wings + static_cast<std::size_t>(wing_row(h1)) * nw;
      for (int k = 0; k < nw; ++k) out[k] = fw * f0[k] + fw * f1[k] + vw * v0[k] + vw * v1[k];
    }
  });
}

/// Child sharpness (edges and vertices) of a level whose topology is refined; empties the
/// arrays when nothing stays sharp. `first_vertex_child` is where vertex-points start.
void refine_sharpness(const Level& p, Level& c, std::uint32_t first_vertex_child,
                      const Context& ctx);

/// Refine the connectivity of p into c (counts, arrays, sharpness; parent_face when
/// ctx.parent_faces).
void refine_topology_catmark(const Level& p, Level& c, const Context& ctx);
void refine_topology_loop(const Level& p, Level& c, const Context& ctx);
/// The same with the connectivity written into `mesh`, which must hold exactly the child
/// counts of elements (see set_child_counts); c receives counts, sharpness and parent_face.
void refine_topology_catmark(const Level& p, Level& c, SurfaceMesh& mesh, const Context& ctx);
void refine_topology_loop(const Level& p, Level& c, SurfaceMesh& mesh, const Context& ctx);

/// Vertex data of width w (p.nv rows in, c.nv rows out, row-major).
void interpolate_catmark(const Level& p, const Level& c, const double* src, double* dst,
                         int w, const Context& ctx);
void interpolate_loop(const Level& p, const Level& c, const double* src, double* dst, int w,
                      const Context& ctx);
/// Linear face-varying data of width w per halfedge (boundary rows unused).
void interpolate_fvar_catmark(const Level& p, const double* src, double* dst, int w,
                              const Context& ctx);
void interpolate_fvar_loop(const Level& p, const double* src, double* dst, int w,
                           const Context& ctx);

/// Vertex-point rule shared by both schemes (parent rule, child rule, blend), applied to
/// parent vertices [begin, end). Face-points must already be in dst for Catmull-Clark.
void vertex_points(const Level& p, const Level& c, const double* src, double* dst, int w,
                   std::uint32_t first_vertex_child, const Context& ctx);

/// Level 0 from a mesh without garbage: connectivity, corner slots, and sharpness from
/// "e:sharpness"/"v:sharpness" with boundary edges (and, when asked, boundary corners)
/// made infinitely sharp. `face_size` 3 or 4 demands that size of every face.
/// Throws: TopologyError for a non-manifold vertex; InvalidArgument naming a face of the
/// wrong size, or a NaN sharpness.
Level build_level0(const SurfaceMesh& mesh, bool sharpen_corners, int face_size);

}  // namespace geom::detail::subdiv
