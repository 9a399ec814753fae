#include <geom/subdivision/limit.h>
#include <geom/subdivision/subdivision.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

namespace geom {
namespace detail::subdiv {

namespace {

/// Smooth limit weights of a vertex with n faces: on the vertex, on each edge end and (for
/// Catmull-Clark) on each opposite face corner, whose weight is a quarter of the edge's.
struct SmoothWeights {
  double vertex, edge, face;
};

SmoothWeights catmark_weights(std::uint32_t n) {
  const double nn = n, f = 1.0 / (nn * (nn + 5.0));
  return {1.0 - nn * 5.0 * f, 4.0 * f, f};
}

SmoothWeights loop_weights(std::uint32_t n) {
  const double nn = n, beta = 0.25 * std::cos(2.0 * M_PI / nn) + 0.375;
  const double gamma = (0.625 - beta * beta) / nn;
  const double e = 1.0 / (nn + 3.0 / (8.0 * gamma));
  return {1.0 - nn * e, e, 0.0};
}

/// The weights of valences below kCached, computed once (the cosines and divisions cost
/// more than the rest of a vertex's mask), the others on demand.
class WeightTable {
 public:
  explicit WeightTable(bool catmark) : catmark_(catmark) {
    for (std::uint32_t n = 1; n < kCached; ++n)
      cache_[n] = catmark ? catmark_weights(n) : loop_weights(n);
  }
  SmoothWeights operator()(std::uint32_t n) const {
    if (n < kCached) return cache_[n];
    return catmark_ ? catmark_weights(n) : loop_weights(n);
  }

