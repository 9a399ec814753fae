#include <geom/lod/collapse.h>

#include <geom/core/huge_pages.h>
#include <geom/spatial/bvh.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace geom::detail {

namespace {

// (b − a) × (c − a), spelled out: GCC leaves Eigen's cross of two difference expressions
// out of line, a call per triangle in the collapse checks.
Eigen::Vector3d normal(const Point& a, const Point& b, const Point& c) {
  const double ux = b.x() - a.x(), uy = b.y() - a.y(), uz = b.z() - a.z();
  const double vx = c.x() - a.x(), vy = c.y() - a.y(), vz = c.z() - a.z();
  return {uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx};
}

double quality(const Point& a, const Point& b, const Point& c, double area2) {
  const double s = (b - a).squaredNorm() + (c - b).squaredNorm() + (a - c).squaredNorm();
  // 4√3·A / Σl² with A = area2 / 2.
  return s > 0 ? 2.0 * std::sqrt(3.0) * area2 / s : 0.0;
}

}  // namespace

CollapseEngine::Placement CollapseEngine::place(std::uint32_t a, std::uint32_t b) const {
  const Point &pa = vd_[a].p, &pb = vd_[b].p;
  if (attributes_) [[unlikely]]
    return place_with_attributes(a, b, vd_[a].q.translated(-pa) + vd_[b].q.translated(-pb));
  // Each quadric is stored relative to its vertex's position: in model-sized coordinates a
  // cost of 1e-16 was the difference of O(1) terms, lost to round-off (fandisk). Summed
  // about a's position, every term stays as small as the edge.
  const Eigen::Vector3d e = pb - pa;
  Quadric q = vd_[a].q;
  q += vd_[b].q.translated(-e);
  // Q at the origin, a's position, is c.
  const double at_a = q.c < 0.0 ? 0.0 : q.c;
  if (vd_[a].locked) return {at_a, pa, 1};
  if (vd_[b].locked) return {q.evaluate(e), pb, 2};
  const Eigen::Vector3d m = 0.5 * e;
  // Differences below the evaluation's round-off (coordinates within twice the edge of
  // the origin) are ties.
  const double e2 = e.x() * e.x() + e.y() * e.y() + e.z() * e.z();
  const double noise =
      kTieTolerance * ((q.a00 + q.a11 + q.a22) * e2 +
                       (std::abs(q.b0) + std::abs(q.b1) + std::abs(q.b2)) *
                           (std::abs(e.x()) + std::abs(e.y()) + std::abs(e.z())) +
                       std::abs(q.c));
  // Which end is cheaper is a coin toss: pick it by index rather than by a branch that
  // would be mispredicted half the time.
  const double ends[2] = {at_a, q.evaluate(e)};
  const Point* end_points[2] = {&pa, &pb};
  const int end = ends[1] < ends[0] - noise;
  Placement best{ends[end], *end_points[end], 1 + end};
  const Eigen::Vector3d opt = q.minimizer(m, pinv_tolerance_);
  // The optimum must stay near the edge: a far-away minimiser of a nearly singular quadric
  // is numerically meaningless even when finite.
  const double reach = 4.0 * e2;
  if ((opt - m).squaredNorm() <= reach) {
    // Ties (within round-off) go to the endpoint: its position is then kept bit-exact,
    // which matters on flat regions and at corners where every choice costs ~0.
    const double co = q.evaluate(opt);
    if (co < best.cost - noise) best = {co, pa + opt, 0};
    // The minimiser, taken relative to the midpoint, costs no more than the midpoint
    // (Q(mid + δ) = Q(mid) − Σ (u·r)²/λ over the kept eigenvectors u): no need to try it.
    return best;
  }
  const double cm = q.evaluate(m);
  if (cm < best.cost - noise) best = {cm, 0.5 * (pa + pb), 3};
  return best;
}

