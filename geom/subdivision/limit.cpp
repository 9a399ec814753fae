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

/// Read access to a level's connectivity, from a Level or from a SurfaceMesh.
struct LevelTopo {
  const Level& l;
  std::uint32_t to(std::uint32_t h) const { return l.to[h]; }
  std::uint32_t next(std::uint32_t h) const { return l.next[h]; }
  std::uint32_t face(std::uint32_t h) const { return l.face[h]; }
  std::uint32_t vh(std::uint32_t v) const { return l.vh[v]; }
  std::uint32_t cw(std::uint32_t h) const { return l.next[h ^ 1u]; }
};
struct MeshTopo {
  const SurfaceMesh& m;
  std::uint32_t to(std::uint32_t h) const { return m.to_vertex(Halfedge(h)).idx(); }
  std::uint32_t next(std::uint32_t h) const { return m.next(Halfedge(h)).idx(); }
  std::uint32_t face(std::uint32_t h) const { return m.face(Halfedge(h)).idx(); }
  std::uint32_t vh(std::uint32_t v) const { return m.halfedge(Vertex(v)).idx(); }
  std::uint32_t cw(std::uint32_t h) const { return next(h ^ 1u); }
};

/// `l` supplies the vertex count and sharpness, `t` the connectivity.
template <int W, class Topo>
void limit_impl(const Level& l, const Topo& t, const double* src, double* dst, int w,
                const Context& ctx) {
  const int nw = W ? W : w;
  const bool sharp = l.has_sharpness();
  for_range(l.nv, ctx.parallel, [&](std::uint32_t b, std::uint32_t end) {
    std::vector<double> esum(static_cast<std::size_t>(nw)), fsum(static_cast<std::size_t>(nw));
    for (std::uint32_t v = b; v < end; ++v) {
      const double* pv = src + static_cast<std::size_t>(v) * nw;
      double* out = dst + static_cast<std::size_t>(v) * nw;
      const std::uint32_t h0 = t.vh(v);
      if (h0 == kNone) {
        Row<W>::set(out, pv, 1.0, w);
        continue;
      }
      int sharp_edges = 0, n_edges = 0, n_faces = 0;
      std::uint32_t ends[2] = {0, 0};
      Row<W>::zero(esum.data(), w);
      Row<W>::zero(fsum.data(), w);
      std::uint32_t h = h0;
      do {
        ++n_edges;
        if (sharp && is_sharp(l.esharp[h >> 1])) ends[sharp_edges++ & 1] = t.to(h);
        Row<W>::add(esum.data(), src + static_cast<std::size_t>(t.to(h)) * nw, 1.0, w);
        if (t.face(h) != kNone) {
          ++n_faces;
          if (ctx.catmark)
            Row<W>::add(fsum.data(), src + static_cast<std::size_t>(t.to(t.next(h))) * nw, 1.0,
                        w);
        }
        h = t.cw(h);
      } while (h != h0);
      const Rule rule = vertex_rule(sharp ? l.vsharp[v] : kSmooth, sharp_edges);
      if (rule == kRuleCorner || ((rule == kRuleSmooth || rule == kRuleDart) && ctx.catmark &&
                                  n_faces == 2)) {
        Row<W>::set(out, pv, 1.0, w);
      } else if (rule == kRuleCrease) {
        const double* a = src + static_cast<std::size_t>(ends[0]) * nw;
        const double* c = src + static_cast<std::size_t>(ends[1]) * nw;
        for (int k = 0; k < nw; ++k)
          out[k] = (1.0 / 6.0) * a[k] + (1.0 / 6.0) * c[k] + (2.0 / 3.0) * pv[k];
      } else if (ctx.catmark) {
        const double n = n_faces;
        double fw = 1.0 / 36.0, ew = 1.0 / 9.0, vw = 4.0 / 9.0;
        if (n_faces != 4) {
          fw = 1.0 / (n * (n + 5.0));
          ew = 4.0 * fw;
          vw = 1.0 - n * (ew + fw);
        }
        for (int k = 0; k < nw; ++k) out[k] = fw * fsum[k] + ew * esum[k] + vw * pv[k];
      } else {
        const double n = n_faces;
        double ew = 1.0 / 12.0, vw = 0.5;
        if (n_faces != 6) {
          const double inv = 1.0 / n;
          const double cos_theta = std::cos(M_PI * 2.0 * inv);
          const double beta = 0.25 * cos_theta + 0.375;
          const double gamma = (0.625 - beta * beta) * inv;
          ew = 1.0 / (n + 3.0 / (8.0 * gamma));
          vw = 1.0 - ew * n;
        }
        for (int k = 0; k < nw; ++k) out[k] = ew * esum[k] + vw * pv[k];
      }
    }
  });
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
  const LevelTopo t{l};
  if (w == 3)
    limit_impl<3>(l, t, src, dst, w, ctx);
  else
    limit_impl<0>(l, t, src, dst, w, ctx);
  if (normals) limit_normals(l, src, dst, w, normals, ctx);
}

void limit_points(const SurfaceMesh& mesh, const Level& sharpness, const double* src,
                  double* dst, int w, const Context& ctx) {
  const MeshTopo t{mesh};
  if (w == 3)
    limit_impl<3>(sharpness, t, src, dst, w, ctx);
  else
    limit_impl<0>(sharpness, t, src, dst, w, ctx);
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
