#include <geom/subdivision/creases.h>
#include <geom/subdivision/level.h>

#include <geom/core/errors.h>
#include <geom/core/soup.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <vector>

namespace geom {

namespace detail::subdiv {

float chaikin_child_sharpness(float s, int n, float semi_sum, int semi_count) {
  if (n < 2) return decrement(s);
  if (s <= kSmooth) return kSmooth;
  if (is_infinite(s)) return kInfinite;
  // 3/4 of the edge's own sharpness plus 1/4 of the mean of the other semi-sharp edges.
  if (semi_count > 1)
    s = 0.75f * s + 0.25f * ((semi_sum - s) / static_cast<float>(semi_count - 1));
  s -= 1.0f;
  return is_sharp(s) ? s : kSmooth;
}

void refine_sharpness(const Level& p, Level& c, std::uint32_t first_vertex_child,
                      const Context& ctx) {
  c.esharp.clear();
  c.vsharp.clear();
  if (!p.has_sharpness()) return;
  c.esharp.assign(c.ne, kSmooth);
  c.vsharp.assign(c.nv, kSmooth);
  // The child edge at vertex from(h) of parent edge h/2 has index C + h (see level.h);
  // interior edges [0, C) stay smooth.
  const std::uint32_t C = p.n_corners;
  if (!ctx.chaikin) {
    for_range(2 * p.ne, ctx.parallel, [&](std::uint32_t b, std::uint32_t e) {
      for (std::uint32_t h = b; h < e; ++h) c.esharp[C + h] = decrement(p.esharp[h >> 1]);
    });
  } else {
    for_range(p.nv, ctx.parallel, [&](std::uint32_t b, std::uint32_t e) {
      for (std::uint32_t v = b; v < e; ++v) {
        const std::uint32_t h0 = p.vh[v];
        if (h0 == kNone) continue;
        int n = 0, semi_count = 0;
        float semi_sum = 0.0f;
        std::uint32_t h = h0;
        do {
          float s = p.esharp[h >> 1];
          ++n;
          if (is_semi_sharp(s)) {
            ++semi_count;
            semi_sum += s;
          }
          h = p.cw(h);
        } while (h != h0);
        do {
          c.esharp[C + h] = chaikin_child_sharpness(p.esharp[h >> 1], n, semi_sum, semi_count);
          h = p.cw(h);
        } while (h != h0);
      }
    });
  }
  for (std::uint32_t v = 0; v < p.nv; ++v)
    c.vsharp[first_vertex_child + v] = decrement(p.vsharp[v]);
  const auto sharp = [](float s) { return is_sharp(s); };
  if (std::none_of(c.esharp.begin(), c.esharp.end(), sharp) &&
      std::none_of(c.vsharp.begin(), c.vsharp.end(), sharp)) {
    c.esharp.clear();
    c.vsharp.clear();
  }
}

namespace {

/// The smooth vertex-point of v: Catmull-Clark's (n−2)/n·v + Σ(e + f)/n², or Loop's
/// (1 − nβ)·v + β·Σe with Loop's original β.
template <int W>
void smooth_vertex(const Level& p, std::uint32_t v, const double* src, const double* dst,
                   double* out, int w, bool catmark) {
  const int nw = W ? W : w;
  const std::uint32_t h0 = p.vh[v];
  double esum[W ? W : 1], fsum[W ? W : 1];
  std::vector<double> dyn;
  double* es = esum;
  double* fs = fsum;
  if constexpr (W == 0) {
    dyn.assign(2 * static_cast<std::size_t>(nw), 0.0);
    es = dyn.data();
    fs = dyn.data() + nw;
  }
  Row<W>::zero(es, w);
  Row<W>::zero(fs, w);
  int n = 0;
  std::uint32_t h = h0;
  do {
    Row<W>::add(es, src + static_cast<std::size_t>(p.to[h]) * nw, 1.0, w);
    if (catmark) Row<W>::add(fs, dst + static_cast<std::size_t>(p.face[h]) * nw, 1.0, w);
    ++n;
    h = p.cw(h);
  } while (h != h0);
  const double* pv = src + static_cast<std::size_t>(v) * nw;
  if (catmark) {
    const double vw = static_cast<double>(n - 2) / n;
    const double fw = 1.0 / (static_cast<double>(n) * n);
    for (int k = 0; k < nw; ++k) out[k] = fw * fs[k] + fw * es[k] + vw * pv[k];
  } else {
    double ew = 0.0625, vw = 0.625;
    if (n != 6) {
      const double inv = 1.0 / n;
      const double cos_theta = std::cos(M_PI * 2.0 * inv);
      const double beta = 0.25 * cos_theta + 0.375;
      ew = (0.625 - beta * beta) * inv;
      vw = 1.0 - ew * n;
    }
    for (int k = 0; k < nw; ++k) out[k] = ew * es[k] + vw * pv[k];
  }
}

template <int W>
void rule_vertex(Rule rule, std::uint32_t v, const std::uint32_t* ends, const double* src,
                 double* out, int w) {
  const int nw = W ? W : w;
  const double* pv = src + static_cast<std::size_t>(v) * nw;
  if (rule == kRuleCorner) {
    Row<W>::set(out, pv, 1.0, w);
    return;
  }
  const double* a = src + static_cast<std::size_t>(ends[0]) * nw;
  const double* b = src + static_cast<std::size_t>(ends[1]) * nw;
  for (int k = 0; k < nw; ++k) out[k] = 0.125 * a[k] + 0.125 * b[k] + 0.75 * pv[k];
}

template <int W>
void vertex_points_impl(const Level& p, const Level& c, const double* src, double* dst, int w,
                        std::uint32_t first_vertex_child, const Context& ctx) {
  const int nw = W ? W : w;
  const bool sharp = p.has_sharpness();
  const bool child_sharp = c.has_sharpness();
  for_range(p.nv, ctx.parallel, [&](std::uint32_t b, std::uint32_t e) {
    std::vector<double> tmp(static_cast<std::size_t>(nw));
    for (std::uint32_t v = b; v < e; ++v) {
      double* out = dst + static_cast<std::size_t>(first_vertex_child + v) * nw;
      const std::uint32_t h0 = p.vh[v];
      if (h0 == kNone) {
        Row<W>::set(out, src + static_cast<std::size_t>(v) * nw, 1.0, w);
        continue;
      }
      if (!sharp) {
        smooth_vertex<W>(p, v, src, dst, out, w, ctx.catmark);
        continue;
      }
      const float pvs = p.vsharp[v];
      const float cvs = child_sharp ? c.vsharp[first_vertex_child + v] : kSmooth;
      FractionalWeight fraction(ctx.chaikin, pvs, cvs);
      int psharp = 0, csharp = 0;
      std::uint32_t pends[2] = {0, 0}, cends[2] = {0, 0};
      std::uint32_t h = h0;
      do {
        const float ps = p.esharp[h >> 1];
        const float cs = child_sharp ? c.esharp[p.n_corners + h] : kSmooth;
        // With exactly two sharp edges, OpenSubdiv's "first and last sharp" pair is them.
        if (is_sharp(ps)) pends[psharp++ & 1] = p.to[h];
        if (is_sharp(cs)) cends[csharp++ & 1] = p.to[h];
        fraction.add_edge(ps, cs);
        h = p.cw(h);
      } while (h != h0);
      const Rule prule = vertex_rule(pvs, psharp);
      if (prule == kRuleSmooth || prule == kRuleDart) {
        smooth_vertex<W>(p, v, src, dst, out, w, ctx.catmark);
        continue;
      }
      rule_vertex<W>(prule, v, pends, src, out, w);
      const Rule crule = vertex_rule(cvs, csharp);
      if (crule == prule) continue;
      if (crule == kRuleSmooth || crule == kRuleDart)
        smooth_vertex<W>(p, v, src, dst, tmp.data(), w, ctx.catmark);
      else
        rule_vertex<W>(crule, v, cends, src, tmp.data(), w);
      const double pw = fraction.value();
      const double cw = 1.0 - pw;
      for (int k = 0; k < nw; ++k) out[k] = pw * out[k] + cw * tmp[k];
    }
  });
}

}  // namespace

void vertex_points(const Level& p, const Level& c, const double* src, double* dst, int w,
                   std::uint32_t first_vertex_child, const Context& ctx) {
  if (w == 3)
    vertex_points_impl<3>(p, c, src, dst, w, first_vertex_child, ctx);
  else
    vertex_points_impl<0>(p, c, src, dst, w, first_vertex_child, ctx);
}

}  // namespace detail::subdiv

std::size_t mark_creases_by_angle(SurfaceMesh& mesh, double degrees) {
  if (!(degrees >= 0.0 && degrees <= 180.0))
    throw InvalidArgument("crease angle must be in [0, 180] degrees, got " +
                          std::to_string(degrees));
  // Newell normals are well defined for non-planar polygons too.
  std::vector<Eigen::Vector3d> normal(mesh.faces_size(), Eigen::Vector3d::Zero());
  for (Face f : mesh.faces()) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    for (Halfedge h : mesh.halfedges(f)) {
      const Point& a = mesh.position(mesh.from_vertex(h));
      const Point& b = mesh.position(mesh.to_vertex(h));
      n += a.cross(b);
    }
    double len = n.norm();
    normal[f.idx()] = len > 0.0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
  }
  const double cos_limit = std::cos(degrees * M_PI / 180.0);
  auto sharp = mesh.get_or_add_property<Edge, double>(prop::kEdgeSharpness, 0.0);
  std::size_t marked = 0;
  for (Edge e : mesh.edges()) {
    if (mesh.is_boundary(e)) continue;
    const Eigen::Vector3d& n0 = normal[mesh.face(e, 0).idx()];
    const Eigen::Vector3d& n1 = normal[mesh.face(e, 1).idx()];
    if (n0.isZero() || n1.isZero()) continue;
    if (n0.dot(n1) < cos_limit && sharp[e] < detail::subdiv::kInfinite) {
      sharp[e] = detail::subdiv::kInfinite;
      ++marked;
    }
  }
  return marked;
}

}  // namespace geom