// The queue orders by cost / √(face weight merged into the two ends) rather than by cost.
// The cost is an area-weighted sum of squared distances, so by cost alone a spike or crease
// made of small triangles goes before a large gently curved patch whose removal moves the
// surface farther: good for the RMS error, bad for the Hausdorff error. Divided by the weight
// it would be a mean squared distance, blind to how much surface a collapse moves. The
// square root sits between the two: over six meshes at 50/10/1% it took the Hausdorff error
// from 1.04× to 0.94× the best peer's (geometric mean), cost alone and the plain mean did
// worse. The weight leaves out the boundary constraint planes (the quadric's trace would
// not): with them, boundary vertices came up ten times early and open meshes lost up to 2×.
// But along a boundary, where the constraint planes make most of the cost, the face weight
// of the two ends says little: it is whatever interior area happened to collapse into them.
// On a flat disk with a hole (libigl's annulus) at 1% it varied 4000-fold between rim
// vertices, and those that had swallowed the interior took in ever more of the rim:
// survivors 2 to 5.4 input edges apart, Hausdorff 1.25× CGAL's. So a boundary collapse
// counts at most kBoundaryArea × the squared lengths of its ends' boundary edges (the weight
// of their planes over boundary_weight): 0.65× CGAL's there. A cap, not a replacement: a rim
// not yet grown heavy keeps its face weight (the boundary length alone let a hemisphere's
// curved rim go early: 1.11× CGAL's Hausdorff at 2%). With kBoundaryArea from 1 to 3 no
// other open-mesh result lost to a peer, except at 1 the Stanford bunny's RMS at 1% (1.002×).
inline float CollapseEngine::priority(std::uint32_t a, std::uint32_t b, double cost) const {
  double weight = vd_[a].weight + vd_[b].weight;
  if (vd_[a].boundary && vd_[b].boundary) [[unlikely]] {
    const double cap = kBoundaryArea * (boundary_length2_[a] + boundary_length2_[b]);
    if (cap > 0) weight = std::min(weight, cap);
  }
  return static_cast<float>(weight > 0 ? cost / std::sqrt(weight) : cost);
}

void CollapseEngine::set_costs(Candidate* c, std::size_t n) const {
  std::size_t i = 0;
  for (; i + 1 < n; i += 2) {
    const std::uint32_t a[2] = {c[i].a, c[i + 1].a}, b[2] = {c[i].b, c[i + 1].b};
    const std::array<double, 2> cost = place_cost_pair(a, b);
    c[i].cost = priority(a[0], b[0], cost[0]);
    c[i + 1].cost = priority(a[1], b[1], cost[1]);
  }
  if (i < n) c[i].cost = priority(c[i].a, c[i].b, place(c[i].a, c[i].b).cost);
}

void CollapseEngine::push_vertex_edges(Worker& wk, std::uint32_t v, bool reuse) {
  const std::uint32_t token = ++wk.token;
  vd_[v].mark = token;
  // Gather first and prefetch the neighbours' quadrics: their cache misses then overlap
  // instead of stalling one placement after another.
  wk.neighbours.clear();
  for (std::uint32_t i = vd_[v].ref_begin; i < vd_[v].ref_begin + vd_[v].ref_size; ++i) {
    const std::uint32_t t = refs_[i];
    for (std::uint32_t w : triangles_[t])
      if (vd_[w].mark != token) {
        vd_[w].mark = token;
        wk.neighbours.push_back(w);
        __builtin_prefetch(&vd_[w].q);
        __builtin_prefetch(&vd_[w].q.b1);
        __builtin_prefetch(&vd_[w].p);
      }
  }
  // Costs first, two edges at a time (set_costs), then the pushes.
  wk.pending.clear();
  const bool v_locked = vd_[v].locked;
  for (std::uint32_t w : wk.neighbours)
    if (!(v_locked && vd_[w].locked)) wk.pending.push_back({0.0f, v, w, stamp_[v] + stamp_[w]});
  if (!reuse || attributes_) {
    set_costs(wk.pending.data(), wk.pending.size());
  } else {
    set_costs_reusing(wk);
  }
  for (const Candidate& c : wk.pending) push(wk, c);
}

// set_costs() on w.pending, taking the costs of edges whose ends did not change since w last
// costed them here from w.costs, and keeping the others there. (Attribute placements read the
// wedges around an edge, which change without its ends' stamps: not for them.)
void CollapseEngine::set_costs_reusing(Worker& wk) const {
  if (wk.costs.empty()) wk.costs.resize(std::size_t{1} << kCostCacheBits);
  auto slot = [&](const Candidate& c) -> Worker::CachedCost& {
    return wk.costs[(c.a * 0x9e3779b1u ^ c.b * 0x85ebca77u) >> (32 - kCostCacheBits)];
  };
  wk.uncosted.clear();
  wk.uncosted_at.clear();
  for (std::uint32_t i = 0; i < wk.pending.size(); ++i) {
    Candidate& c = wk.pending[i];
    const Worker::CachedCost& e = slot(c);
    if (e.a == c.a && e.b == c.b && e.stamps == c.stamps) {
      c.cost = e.cost;  // place() reads the two ends' records alone
    } else {
      wk.uncosted.push_back(c);
      wk.uncosted_at.push_back(i);
    }
  }
  set_costs(wk.uncosted.data(), wk.uncosted.size());
  for (std::size_t k = 0; k < wk.uncosted.size(); ++k) {
    const Candidate& c = wk.uncosted[k];
    wk.pending[wk.uncosted_at[k]].cost = c.cost;
    slot(c) = {c.a, c.b, c.stamps, c.cost};
  }
}

