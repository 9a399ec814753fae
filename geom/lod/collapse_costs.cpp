// The cost of two edge collapses at once, one per SIMD lane: the engine evaluates every edge
// of the survivor after each collapse (about seven) and every edge at the start, and
// place()'s chain of products, a division and comparisons is latency-bound, so two
// independent chains side by side take little more time than one.
//
// Each lane repeats place()'s operations in place()'s order, so it produces the same bits:
// a change to place() or to Quadric::minimizer() must be made here too (debug builds check
// every pair against place(), except on targets with fused multiply-add, where the compiler
// may fuse scalar and vector code differently and the last bits of a cost may differ).

#include <geom/lod/collapse.h>

#include <cassert>
#include <cmath>

namespace geom::detail {

namespace {

// Two doubles (SSE2 on x86-64, NEON on AArch64; GCC and Clang split it elsewhere).
using V2 = double __attribute__((vector_size(16)));

struct QuadricPair {
  V2 a00, a01, a02, a11, a12, a22, b0, b1, b2, c;

  QuadricPair(const Quadric& x, const Quadric& y)
      : a00{x.a00, y.a00},
        a01{x.a01, y.a01},
        a02{x.a02, y.a02},
        a11{x.a11, y.a11},
        a12{x.a12, y.a12},
        a22{x.a22, y.a22},
        b0{x.b0, y.b0},
        b1{x.b1, y.b1},
        b2{x.b2, y.b2},
        c{x.c, y.c} {}
  QuadricPair& operator+=(const QuadricPair& q) {
    a00 += q.a00, a01 += q.a01, a02 += q.a02, a11 += q.a11, a12 += q.a12, a22 += q.a22;
    b0 += q.b0, b1 += q.b1, b2 += q.b2, c += q.c;
    return *this;
  }
  // Quadric::translated(t).
  void translate(V2 x, V2 y, V2 z) {
    const V2 ax = a00 * x + a01 * y + a02 * z;
    const V2 ay = a01 * x + a11 * y + a12 * z;
    const V2 az = a02 * x + a12 * y + a22 * z;
    const V2 old0 = b0, old1 = b1, old2 = b2;
    b0 = old0 + ax, b1 = old1 + ay, b2 = old2 + az;
    c = c + ((ax + 2.0 * old0) * x + (ay + 2.0 * old1) * y + (az + 2.0 * old2) * z);
  }
  // Quadric::evaluate without its clamp at 0.
  V2 evaluate(V2 x, V2 y, V2 z) const {
    return a00 * x * x + a11 * y * y + a22 * z * z +
           2.0 * (a01 * x * y + a02 * x * z + a12 * y * z) + 2.0 * (b0 * x + b1 * y + b2 * z) + c;
  }
};

V2 abs(V2 x) { return V2{std::abs(x[0]), std::abs(x[1])}; }
double clamp0(double v) { return v < 0.0 ? 0.0 : v; }

}  // namespace

std::array<double, 2> CollapseEngine::place_cost_pair(const std::uint32_t* a,
                                                      const std::uint32_t* b) const {
  const VertexData &a0 = vd_[a[0]], &a1 = vd_[a[1]], &b0 = vd_[b[0]], &b1 = vd_[b[1]];
  const V2 ax{a0.p.x(), a1.p.x()}, ay{a0.p.y(), a1.p.y()}, az{a0.p.z(), a1.p.z()};
  const V2 bx{b0.p.x(), b1.p.x()}, by{b0.p.y(), b1.p.y()}, bz{b0.p.z(), b1.p.z()};
  // Both quadrics about a's position, as in place().
  const V2 ex = bx - ax, ey = by - ay, ez = bz - az;
  QuadricPair q(a0.q, a1.q);
  QuadricPair qb(b0.q, b1.q);
  qb.translate(-ex, -ey, -ez);
  q += qb;
  const V2 mx = 0.5 * ex, my = 0.5 * ey, mz = 0.5 * ez;
  const V2 e2 = ex * ex + ey * ey + ez * ez;
  const V2 noise =
      kTieTolerance * ((q.a00 + q.a11 + q.a22) * e2 +
                       (abs(q.b0) + abs(q.b1) + abs(q.b2)) * (abs(ex) + abs(ey) + abs(ez)) +
                       abs(q.c));
  const V2 at_a = q.c, at_b = q.evaluate(ex, ey, ez);

  // Quadric::minimizer(mid) by its closed form; lanes that need the pseudo-inverse leave below.
  const V2 rx = -(q.a00 * mx + q.a01 * my + q.a02 * mz + q.b0);
  const V2 ry = -(q.a01 * mx + q.a11 * my + q.a12 * mz + q.b1);
  const V2 rz = -(q.a02 * mx + q.a12 * my + q.a22 * mz + q.b2);
  const V2 trace = q.a00 + q.a11 + q.a22;
  const V2 c00 = q.a11 * q.a22 - q.a12 * q.a12;
  const V2 c01 = q.a02 * q.a12 - q.a01 * q.a22;
  const V2 c02 = q.a01 * q.a12 - q.a02 * q.a11;
  const V2 det = q.a00 * c00 + q.a01 * c01 + q.a02 * c02;
  const V2 c11 = q.a00 * q.a22 - q.a02 * q.a02;
  const V2 c12 = q.a01 * q.a02 - q.a00 * q.a12;
  const V2 c22 = q.a00 * q.a11 - q.a01 * q.a01;
  const V2 sigma2 = c00 + c11 + c22;
  const V2 inv = 1.0 / det;
  const V2 ox = mx + (c00 * rx + c01 * ry + c02 * rz) * inv;
  const V2 oy = my + (c01 * rx + c11 * ry + c12 * rz) * inv;
  const V2 oz = mz + (c02 * rx + c12 * ry + c22 * rz) * inv;
  const V2 at_opt = q.evaluate(ox, oy, oz);
  const V2 reach = 4.0 * e2;
  const V2 dx = ox - mx, dy = oy - my, dz = oz - mz;
  const V2 away = dx * dx + dy * dy + dz * dz;
  // The midpoint's cost only where the optimum is out of reach, which is rare.
  const bool both_near = away[0] <= reach[0] && away[1] <= reach[1];
  const V2 at_mid = both_near ? V2{0.0, 0.0} : q.evaluate(mx, my, mz);

  std::array<double, 2> cost;
  for (int k = 0; k < 2; ++k) {
    const bool plain = !attributes_ && !(k ? a1 : a0).locked && !(k ? b1 : b0).locked &&
                       trace[k] > 0 && std::isfinite(trace[k]) &&
                       Quadric::closed_form_ok(trace[k], det[k], sigma2[k], pinv_tolerance_);
    if (!plain) [[unlikely]] {
      cost[k] = place(a[k], b[k]).cost;
      continue;
    }
    const double ca = clamp0(at_a[k]), cb = clamp0(at_b[k]);
    double best = cb < ca - noise[k] ? cb : ca;
    const double inner = clamp0(away[k] <= reach[k] ? at_opt[k] : at_mid[k]);
    if (inner < best - noise[k]) best = inner;
    cost[k] = best;
#ifndef __FP_FAST_FMA
    assert(cost[k] == place(a[k], b[k]).cost);
#endif
  }
  return cost;
}

}  // namespace geom::detail