 private:
  static constexpr std::uint32_t kCached = 32;
  bool catmark_;
  SmoothWeights cache_[kCached] = {};
};

/// A row of width W (or w) to sum into: on the stack unless it is wider than kStack.
template <int W>
struct Scratch {
  static constexpr int kStack = 64;
  explicit Scratch(int w) : wide(W || w <= kStack ? 0 : static_cast<std::size_t>(w)) {}
  double* data() { return wide.empty() ? stack : wide.data(); }
  double stack[W ? W : kStack];
  std::vector<double> wide;
};

template <int W>
const double* row(const double* data, std::uint32_t i, int w) {
  return data + static_cast<std::size_t>(i) * (W ? W : w);
}
template <int W>
double* row(double* data, std::uint32_t i, int w) {
  return data + static_cast<std::size_t>(i) * (W ? W : w);
}

/// out = wv·v + wa·(a + b): the crease limit (wv = 2/3, wa = 1/6).
template <int W>
void blend2(double* out, const double* v, double wv, const double* a, const double* b,
            double wa, int w) {
  for (int k = 0; k < (W ? W : w); ++k) out[k] = wv * v[k] + wa * (a[k] + b[k]);
}

/// out = wv·v + ws·sum: the smooth limit from the sum of the ring's weighted rows.
template <int W>
void finish(double* out, const double* v, double wv, const double* sum, double ws, int w) {
  for (int k = 0; k < (W ? W : w); ++k) out[k] = wv * v[k] + ws * sum[k];
}


/// Sharpness of edge e of the refined level `c` (smooth when nothing in it is sharp).
float edge_sharpness(const Level& c, std::uint32_t e) {
  return c.has_sharpness() ? c.esharp[e] : kSmooth;
}

/// prev(h) inside its face, by walking the face (Level keeps no prev links).
std::uint32_t prev_in_face(const Level& p, std::uint32_t h) {
  std::uint32_t g = p.next[h];
  while (p.next[g] != h) g = p.next[g];
  return g;
}

/// Where a vertex's limit mask finds its ring, as rows of src: the level's own neighbours
/// (LevelRing), or for the child level's vertex-points the edge- and face-points made from
/// the parent's ring, with the child's sharpness (ChildRing). The mask is one (vertex_masks).
struct LevelRing {
  const Level& l;
  std::uint32_t vertex(std::uint32_t v) const { return v; }
  std::uint32_t edge_end(std::uint32_t h) const { return l.to[h]; }
  std::uint32_t opposite(std::uint32_t h) const { return l.to[l.next[h]]; }  // Catmull-Clark
  bool edge_sharp(std::uint32_t h) const { return l.has_sharpness() && is_sharp(l.esharp[h >> 1]); }
  float vertex_sharpness(std::uint32_t v) const { return l.has_sharpness() ? l.vsharp[v] : kSmooth; }
};

struct ChildRing {
  const Level& p;  // the parent, whose ring is walked
  const Level& c;
  std::uint32_t edge_base, vertex_base;  // first child row of the edge-points, vertex-points
  std::uint32_t vertex(std::uint32_t v) const { return vertex_base + v; }
  std::uint32_t edge_end(std::uint32_t h) const { return edge_base + (h >> 1); }
  std::uint32_t opposite(std::uint32_t h) const { return p.face[h]; }  // the face-point
  bool edge_sharp(std::uint32_t h) const { return is_sharp(edge_sharpness(c, p.n_corners + h)); }
  float vertex_sharpness(std::uint32_t v) const {
    return c.has_sharpness() ? c.vsharp[vertex_base + v] : kSmooth;
  }
};

/// The limit masks of the vertices of `walk`, one walk around each ring. Edge ends count 4
/// and opposite corners 1 in `sum` for Catmull-Clark (its edge weight is four times its face
/// weight), edge ends 1 for Loop, so one weight finishes the smooth mask.
template <int W, class Ring>
void vertex_masks(const Level& walk, const Ring& ring, const double* src, double* dst, int w,
                  const Context& ctx) {
  const WeightTable weights(ctx.catmark);
  const double edge_weight = ctx.catmark ? 4.0 : 1.0;
  for_range(walk.nv, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    Scratch<W> scratch(w);
    double* sum = scratch.data();
    for (std::uint32_t v = b; v < end; ++v) {
      const double* pv = row<W>(src, ring.vertex(v), w);
      double* out = row<W>(dst, ring.vertex(v), w);
      const std::uint32_t h0 = walk.vh[v];
      if (h0 == kNone) {
        Row<W>::set(out, pv, 1.0, w);
        continue;
      }
      int sharp_edges = 0;
      std::uint32_t n_faces = 0, ends[2] = {0, 0};
      Row<W>::zero(sum, w);
      std::uint32_t h = h0;
      do {
        const std::uint32_t e = ring.edge_end(h);
        if (ring.edge_sharp(h)) ends[sharp_edges++ & 1] = e;
        Row<W>::add(sum, row<W>(src, e, w), edge_weight, w);
        if (walk.face[h] != kNone) {
          ++n_faces;
          if (ctx.catmark) Row<W>::add(sum, row<W>(src, ring.opposite(h), w), 1.0, w);
        }
        h = walk.cw(h);
      } while (h != h0);
      const Rule rule = vertex_rule(ring.vertex_sharpness(v), sharp_edges);
      // A Catmull-Clark vertex of two faces that is not a crease stays put.
      if (rule == kRuleCorner || (rule != kRuleCrease && ctx.catmark && n_faces == 2)) {
        Row<W>::set(out, pv, 1.0, w);
      } else if (rule == kRuleCrease) {
        blend2<W>(out, pv, 2.0 / 3.0, row<W>(src, ends[0], w), row<W>(src, ends[1], w),
                  1.0 / 6.0, w);
      } else {
        const SmoothWeights sw = weights(n_faces);
        finish<W>(out, pv, sw.vertex, sum, ctx.catmark ? sw.face : sw.edge, w);
      }
    }
  });
}

/// Limit masks over a level's own connectivity.
template <int W>
void limit_level(const Level& l, const double* src, double* dst, int w, const Context& ctx) {
  vertex_masks<W>(l, LevelRing{l}, src, dst, w, ctx);
}

/// Catmull-Clark limit of the child level of `p` from the parent's connectivity, element
/// by element as refinement made the child vertices (face-, edge-, vertex-points), so the
/// reads and writes run through the arrays in order instead of around scattered rings.
/// Child vertices: face-point of f at f, edge-point of e at F + e, vertex-point of v at
/// F + E + v; the child edge at from(h) of parent edge h/2 is C + h (level.h).
template <int W>
void limit_catmark_children(const Level& p, const Level& c, const double* src, double* dst,
                            int w, const Context& ctx) {
  const std::uint32_t F = p.nf, E = p.ne, FE = F + E, C = p.n_corners;
  const WeightTable weights(true);
  // A face-point is smooth with one face per corner: edge ends are the edge-points of the
  // face's edges, opposite corners the vertex-points of its corners.
  for_range(F, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    Scratch<W> scratch(w);
    double* sum = scratch.data();
    for (std::uint32_t f = b; f < end; ++f) {
      Row<W>::zero(sum, w);
      std::uint32_t n = 0, h = p.fh[f];
      do {
        Row<W>::add(sum, row<W>(src, F + (h >> 1), w), 4.0, w);
        Row<W>::add(sum, row<W>(src, FE + p.to[h], w), 1.0, w);
        ++n;
        h = p.next[h];
      } while (h != p.fh[f]);
      const SmoothWeights sw = weights(n);
      finish<W>(row<W>(dst, f, w), row<W>(src, f, w), sw.vertex, sum, sw.face, w);
    }
  });
  // An edge-point is a crease between its end vertex-points when both halves stay sharp
  // (boundary edges always do); otherwise it is regular: edge ends are the end
  // vertex-points and the face-points, opposite corners the edge-points of the edges
  // before and after it in both faces.
  for_range(E, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    Scratch<W> scratch(w);
    double* sum = scratch.data();
    for (std::uint32_t e = b; e < end; ++e) {
      const std::uint32_t h0 = 2 * e, h1 = 2 * e + 1;
      const double* va = row<W>(src, FE + p.to[h1], w);
      const double* vb = row<W>(src, FE + p.to[h0], w);
      const double* pe = row<W>(src, F + e, w);
      double* out = row<W>(dst, F + e, w);
      if (is_sharp(edge_sharpness(c, C + h0)) && is_sharp(edge_sharpness(c, C + h1))) {
        blend2<W>(out, pe, 2.0 / 3.0, va, vb, 1.0 / 6.0, w);
        continue;
      }
      Row<W>::set(sum, va, 4.0, w);
      Row<W>::add(sum, vb, 4.0, w);
      for (std::uint32_t h : {h0, h1}) {
        Row<W>::add(sum, row<W>(src, p.face[h], w), 4.0, w);
        Row<W>::add(sum, row<W>(src, F + (p.next[h] >> 1), w), 1.0, w);
        Row<W>::add(sum, row<W>(src, F + (prev_in_face(p, h) >> 1), w), 1.0, w);
      }
      finish<W>(out, pe, 4.0 / 9.0, sum, 1.0 / 36.0, w);
    }
  });
  vertex_masks<W>(p, ChildRing{p, c, F, FE}, src, dst, w, ctx);
}