void CollapseEngine::push(Worker& w, const Candidate& c) {
  if (parts_ == 0 || merged_) {
    w.queue.push(c);
    return;
  }
  const std::uint8_t r = region_[c.a];
  if (r != kSeam && r == region_[c.b]) workers_[r].queue.push(c);
  else if (w.in_step) w.staged.push_back(c);
  else workers_[parts_].queue.push(c);
}

void CollapseEngine::drop_ref(std::uint32_t w, std::uint32_t t) {
  // Order-preserving: traversal order decides ties, so it stays what it was.
  // The lists are short: a plain loop, not a call to memmove.
  std::uint32_t* list = refs_.get() + vd_[w].ref_begin;
  const std::uint32_t n = vd_[w].ref_size;
  std::uint32_t i = 0;
  while (list[i] != t) ++i;
  for (; i + 1 < n; ++i) list[i] = list[i + 1];
  vd_[w].ref_size = n - 1;
}

// Whether triangle t stays acceptable when its corner `moved` goes to p: no flip against its
// current normal, and no drop below the quality bound unless it was already that poor.
bool CollapseEngine::face_ok(std::uint32_t t, std::uint32_t moved, const Point& p,
                             FanFace& out) const {
  const auto& tri = triangles_[t];
  const int k = tri[0] == moved ? 0 : tri[1] == moved ? 1 : 2;
  const Point& a = vd_[tri[0]].p;
  const Point& b = vd_[tri[1]].p;
  const Point& c = vd_[tri[2]].p;
  const Eigen::Vector3d n0 = normal(a, b, c);
  const Point& a1 = k == 0 ? p : a;
  const Point& b1 = k == 1 ? p : b;
  const Point& c1 = k == 2 ? p : c;
  const Eigen::Vector3d n1 = normal(a1, b1, c1);
  out = {tri[(k + 1) % 3], tri[(k + 2) % 3], n1};
  if (n0.squaredNorm() > 0 && !(n0.dot(n1) > 0)) return false;
  // Most triangles pass the quality bound by far; those above twice the bound are let
  // through without a square root (quality² = 12·|n|² / s²).
  const double s1 = (b1 - a1).squaredNorm() + (c1 - b1).squaredNorm() + (a1 - c1).squaredNorm();
  const double m = options_.min_triangle_quality;
  if (12.0 * n1.squaredNorm() > 4.0 * m * m * s1 * s1) return true;
  const double q1 = quality(a1, b1, c1, n1.norm());
  return !(q1 < m && q1 < quality(a, b, c, n0.norm()));
}

void CollapseEngine::fan_face(std::uint32_t t, std::uint32_t moved, const Point& p,
                              FanFace& out) const {
  const auto& tri = triangles_[t];
  const int k = tri[0] == moved ? 0 : tri[1] == moved ? 1 : 2;
  const std::uint32_t x = tri[(k + 1) % 3], y = tri[(k + 2) % 3];
  out = {x, y, normal(p, vd_[x].p, vd_[y].p)};
}

// Whether two neighbouring triangles of the new fan (sharing an edge from the merged vertex)
// meet at a fold: normals more than acos(kFoldCos) apart. Each triangle alone may pass face_ok
// and yet the pair fold over; ordered by cost / √weight, such folds showed up on a noisy
// torus as triangles facing against the input surface.
bool CollapseEngine::fan_folds(Worker& w, int size) {
  // Each triangle's neighbour across the edge to its `prev` corner is the one whose `next`
  // that corner is: found through the corner's mark (one token per triangle) rather than by
  // scanning the fan, which cost more than the rest of the check.
  const std::uint32_t base = w.token + 1;
  w.token += static_cast<std::uint32_t>(size) + 1;
  const auto& fan = w.fan;
  for (int i = 0; i < size; ++i) vd_[fan[i].next].mark = base + static_cast<std::uint32_t>(i);
  const double c2 = kFoldCos * kFoldCos;
  for (int i = 0; i < size; ++i) {
    const std::uint32_t j = vd_[fan[i].prev].mark - base;
    if (j >= static_cast<std::uint32_t>(size) || fan[j].next != fan[i].prev) continue;
    const double d = fan[i].n.dot(fan[j].n);
    if (d < 0 && d * d > c2 * fan[i].n.squaredNorm() * fan[j].n.squaredNorm()) return true;
  }
  return false;
}

