// Catmull-Clark refinement of one level: child connectivity by index arithmetic (no
// searching, no per-element allocation), then face-, edge- and vertex-points.
//
// The child face of parent halfedge g (ending at corner j of face f) is the quad
// child(v_j) → mid(next g) → face-point → mid(g). With h = prev(g), sl = slot(h), and the
// interior edge of slot s joining the face-point to mid(next(s's halfedge)):
//   second(g)             mid(g) → child(v_j)
//   first(next g)         child(v_j) → mid(next g)
//   2·slot(g) + 1         mid(next g) → face-point
//   2·sl                  face-point → mid(g)
// A face's corners hold consecutive slots (slot(fh) first), so walking each parent face
// builds its child faces in index order; boundary halves are a second pass. Every child
// halfedge is written exactly once and both passes run in parallel. OpenSubdiv rotates a
// child of a quad so that child(v_j) is its corner j (children of other polygons start at
// child(v_j)).
//
// Ref: E. Catmull, J. Clark, CAD 10(6), 1978; OpenSubdiv Sdc::Scheme<SCHEME_CATMARK>.

#include <geom/subdivision/level.h>

namespace geom::detail::subdiv {

namespace {

template <class Sink>
void catmark_topology(const Level& p, Level& c, Sink& out, const Context& ctx) {
  const std::uint32_t E = p.ne, F = p.nf, C = p.n_corners;
  set_child_counts(p, c, true);
  out.allocate(ctx);
  c.parent_face.resize(ctx.parent_faces ? c.nf : 0);
  // Interior child halfedges, face by face: the corners of a face are consecutive slots, so
  // the child faces and their interior edges are written in order and each ring is written
  // whole, once (for a SurfaceMesh, next and prev of a ring stay inside it).
  for_range(F, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    for (std::uint32_t f = b; f < end; ++f) {
      const std::uint32_t n = p.face_size(f);
      const std::uint32_t base = p.face_base.empty() ? n * f : p.face_base[f];
      std::uint32_t g = p.next[p.fh[f]], gg = p.next[g];
      out.vh(f, 2 * base);
      for (std::uint32_t j = 0; j < n; ++j) {
        const std::uint32_t jn = j + 1 == n ? 0 : j + 1;
        const std::uint32_t sl = base + j, sg = base + jn;
        const std::uint32_t ring[4] = {second_half(g, C), first_half(gg, C), 2 * sg + 1, 2 * sl};
        out.to(ring[0], F + E + p.to[g]);
        out.to(ring[1], F + (gg >> 1));
        out.to(ring[2], f);
        out.to(ring[3], F + (g >> 1));
        for (int k = 0; k < 4; ++k) {
          out.next(ring[k], ring[(k + 1) & 3]);
          out.face(ring[k], sg);
        }
        const std::uint32_t r = n == 4 ? jn : 0;
        if (!ctx.last)
          for (std::uint32_t k = 0; k < 4; ++k) out.slot(ring[k], 4 * sg + ((k + r) & 3u));
        out.fh(sg, ring[(4 - r) & 3u]);
        if (ctx.parent_faces) c.parent_face[sg] = f;
        g = gg;
        gg = p.next[gg];
      }
    }
  });
  link_boundary_and_points(p, out, ctx, F, F + E);
  refine_sharpness(p, c, F + E, ctx);
}

}  // namespace

void refine_topology_catmark(const Level& p, Level& c, const Context& ctx) {
  LevelSink sink{c};
  catmark_topology(p, c, sink, ctx);
}

void refine_topology_catmark(const Level& p, Level& c, SurfaceMesh& mesh, const Context& ctx) {
  MeshSink sink{mesh};
  catmark_topology(p, c, sink, ctx);
}

namespace {

template <int W>
void face_points(const Level& p, const double* src, double* dst, int w, const Context& ctx) {
  const int nw = W ? W : w;
  const std::uint32_t F = p.nf;
  for_range(F, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    for (std::uint32_t f = b; f < end; ++f) {
      double* out = dst + static_cast<std::size_t>(f) * nw;
      Row<W>::zero(out, w);
      const double weight = 1.0 / p.face_size(f);
      std::uint32_t h = p.fh[f];
      do {
        Row<W>::add(out, src + static_cast<std::size_t>(p.to[h]) * nw, weight, w);
        h = p.next[h];
      } while (h != p.fh[f]);
    }
  });
}

template <int W>
void fvar(const Level& p, const double* src, double* dst, int w, const Context& ctx) {
  const int nw = W ? W : w;
  const std::uint32_t C = p.n_corners;
  for_range(p.nf, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    std::vector<double> avg(static_cast<std::size_t>(nw));
    for (std::uint32_t f = b; f < end; ++f) {
      const std::uint32_t h0 = p.fh[f];
      const int n = static_cast<int>(p.face_size(f));
      Row<W>::zero(avg.data(), w);
      std::uint32_t h = h0;
      do {
        Row<W>::add(avg.data(), src + static_cast<std::size_t>(h) * nw, 1.0 / n, w);
        h = p.next[h];
      } while (h != h0);
      // Values sit on the child halfedges that end at each child corner (see the ring in
      // refine_topology_catmark).
      do {
        const std::uint32_t g = p.next[h];
        const double* a = src + static_cast<std::size_t>(h) * nw;
        const double* bb = src + static_cast<std::size_t>(g) * nw;
        Row<W>::set(dst + static_cast<std::size_t>(second_half(h, C)) * nw, a, 1.0, w);
        double* m0 = dst + static_cast<std::size_t>(first_half(g, C)) * nw;
        double* m1 = dst + static_cast<std::size_t>(2 * p.slot[h]) * nw;
        for (int k = 0; k < nw; ++k) m0[k] = m1[k] = 0.5 * a[k] + 0.5 * bb[k];
        Row<W>::set(dst + static_cast<std::size_t>(2 * p.slot[h] + 1) * nw, avg.data(), 1.0, w);
        h = g;
      } while (h != h0);
    }
  });
}

}  // namespace

void interpolate_catmark(const Level& p, const Level& c, const double* src, double* dst,
                         int w, const Context& ctx) {
  // Edge-points average the two ends and the two face-points (written first, rows 0..nf).
  const auto face_point = [&](std::uint32_t h) { return p.face[h]; };
  if (w == 3) {
    face_points<3>(p, src, dst, w, ctx);
    edge_points<3>(p, c, src, dst, w, p.nf, 0.25, 0.25, dst, face_point, ctx);
  } else {
    face_points<0>(p, src, dst, w, ctx);
    edge_points<0>(p, c, src, dst, w, p.nf, 0.25, 0.25, dst, face_point, ctx);
  }
  vertex_points(p, c, src, dst, w, p.nf + p.ne, ctx);
}

void interpolate_fvar_catmark(const Level& p, const double* src, double* dst, int w,
                              const Context& ctx) {
  if (w == 2)
    fvar<2>(p, src, dst, w, ctx);
  else
    fvar<0>(p, src, dst, w, ctx);
}

}  // namespace geom::detail::subdiv