/// Loop's counterpart: child vertices are edge-points (e) then vertex-points (E + v); an
/// interior edge-point is regular (six triangles), its ring the end vertex-points and the
/// edge-points of the two other edges of both faces.
template <int W>
void limit_loop_children(const Level& p, const Level& c, const double* src, double* dst,
                         int w, const Context& ctx) {
  const std::uint32_t E = p.ne, C = p.n_corners;
  const WeightTable weights(false);
  const SmoothWeights regular = weights(6);
  for_range(E, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    Scratch<W> scratch(w);
    double* sum = scratch.data();
    for (std::uint32_t e = b; e < end; ++e) {
      const std::uint32_t h0 = 2 * e, h1 = 2 * e + 1;
      const double* va = row<W>(src, E + p.to[h1], w);
      const double* vb = row<W>(src, E + p.to[h0], w);
      const double* pe = row<W>(src, e, w);
      double* out = row<W>(dst, e, w);
      if (is_sharp(edge_sharpness(c, C + h0)) && is_sharp(edge_sharpness(c, C + h1))) {
        blend2<W>(out, pe, 2.0 / 3.0, va, vb, 1.0 / 6.0, w);
        continue;
      }
      Row<W>::set(sum, va, 1.0, w);
      Row<W>::add(sum, vb, 1.0, w);
      for (std::uint32_t h : {h0, h1}) {
        const std::uint32_t g = p.next[h];
        Row<W>::add(sum, row<W>(src, g >> 1, w), 1.0, w);
        Row<W>::add(sum, row<W>(src, p.next[g] >> 1, w), 1.0, w);
      }
      finish<W>(out, pe, regular.vertex, sum, regular.edge, w);
    }
  });
  vertex_masks<W>(p, ChildRing{p, c, 0, E}, src, dst, w, ctx);
}