// The quadric measures the new position against the planes merged into it, not how far the
// surface moves away from the positions it drops: a thin spike's planes pass near its base,
// and a vertex that slides along a ridge to its optimum keeps the ridge's planes but leaves
// its old place hollow. So the height of the removed positions (u's, and v's when v moves)
// over the new fan is checked too; a collapse that leaves one more than √kTipRatio × the RMS
// quadric error (√(cost / weight)) above the surface costs kTipWeight · weight · height²
// instead (0: the quadric's cost stands). Over six meshes at 50/10/1% this took the
// Hausdorff losses to the best peer from 5 to 2 of 18 (on the 1M torus about one collapse
// in a thousand is requeued); a lower bound (the nearest plane of the fan) instead of the true
// distance, or checking only v, did worse.
double CollapseEngine::tip_cost(const Worker& w, std::uint32_t u, std::uint32_t v,
                                const Placement& pl) const {
  const double weight = vd_[u].weight + vd_[v].weight;
  if (w.fan_size == 0 || !(weight > 0)) return 0.0;
  const double t2 = kTipRatio * pl.cost / weight;
  double h2 = tip_height2(w, 0, pl.p, vd_[u].p, t2);
  if (pl.p != vd_[v].p)
    h2 = std::max(h2, tip_height2(w, w.fan_v < w.fan_size ? w.fan_v : 0, pl.p, vd_[v].p, t2));
  return kTipWeight * weight * std::max(h2, midpoint_height2(u, v, pl.p, w, t2));
}

// The squared distance of the new fan edges' midpoints from the old surface (u's and v's
// triangles before the collapse), when one is too high: more than √(kMidRatio · kTipRatio)
// × the RMS quadric error and more than kMidSlope × the edge's length; else 0. tip_cost()
// checks the removed positions against the new fan (original to simplified); this is the
// other way round, for an edge that comes to cut across a crease or groove, with its worst
// point inside the edge where no vertex shows it (armadillo at 50%: 5.9e-4 of the diagonal,
// 1.05x CGAL's maximum, along one such edge). The slope bound keeps it to steep cuts: gentle
// curvature bends the surface away from a chord by only a small fraction of its length.
// The height found counts at 1 / kMidRatio.
double CollapseEngine::midpoint_height2(std::uint32_t u, std::uint32_t v, const Point& p,
                                        const Worker& w, double t2) const {
  const double tm0 = kMidRatio * t2;
  double h2 = 0;
  for (int side = 0; side < 2; ++side) {
    // The fan's triangles from x's side: fan[first .. last).
    const std::uint32_t x = side == 0 ? u : v;
    const int first = side == 0 ? 0 : w.fan_v, last = side == 0 ? w.fan_v : w.fan_size;
    // The old edge x-q's midpoint, on the old surface, is within |p - x| / 2 of the new one:
    // none of this side's edges can be too high when that is within the bound (a survivor
    // that stays put, say).
    const double drift2 = 0.25 * (p - vd_[x].p).squaredNorm();
    if (drift2 <= tm0) continue;
    for (int i = first; i < last; ++i) {
      const std::uint32_t q = w.fan[i].next;
      const double tm = std::max(tm0, kMidSlope * kMidSlope * (p - vd_[q].p).squaredNorm());
      if (drift2 <= tm) continue;
      const Point m = 0.5 * (p + vd_[q].p);
      // The old triangles at the edge x-q usually hold a point near enough (for about 80%
      // of the edges on the 1M torus at 10%), and the fan has their corners at hand: those
      // of x's side with q as a corner. Only the other edges search both ends' lists (all
      // did before; the check then cost about 7% of simplify() there, now two thirds of
      // that). The margin keeps the outcome the search's: only a clear pass counts (a
      // rotation of the corners rounds differently).
      bool near = false;
      for (int j = first; j < last && !near; ++j) {
        const FanFace& f = w.fan[j];
        if (f.next != q && f.prev != q) continue;
        const Point c = closest_point_on_triangle(m, vd_[x].p, vd_[f.next].p, vd_[f.prev].p);
        near = (c - m).squaredNorm() <= tm * (1.0 - 1e-6);
      }
      if (near) continue;
      const double best = old_surface_distance2(u, v, q, m, tm);
      if (best > tm && std::isfinite(best)) h2 = std::max(h2, best / kMidRatio);
    }
  }
  return h2;
}

