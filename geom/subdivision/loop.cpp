// Loop refinement of one level: each triangle splits into three corner triangles and a
// middle one, numbered 4f + j (corner j) and 4f + 3 (middle), as OpenSubdiv numbers them.
//
// Corner triangle j of face f (parent halfedge h ending at corner j, hn = next(h)):
//   second(h)   mid(h) → child(v_j)
//   first(hn)   child(v_j) → mid(hn)
//   2·slot(h)   mid(hn) → mid(h)       (the interior edge cutting corner j)
// rotated so that child(v_j) is its corner j. The middle triangle is the 2·slot + 1
// halfedges, starting at mid(h_2) as OpenSubdiv starts it.
//
// Ref: C. Loop, "Smooth subdivision surfaces based on triangles", 1987; OpenSubdiv
// Sdc::Scheme<SCHEME_LOOP>.

#include <geom/subdivision/level.h>

namespace geom::detail::subdiv {

namespace {

template <class Sink>
void loop_topology(const Level& p, Level& c, Sink& out, const Context& ctx) {
  const std::uint32_t E = p.ne, C = p.n_corners;
  set_child_counts(p, c, false);
  out.allocate(ctx);
  c.parent_face.resize(ctx.parent_faces ? c.nf : 0);
  // Interior child halfedges, face by face (corner j of face f holds slot 3f + j), so each
  // child triangle is written whole, once; boundary halves are a second pass.
  const std::uint32_t F = p.nf;
  for_range(F, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    for (std::uint32_t f = b; f < end; ++f) {
      std::uint32_t hs[3];
      hs[0] = p.fh[f];
      hs[1] = p.next[hs[0]];
      hs[2] = p.next[hs[1]];
      const std::uint32_t mid = 4 * f + 3;
      for (std::uint32_t j = 0; j < 3; ++j) {
        const std::uint32_t jn = j == 2 ? 0 : j + 1;
        const std::uint32_t h = hs[j], hn = hs[jn], sl = 3 * f + j;
        const std::uint32_t cf = 4 * f + j;
        const std::uint32_t ring[3] = {second_half(h, C), first_half(hn, C), 2 * sl};
        out.to(ring[0], E + p.to[h]);
        out.to(ring[1], hn >> 1);
        out.to(ring[2], h >> 1);
        for (std::uint32_t k = 0; k < 3; ++k) {
          out.next(ring[k], ring[k == 2 ? 0 : k + 1]);
          out.face(ring[k], cf);
          if (!ctx.last) out.slot(ring[k], 3 * cf + (k + j) % 3);
        }
        out.fh(cf, ring[(3 - j) % 3]);
        if (ctx.parent_faces) c.parent_face[cf] = f;
        const std::uint32_t inner = 2 * sl + 1;
        out.to(inner, hn >> 1);
        out.next(inner, 2 * (3 * f + jn) + 1);
        out.face(inner, mid);
        if (!ctx.last) out.slot(inner, 3 * mid + (j + 2) % 3);
      }
      out.fh(mid, 2 * (3 * f + 1) + 1);
      if (ctx.parent_faces) c.parent_face[mid] = f;
    }
  });
  link_boundary_and_points(p, out, ctx, 0, E);
  refine_sharpness(p, c, E, ctx);
}

}  // namespace

void refine_topology_loop(const Level& p, Level& c, const Context& ctx) {
  LevelSink sink{c};
  loop_topology(p, c, sink, ctx);
}

void refine_topology_loop(const Level& p, Level& c, SurfaceMesh& mesh, const Context& ctx) {
  MeshSink sink{mesh};
  loop_topology(p, c, sink, ctx);
}

namespace {

template <int W>
void fvar(const Level& p, const double* src, double* dst, int w, const Context& ctx) {
  const int nw = W ? W : w;
  const std::uint32_t C = p.n_corners;
  for_range(p.nf, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    for (std::uint32_t f = b; f < end; ++f) {
      const std::uint32_t h0 = p.fh[f];
      std::uint32_t h = h0;
      do {
        const std::uint32_t hn = p.next[h];
        const double* a = src + static_cast<std::size_t>(h) * nw;
        const double* bb = src + static_cast<std::size_t>(hn) * nw;
        Row<W>::set(dst + static_cast<std::size_t>(second_half(h, C)) * nw, a, 1.0, w);
        // mid(hn) is a corner of triangles j and j + 1 and of the middle one.
        double* m0 = dst + static_cast<std::size_t>(first_half(hn, C)) * nw;
        double* m1 = dst + static_cast<std::size_t>(2 * p.slot[hn]) * nw;
        double* m2 = dst + static_cast<std::size_t>(2 * p.slot[h] + 1) * nw;
        for (int k = 0; k < nw; ++k) m0[k] = m1[k] = m2[k] = 0.5 * a[k] + 0.5 * bb[k];
        h = hn;
      } while (h != h0);
    }
  });
}

}  // namespace

void interpolate_loop(const Level& p, const Level& c, const double* src, double* dst, int w,
                      const Context& ctx) {
  // Loop's edge mask: 3/8 for each end, 1/8 for the corner opposite the edge on each side.
  const auto opposite = [&](std::uint32_t h) { return p.to[p.next[h]]; };
  if (w == 3)
    edge_points<3>(p, c, src, dst, w, 0, 0.375, 0.125, src, opposite, ctx);
  else
    edge_points<0>(p, c, src, dst, w, 0, 0.375, 0.125, src, opposite, ctx);
  vertex_points(p, c, src, dst, w, p.ne, ctx);
}

void interpolate_fvar_loop(const Level& p, const double* src, double* dst, int w,
                           const Context& ctx) {
  if (w == 2)
    fvar<2>(p, src, dst, w, ctx);
  else
    fvar<0>(p, src, dst, w, ctx);
}

}  // namespace geom::detail::subdiv