Eigen::Vector3d row3(const double* data, std::uint32_t v, int w) {
  const double* p = data + static_cast<std::size_t>(v) * w;
  return {p[0], p[1], p[2]};
}

/// Sum over the faces at v of (a − v) × (b − v) for consecutive ring neighbours a, b:
/// twice the area-weighted normal of the fan (exactly that for triangles).
Eigen::Vector3d fan_normal(const Level& l, std::uint32_t v, const double* pos, int w) {
  const Eigen::Vector3d pv = row3(pos, v, w);
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  const std::uint32_t h0 = l.vh[v];
  std::uint32_t prev = h0, h = l.cw(h0);
  // cw(h) follows h clockwise, so face(h) lies between h and the previous (ccw) one.
  do {
    if (l.face[h] != kNone) n += (row3(pos, l.to[h], w) - pv).cross(row3(pos, l.to[prev], w) - pv);
    prev = h;
    h = l.cw(h);
  } while (prev != h0);
  return n;
}

/// The ring of v in OpenSubdiv's order: outgoing halfedges counter-clockwise, face i lying
/// between edges i and i + 1, starting after the boundary on a boundary vertex and at the
/// lowest-numbered face otherwise (OpenSubdiv orders a control vertex from its first face).
/// The crease and corner tangent masks depend on this order.
void osd_ring(const Level& l, std::uint32_t v, bool boundary,
              std::vector<std::uint32_t>& cw, std::vector<std::uint32_t>& ring) {
  std::uint32_t start = l.vh[v];
  if (!boundary) {
    std::uint32_t h = start;
    do {
      if (l.face[h] < l.face[start]) start = h;
      h = l.cw(h);
    } while (h != l.vh[v]);
  }
  cw.clear();
  std::uint32_t h = start;
  do {
    cw.push_back(h);
    h = l.cw(h);
  } while (h != start);
  // Clockwise from the start reversed is counter-clockwise; a boundary vertex's clockwise
  // walk from its boundary halfedge ends at the counter-clockwise first edge.
  const std::size_t k = cw.size();
  ring.resize(k);
  for (std::size_t i = 0; i < k; ++i) ring[i] = boundary ? cw[k - 1 - i] : cw[(k - i) % k];
}

/// Tangents along and across a crease whose sharp edges are ring[c0] and ring[c1], c0 < c1,
/// over the faces between them: the uniform B-spline cross tangent when one edge lies
/// between, Biermann-Levin-Zorin's masks for more, and the average of the crease edges for
/// a single face (Catmull-Clark); Loop's masks are the triangle analogues.
std::pair<Eigen::Vector3d, Eigen::Vector3d> crease_tangents(
    const Level& l, std::uint32_t v, const std::vector<std::uint32_t>& ring, std::size_t c0,
    std::size_t c1, const double* pos, int w, bool catmark) {
  const Eigen::Vector3d pv = row3(pos, v, w);
  auto edge_end = [&](std::size_t i) { return row3(pos, l.to[ring[i]], w); };
  auto face_opposite = [&](std::size_t i) { return row3(pos, l.to[l.next[ring[i]]], w); };
  const Eigen::Vector3d along = edge_end(c0) - edge_end(c1);
  const std::size_t inner = c1 - c0 - 1;
  Eigen::Vector3d across = Eigen::Vector3d::Zero();
  if (inner == 0) {
    across = edge_end(c0) + edge_end(c1) - 2.0 * pv;
  } else if (catmark && inner == 1) {
    across = -4.0 * pv - edge_end(c0) + 4.0 * edge_end(c0 + 1) - edge_end(c1) +
             face_opposite(c0) + face_opposite(c0 + 1);
  } else if (catmark) {
    const double k = static_cast<double>(inner + 1), theta = M_PI / k;
    const double c = std::cos(theta), sn = std::sin(theta);
    const double r = (c + 1.0) / sn;
    across = 4.0 * r * (c - 1.0) * pv - r * (1.0 + 2.0 * c) * (edge_end(c0) + edge_end(c1)) +
             sn * face_opposite(c0);
    for (std::size_t i = 1; i <= inner; ++i) {
      const double si = std::sin(static_cast<double>(i) * theta);
      const double si1 = std::sin(static_cast<double>(i + 1) * theta);
      across += 4.0 * si * edge_end(c0 + i) + (si + si1) * face_opposite(c0 + i);
    }
  } else if (inner == 1) {
    across = edge_end(c0 + 1) - pv;
  } else if (inner == 2) {
    across = -pv - 0.5 * (edge_end(c0) + edge_end(c1)) + edge_end(c0 + 1) +
             edge_end(c0 + 2);
  } else {
    const double theta = M_PI / static_cast<double>(inner + 1);
    across = -std::sin(theta) * (edge_end(c0) + edge_end(c1));
    for (std::size_t i = 1; i <= inner; ++i)
      across += 2.0 * (1.0 - std::cos(theta)) * std::sin(static_cast<double>(i) * theta) *
                edge_end(c0 + i);
  }
  return {along, across};
}