// The squared distance from m to u's and v's triangles, or any value up to tm once one of
// them is that near.
double CollapseEngine::old_surface_distance2(std::uint32_t u, std::uint32_t v, std::uint32_t q,
                                             const Point& m, double tm) const {
  // The triangles at q first: they usually hold the nearest point.
  double best = std::numeric_limits<double>::infinity();
  for (int pass = 0; pass < 2 && best > tm; ++pass)
    for (std::uint32_t y : {u, v}) {
      const std::uint32_t end = vd_[y].ref_begin + vd_[y].ref_size;
      for (std::uint32_t r = vd_[y].ref_begin; r < end && best > tm; ++r) {
        if (has_tri_with(refs_[r], q) != (pass == 0)) continue;
        const auto& tri = triangles_[refs_[r]];
        const Point c = closest_point_on_triangle(m, vd_[tri[0]].p, vd_[tri[1]].p, vd_[tri[2]].p);
        best = std::min(best, (c - m).squaredNorm());
      }
    }
  return best;
}

// The squared distance from x to the new fan around p, or 0 when it is at most t2. Most
// checks end at the first triangles tried: x's own former triangles (from `start`) usually
// hold its projection.
double CollapseEngine::tip_height2(const Worker& w, int start, const Point& p, const Point& x,
                                   double t2) const {
  const Eigen::Vector3d d = x - p;
  if (d.squaredNorm() <= t2) return 0.0;
  const int size = w.fan_size;
  const auto& fan = w.fan;
  for (int k = 0, i = start; k < size; ++k, i = i + 1 == size ? 0 : i + 1) {
    const Eigen::Vector3d& n = fan[i].n;
    const Point& a = vd_[fan[i].next].p;
    const Point& b = vd_[fan[i].prev].p;
    // Twice the signed areas that x's projection makes with the three edges; they sum to n·n.
    const double s1 = normal(p, a, x).dot(n);
    if (s1 < 0) continue;
    const double s2 = normal(a, b, x).dot(n);
    if (s2 < 0) continue;
    const double nn = n.squaredNorm();
    if (s1 + s2 > nn) continue;
    const double h = n.dot(d);
    if (h * h <= t2 * nn) return 0.0;
  }
  // Rarely: x projects onto no triangle near enough, or off the fan.
  for (int i = 0; i < size; ++i) {
    const double h = fan[i].n.dot(d);
    if (h * h > t2 * fan[i].n.squaredNorm()) continue;
    const Point c = closest_point_on_triangle(x, p, vd_[fan[i].next].p, vd_[fan[i].prev].p);
    if ((c - x).squaredNorm() <= t2) return 0.0;
  }
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < size; ++i) {
    const Point c = closest_point_on_triangle(x, p, vd_[fan[i].next].p, vd_[fan[i].prev].p);
    best = std::min(best, (c - x).squaredNorm());
  }
  return std::isfinite(best) ? best : 0.0;
}

void CollapseEngine::ensure_refs(Worker& w, std::size_t extra) {
  if (w.ref_end + extra <= w.ref_limit) return;
  // Out of room: rewrite the lists of live vertices, without the space of removed ones and of
  // superseded lists, into a fresh array with slack, so that this (rare) reallocation is
  // amortised over many collapses.
  std::size_t live = 0;
  for (const VertexData& d : vd_) live += d.ref_size;
  compact_refs(std::max(refs_capacity_, 2 * live + workers_.size() * extra + 64));
}

int CollapseEngine::try_collapse(Worker& wk, std::uint32_t u, std::uint32_t v,
                                 const Placement& pl) {
  // 1 = ok, 0 = topologically or geometrically invalid, 2 = over max_error.
  std::uint32_t opposite[2] = {kNone, kNone};
  int n_shared = 0;
  // The walk over u's triangles also marks u's neighbours for the link condition below.
  const std::uint32_t token_u = ++wk.token;
  for (std::uint32_t i = vd_[u].ref_begin; i < vd_[u].ref_begin + vd_[u].ref_size; ++i) {
    const std::uint32_t t = refs_[i];
    for (std::uint32_t w : triangles_[t]) vd_[w].mark = token_u;
    if (!has_tri_with(t, v)) continue;
    if (n_shared == 2) return 0;
    const auto& tri = triangles_[t];
    opposite[n_shared++] = tri[0] != u && tri[0] != v ? tri[0] : tri[1] != u && tri[1] != v ? tri[1] : tri[2];
    // The collapse would drop the shared triangle from this list: fetch it while the
    // checks below run.
    __builtin_prefetch(refs_.get() + vd_[opposite[n_shared - 1]].ref_begin);
    __builtin_prefetch(&tri_alive_[t], 1);
  }
  if (n_shared == 0) return 0;
  if (attributes_ && !attributes_allow(u, v, pl)) [[unlikely]] return 0;
  const bool boundary_edge = n_shared == 1;
  // An interior edge between two boundary vertices would pinch or merge boundaries.
  if (!boundary_edge && vd_[u].boundary && vd_[v].boundary) return 0;

  // Link condition: the common neighbours of u and v are exactly the opposite corners.
  const std::uint32_t token_common = ++wk.token;
  int common = 0;
  for (std::uint32_t i = vd_[v].ref_begin; i < vd_[v].ref_begin + vd_[v].ref_size; ++i) {
    const std::uint32_t t = refs_[i];
    for (std::uint32_t w : triangles_[t])
      if (w != u && w != v && vd_[w].mark == token_u) {
        vd_[w].mark = token_common;
        ++common;
      }
  }
  if (common != n_shared) return 0;

  // Valences stay sane: interior vertices keep ≥ 3 triangles, boundary ones ≥ 1. This is
  // what stops a tetrahedron from folding into a two-triangle pillow.
  for (int s = 0; s < n_shared; ++s) {
    const std::uint32_t w = opposite[s];
    if (vd_[w].ref_size - 1 < (vd_[w].boundary ? 1u : 3u)) return 0;
  }
  const std::uint32_t merged = vd_[u].ref_size + vd_[v].ref_size - 2u * static_cast<std::uint32_t>(n_shared);
  if (merged < ((vd_[u].boundary || vd_[v].boundary) ? 1u : 3u)) return 0;

  // The new fan is recorded on the way for the fold check (a larger fan, rare, goes unchecked).
  const bool fold = merged <= kFanMax;
  int fan = 0;
  FanFace spare;
  auto& new_fan = wk.fan;
  for (std::uint32_t i = vd_[u].ref_begin; i < vd_[u].ref_begin + vd_[u].ref_size; ++i) {
    const std::uint32_t t = refs_[i];
    if (has_tri_with(t, v)) continue;
    if (!face_ok(t, u, pl.p, fold ? new_fan[fan++] : spare)) return 0;
  }
  wk.fan_v = fan;
  // A survivor that stays put leaves its own triangles as they were.
  const bool moves = pl.p != vd_[v].p;
  if (moves || fold)
    for (std::uint32_t i = vd_[v].ref_begin; i < vd_[v].ref_begin + vd_[v].ref_size; ++i) {
      const std::uint32_t t = refs_[i];
      if (has_tri_with(t, u)) continue;
      if (!moves) fan_face(t, v, pl.p, new_fan[fan++]);
      else if (!face_ok(t, v, pl.p, fold ? new_fan[fan++] : spare)) return 0;
    }
  if (fold && fan_folds(wk, fan)) return 0;
  wk.fan_size = fold ? fan : 0;

  if (std::isfinite(options_.max_error)) {
    const double w = vd_[u].weight + vd_[v].weight;
    const double err = w > 0 ? std::sqrt(pl.cost / w) * scale_ : 0.0;
    if (err > options_.max_error) return 2;
  }
  return 1;
}