/// tan1 × tan2 of the smooth tangent masks over the clockwise ring (valence 3 or more),
/// zero otherwise.
Eigen::Vector3d smooth_normal(const Level& l, const std::vector<std::uint32_t>& cw,
                              const double* src, int w, bool catmark) {
  const std::size_t k = cw.size();
  if (k < 3) return Eigen::Vector3d::Zero();
  // Tangent masks over the ring in counter-clockwise order (the reverse of `cw`), face i
  // lying between edges i and i + 1.
  const double theta = 2.0 * M_PI / static_cast<double>(k);
  Eigen::Vector3d t1 = Eigen::Vector3d::Zero(), t2 = Eigen::Vector3d::Zero();
  double face_scale = 0.0;
  if (catmark) {
    const double c = std::cos(theta), ch = std::cos(0.5 * theta);
    const double lambda = 5.0 / 16.0 + (c + ch * std::sqrt(2.0 * (9.0 + c))) / 16.0;
    face_scale = 1.0 / (4.0 * lambda - 1.0);
  }
  for (std::size_t i = 0; i < k; ++i) {
    const std::uint32_t h = cw[(k - i) % k];
    const Eigen::Vector3d e = row3(src, l.to[h], w);
    const double a = i * theta, a1 = (i + 1) * theta;
    if (catmark) {
      const Eigen::Vector3d f = row3(src, l.to[l.next[h]], w);
      t1 += 4.0 * std::cos(a) * e + face_scale * (std::cos(a) + std::cos(a1)) * f;
      t2 += 4.0 * std::sin(a) * e + face_scale * (std::sin(a) + std::sin(a1)) * f;
    } else {
      t1 += std::cos(a) * e;
      t2 += std::sin(a) * e;
    }
  }
  return t1.cross(t2);
}