int CollapseEngine::collapse(Worker& wk, std::uint32_t u, std::uint32_t v, const Placement& pl) {
  if (attributes_) [[unlikely]] collapse_attributes(u, v);
  ensure_refs(wk, vd_[u].ref_size + vd_[v].ref_size);
  std::uint32_t* const refs = refs_.get();
  CollapseRecord rec;
  if (record_) {
    rec.u = u;
    rec.v = v;
    rec.pos_u = model_[u];
    rec.pos_v_before = model_[v];
    rec.changed_begin = static_cast<std::uint32_t>(changed_.size());
  }
  const auto new_begin = static_cast<std::uint32_t>(wk.ref_end);
  std::uint32_t* out = refs + new_begin;
  for (std::uint32_t i = vd_[v].ref_begin; i < vd_[v].ref_begin + vd_[v].ref_size; ++i) {
    const std::uint32_t t = refs[i];
    if (!has_tri_with(t, u)) *out++ = t;
  }
  int n_dead = 0;
  for (std::uint32_t i = vd_[u].ref_begin; i < vd_[u].ref_begin + vd_[u].ref_size; ++i) {
    const std::uint32_t t = refs[i];
    auto& tri = triangles_[t];
    if (has_tri_with(t, v)) {
      tri_alive_[t] = 0;
      for (std::uint32_t w : tri)
        if (w != u && w != v) {
          drop_ref(w, t);
        }
      if (record_) rec.dead[n_dead] = t;
      ++n_dead;
      continue;
    }
    for (std::uint32_t k = 0; k < 3; ++k)
      if (tri[k] == u) {
        tri[k] = v;
        if (record_) changed_.push_back(3 * t + k);
      }
    *out++ = t;
  }
  const double w = vd_[u].weight + vd_[v].weight;
  if (w > 0) wk.max_error = std::max(wk.max_error, std::sqrt(pl.cost / w) * scale_);

  wk.ref_end = static_cast<std::size_t>(out - refs);
  vd_[v].ref_begin = new_begin;
  vd_[v].ref_size = static_cast<std::uint32_t>(wk.ref_end - new_begin);
  vd_[u].ref_size = 0;
  if (!merged_into_.empty()) merged_into_[u] = v;
  // Both quadrics move to the survivor's new position, their new origin.
  vd_[v].q = vd_[v].q.translated(pl.p - vd_[v].p) + vd_[u].q.translated(pl.p - vd_[u].p);
  vd_[v].weight = w;
  if (vd_[u].boundary) boundary_length2_[v] += boundary_length2_[u];
  vd_[v].p = pl.p;
  // Sources 1 and 2 keep the survivor's own position (run() orders u, v so): its model-unit
  // value stays, so kept and locked vertices stay bit-exact. A moved vertex gets its model
  // position from vd_[v].p when it is needed (model()): writing it here was a cache miss
  // per collapse, and simplify() needs only the survivors' at the end.
  if (pl.source == 0 || pl.source == 3) {
    vd_[v].moved = 1;
    if (record_) model_[v] = model(v);
  }
  vd_[v].boundary |= vd_[u].boundary;
  ++stamp_[v];
  ++stamp_[u];
  ++wk.collapses;
  wk.removed += static_cast<std::size_t>(n_dead);
  if (record_) {
    rec.pos_v_after = model_[v];
    rec.changed_end = static_cast<std::uint32_t>(changed_.size());
    records_.push_back(rec);
  }
  return n_dead;
}

// Each collapse lands somewhere random on the surface, and its data is a chain of dependent
// loads (vertex record → triangle list → triangles → neighbours' records). Fetch that chain
// for the next few queued collapses in stages, one link per stage, so that by the time a
// collapse comes up its neighbourhood is in cache, and the misses of several collapses
// overlap instead of stalling one after another.
void CollapseEngine::prefetch_upcoming(const Worker& w) const {
  const RadixQueue& queue = w.queue;
  auto ends = [](const Candidate* c) { return std::array<std::uint32_t, 2>{c->a, c->b}; };
  if (const Candidate* c = queue.peek(6))
    for (std::uint32_t x : ends(c)) {
      __builtin_prefetch(&vd_[x].q);
      __builtin_prefetch(&vd_[x].p);
    }
  if (const Candidate* c = queue.peek(4))
    for (std::uint32_t x : ends(c)) {
      const std::uint32_t* list = refs_.get() + vd_[x].ref_begin;
      __builtin_prefetch(list);
      if (vd_[x].ref_size > 1) __builtin_prefetch(list + vd_[x].ref_size - 1);
      // A progressive mesh's records read and write the model positions.
      if (record_) __builtin_prefetch(&model_[x], 1);
    }
  if (const Candidate* c = queue.peek(2))
    for (std::uint32_t x : ends(c))
      for (std::uint32_t i = vd_[x].ref_begin; i < vd_[x].ref_begin + vd_[x].ref_size; ++i)
        __builtin_prefetch(&triangles_[refs_[i]]);
  // One corner per triangle, the one after x: around an interior vertex that is each
  // neighbour once, where all three corners fetched each neighbour twice and x itself every
  // time, and the surplus prefetches queued behind the misses.
  if (const Candidate* c = queue.peek(0))
    for (std::uint32_t x : ends(c))
      for (std::uint32_t i = vd_[x].ref_begin; i < vd_[x].ref_begin + vd_[x].ref_size; ++i) {
        const auto& tri = triangles_[refs_[i]];
        const std::uint32_t w = tri[0] == x ? tri[1] : tri[1] == x ? tri[2] : tri[0];
        __builtin_prefetch(&vd_[w].q);
        __builtin_prefetch(&vd_[w].p);
        __builtin_prefetch(&stamp_[w]);
      }
}