void limit_normals(const Level& l, const double* src, const double* limit, int w,
                   double* normals, const Context& ctx) {
  const bool sharp = l.has_sharpness();
  for_range(l.nv, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    std::vector<std::uint32_t> cw, ring;
    for (std::uint32_t v = b; v < end; ++v) {
      Eigen::Vector3d n = Eigen::Vector3d::Zero();
      const std::uint32_t h0 = l.vh[v];
      if (h0 == kNone) {
        Eigen::Map<Eigen::Vector3d>(normals + 3 * static_cast<std::size_t>(v)) = n;
        continue;
      }
      const bool boundary = l.face[h0] == kNone;
      osd_ring(l, v, boundary, cw, ring);
      const std::size_t k = ring.size();
      std::size_t ends[2] = {0, 0};
      int sharp_edges = 0;
      for (std::size_t i = 0; i < k; ++i)
        if (sharp && is_sharp(l.esharp[ring[i] >> 1])) ends[sharp_edges++ & 1] = i;
      Rule rule = vertex_rule(sharp ? l.vsharp[v] : kSmooth, sharp_edges);
      // Catmull-Clark's smooth masks degenerate at two faces; OpenSubdiv takes the corner's.
      if ((rule == kRuleSmooth || rule == kRuleDart) && ctx.catmark && k == 2) rule = kRuleCorner;
      const Eigen::Vector3d pv = row3(src, v, w);
      if (rule == kRuleSmooth || rule == kRuleDart) {
        n = smooth_normal(l, cw, src, w, ctx.catmark);
      } else if (rule == kRuleCrease) {
        const auto [along, across] =
            crease_tangents(l, v, ring, ends[0], ends[1], src, w, ctx.catmark);
        n = along.cross(across);
      } else if (k >= 2) {
        n = (row3(src, l.to[ring[0]], w) - pv).cross(row3(src, l.to[ring[1]], w) - pv);
      }
      // Orient as the faces are (OpenSubdiv's tangent pair may be either handedness).
      const Eigen::Vector3d fan = fan_normal(l, v, src, w);
      if (n.squaredNorm() == 0.0) n = fan_normal(l, v, limit, w);
      if (n.dot(fan) < 0.0) n = -n;
      const double len = n.norm();
      if (len > 0.0) n /= len;
      Eigen::Map<Eigen::Vector3d>(normals + 3 * static_cast<std::size_t>(v)) = n;
    }
  });
}

}  // namespace

void limit_points(const Level& l, const double* src, double* dst, int w, double* normals,
                  const Context& ctx) {
  if (w == 3)
    limit_level<3>(l, src, dst, w, ctx);
  else
    limit_level<0>(l, src, dst, w, ctx);
  if (normals) limit_normals(l, src, dst, w, normals, ctx);
}

void limit_children(const Level& p, const Level& c, const double* src, double* dst, int w,
                    const Context& ctx) {
  if (ctx.catmark && w == 3)
    limit_catmark_children<3>(p, c, src, dst, w, ctx);
  else if (ctx.catmark)
    limit_catmark_children<0>(p, c, src, dst, w, ctx);
  else if (w == 3)
    limit_loop_children<3>(p, c, src, dst, w, ctx);
  else
    limit_loop_children<0>(p, c, src, dst, w, ctx);
}

}  // namespace detail::subdiv

LimitResult limit_positions(const SurfaceMesh& input, const LimitOptions& options) {
  using namespace detail::subdiv;
  SurfaceMesh compacted;
  const SurfaceMesh* mesh = &input;
  if (input.has_garbage()) {
    compacted = input;
    compacted.compact();
    mesh = &compacted;
  }
  const bool catmark = options.scheme == SubdivisionScheme::kCatmullClark;
  Level level = build_level0(*mesh, options.boundary == BoundaryInterpolation::kEdgesAndCorners,
                             catmark ? 4 : 3);
  Context ctx;
  ctx.catmark = catmark;
  const auto& points = mesh->positions().vector();
  std::vector<double> src(3 * static_cast<std::size_t>(level.nv));
  for (std::uint32_t v = 0; v < level.nv; ++v)
    for (int k = 0; k < 3; ++k) src[3 * v + k] = points[v][k];
  std::vector<double> dst(src.size()), normals;
  if (options.normals) normals.resize(src.size());
  limit_points(level, src.data(), dst.data(), 3, options.normals ? normals.data() : nullptr,
               ctx);
  LimitResult result;
  result.positions.resize(level.nv);
  double sum = 0.0;
  for (std::uint32_t v = 0; v < level.nv; ++v) {
    result.positions[v] = Point(dst[3 * v], dst[3 * v + 1], dst[3 * v + 2]);
    const double d = (result.positions[v] - points[v]).norm();
    result.max_distance = std::max(result.max_distance, d);
    sum += d * d;
  }
  if (level.nv > 0) result.rms_distance = std::sqrt(sum / level.nv);
  if (options.normals) {
    result.normals.resize(level.nv);
    for (std::uint32_t v = 0; v < level.nv; ++v)
      result.normals[v] = Normal(normals[3 * v], normals[3 * v + 1], normals[3 * v + 2]);
  }
  return result;
}

}  // namespace geom