CollapseEngine::Drain CollapseEngine::drain(Worker& wk, const DrainLimits& limits) {
  std::size_t removed = 0, next_report = wk.collapses + 4096;
  const std::size_t spare = limits.exact ? 1 : 0;
  while (removed + spare < limits.faces) {
    const Candidate* top = wk.queue.top();
    if (!top) return Drain::kEmpty;
    if (RadixQueue::key(top->cost) > limits.key) return Drain::kLimit;
    const Candidate c = *top;
    wk.queue.drop_top();
    if (wk.in_step) {
      // An end became seam since the entry was queued: it is the seam's now.
      if (region_[c.a] != wk.part || region_[c.b] != wk.part) {
        wk.staged.push_back(c);
        continue;
      }
      // Only the serial code may move refs_.
      if (wk.ref_end + vd_[c.a].ref_size + vd_[c.b].ref_size > wk.ref_limit) {
        wk.queue.push(c);
        return Drain::kRoom;
      }
    }
    if (vd_.size() > kPrefetchMinVertices) prefetch_upcoming(wk);
    const Placement pl = place(c.a, c.b);
    // Remove the vertex whose position is not kept; a locked vertex is always the survivor.
    std::uint32_t u = c.a, v = c.b;
    if (pl.source == 1 || vd_[c.a].locked) std::swap(u, v);
    const int verdict = try_collapse(wk, u, v, pl);
    if (verdict != 1) {
      // Remember both ends: when a neighbour changes, their edges get another chance.
      vd_[c.a].retry = vd_[c.b].retry = 1;
      if (verdict == 2) wk.error_rejected = true;
      continue;
    }
    // Requeued at the higher cost, unless it already came out at it: with its neighbourhood
    // unchanged the same cost comes back, and the collapse goes ahead.
    if (const double tip = tip_cost(wk, u, v, pl); tip > pl.cost) {
      const float key = priority(c.a, c.b, tip);
      if (key > c.cost * (1.0f + 1e-6f)) {
        push(wk, {key, c.a, c.b, c.stamps});
        continue;
      }
    }
    const int dead = collapse(wk, u, v, pl);
    removed += static_cast<std::size_t>(dead);
    if (!wk.in_step) {
      alive_triangles_ -= static_cast<std::size_t>(dead);
      if (parts_ > 0 && !merged_) extend_seam(v);
    }
    // Re-evaluated now, while the neighbourhood is in cache, rather than when the old
    // entries reach the top.
    vd_[v].retry = 0;
    push_vertex_edges(wk, v);
    // Neighbours with rejected edges: their surroundings changed, so queue their edges
    // again (duplicates of still-valid entries are harmless). push_vertex_edges left v's
    // neighbours in neighbours, in the order of a walk over v's triangles.
    wk.retry.clear();
    for (std::uint32_t w : wk.neighbours)
      if (vd_[w].retry) wk.retry.push_back(w);
    for (std::uint32_t w : wk.retry) {
      vd_[w].retry = 0;
      // A seam vertex's edges reach other parts: the seam queues them after the step.
      if (wk.in_step && region_[w] != wk.part) wk.staged_retry.push_back(w);
      else push_vertex_edges(wk, w, true);
    }
    if (!wk.in_step && options_.progress && wk.collapses >= next_report) {
      next_report = wk.collapses + 4096;
      if (!options_.progress(progress())) return Drain::kCancelled;
    }
  }
  return Drain::kDone;
}

double CollapseEngine::progress() const {
  const double total = static_cast<double>(run_start_ - run_target_);
  return total > 0 ? static_cast<double>(run_start_ - alive_triangles_) / total : 1.0;
}

std::size_t CollapseEngine::n_collapses() const {
  std::size_t n = 0;
  for (const Worker& w : workers_) n += w.collapses;
  return n;
}

double CollapseEngine::max_error() const {
  double e = 0;
  for (const Worker& w : workers_) e = std::max(e, w.max_error);
  return e;
}

}  // namespace geom::detail
