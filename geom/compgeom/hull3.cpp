// Quickhull in 3D. A point joins the hull only when it is strictly above some face, so
// points on the hull's faces and edges never enter; points that were extreme when inserted
// but end up on a flat facet or edge of the final hull are caught by a local test and a
// second pass over the extreme points alone removes them.

#include <geom/compgeom/hull2.h>
#include <geom/compgeom/hull3.h>
#include <geom/core/errors.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace geom {

namespace {

constexpr std::uint32_t kNone = 0xFFFFFFFFu;

struct Face {
  std::array<std::uint32_t, 3> v;
  std::array<std::uint32_t, 3> nb;  // nb[i]: across edge (v[i], v[i+1])
  std::vector<std::uint32_t> outside;
  std::uint32_t far = kNone;
  double far_dist = 0;
  bool dead = false;
};

class Quickhull {
 public:
  Quickhull(const double* xyz, PredicateStats& st) : p_(xyz), st_(st) {}

  const double* p(std::uint32_t i) const { return p_ + 3 * std::size_t(i); }

  // > 0 when q is strictly above (outside) face f; the magnitude orders candidates.
  double height(const Face& f, std::uint32_t q, int& sign) {
    bool sure;
    ++st_.calls;
    double d = detail::orient3d_filter(p(f.v[0]), p(f.v[1]), p(f.v[2]), p(q), sure);
    if (sure) {
      sign = -detail::sign_of(d);
    } else {
      ++st_.exact;
      sign = -detail::orient3d_exact(p(f.v[0]), p(f.v[1]), p(f.v[2]), p(q));
    }
    return -d;
  }

  bool assign(std::uint32_t q, std::span<const std::uint32_t> candidates) {
    for (std::uint32_t fi : candidates) {
      Face& f = faces_[fi];
      int s;
      double h = height(f, q, s);
      if (s > 0) {
        f.outside.push_back(q);
        if (f.far == kNone || h > f.far_dist) f.far = q, f.far_dist = h;
        return true;
      }
    }
    return false;
  }

  std::uint32_t new_face(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    faces_.push_back({{a, b, c}, {kNone, kNone, kNone}, {}, kNone, 0, false});
    return static_cast<std::uint32_t>(faces_.size() - 1);
  }

  static int edge_of(const Face& f, std::uint32_t a) {
    return f.v[0] == a ? 0 : f.v[1] == a ? 1 : 2;
  }

  // Runs on the points `ids`; the first four form a positively oriented tetrahedron
  // (orient3d(t0, t1, t2, t3) > 0).
  std::vector<std::array<std::uint32_t, 3>> run(std::span<const std::uint32_t> ids,
                                                std::array<std::uint32_t, 4> t,
                                                std::size_t n_total) {
    faces_.clear();
    // (t0, t1, t2) has t3 below it, so it faces outward; the other three follow.
    std::uint32_t f0 = new_face(t[0], t[1], t[2]);
    std::uint32_t f1 = new_face(t[1], t[0], t[3]);
    std::uint32_t f2 = new_face(t[2], t[1], t[3]);
    std::uint32_t f3 = new_face(t[0], t[2], t[3]);
    link_all({f0, f1, f2, f3});
    std::array<std::uint32_t, 4> init = {f0, f1, f2, f3};
    for (std::uint32_t q : ids)
      if (q != t[0] && q != t[1] && q != t[2] && q != t[3]) assign(q, init);
    std::vector<std::uint32_t> stack = {f0, f1, f2, f3};
    std::vector<std::uint32_t> visible, newf, pts;
    struct Horizon {
      std::uint32_t a, b, out;
    };
    std::vector<Horizon> horizon;
    mark_.assign(faces_.size(), 0);
    start_of_.assign(n_total, kNone);
    std::uint32_t stamp = 0;
    while (!stack.empty()) {
      std::uint32_t fi = stack.back();
      stack.pop_back();
      if (faces_[fi].dead || faces_[fi].outside.empty()) continue;
      const std::uint32_t eye = faces_[fi].far;
      ++stamp;
      // Visible region: faces strictly below eye, grown from fi. Horizon edges are kept in
      // the orientation of their visible face.
      visible.clear();
      horizon.clear();
      visible.push_back(fi);
      mark_[fi] = 2 * stamp;
      for (std::size_t k = 0; k < visible.size(); ++k) {
        std::uint32_t g = visible[k];
        for (int e = 0; e < 3; ++e) {
          std::uint32_t h = faces_[g].nb[e];
          if (mark_[h] == 2 * stamp) continue;
          int s = 0;
          if (mark_[h] != 2 * stamp + 1) height(faces_[h], eye, s);
          if (s > 0) {
            mark_[h] = 2 * stamp;
            visible.push_back(h);
          } else {
            mark_[h] = 2 * stamp + 1;
            horizon.push_back({faces_[g].v[e], faces_[g].v[(e + 1) % 3], h});
          }
        }
      }
      newf.clear();
      for (const Horizon& e : horizon) {
        std::uint32_t nf = new_face(e.a, e.b, eye);
        mark_.push_back(0);
        Face& out = faces_[e.out];
        out.nb[edge_of(out, e.b)] = nf;  // the outside face has the edge as (b, a)
        faces_[nf].nb[0] = e.out;
        start_of_[e.a] = nf;
        newf.push_back(nf);
      }
      for (std::uint32_t nf : newf) {
        // nf = (a, b, eye): its edge (b, eye) is the edge (eye, b) of the face starting at b.
        std::uint32_t b = faces_[nf].v[1];
        std::uint32_t m = start_of_[b];
        faces_[nf].nb[1] = m;
        faces_[m].nb[2] = nf;
      }
      pts.clear();
      for (std::uint32_t g : visible) {
        Face& f = faces_[g];
        f.dead = true;
        for (std::uint32_t q : f.outside)
          if (q != eye) pts.push_back(q);
        std::vector<std::uint32_t>().swap(f.outside);
      }
      for (std::uint32_t q : pts) assign(q, newf);
      for (std::uint32_t nf : newf)
        if (!faces_[nf].outside.empty()) stack.push_back(nf);
    }
    std::vector<std::array<std::uint32_t, 3>> tris;
    for (const Face& f : faces_)
      if (!f.dead) tris.push_back(f.v);
    return tris;
  }

 private:
  void link_all(std::initializer_list<std::uint32_t> fs) {
    for (std::uint32_t a : fs)
      for (int i = 0; i < 3; ++i)
        for (std::uint32_t b : fs)
          for (int j = 0; j < 3; ++j)
            if (a != b && faces_[a].v[i] == faces_[b].v[(j + 1) % 3] &&
                faces_[a].v[(i + 1) % 3] == faces_[b].v[j])
              faces_[a].nb[i] = b;
  }

  const double* p_;
  PredicateStats& st_;
  std::vector<Face> faces_;
  std::vector<std::uint32_t> mark_, start_of_;
};

bool same3(const double* a, const double* b) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

// Exactly collinear: all three coordinate projections have zero orientation.
bool collinear3(const double* a, const double* b, const double* c) {
  double pa[3][2] = {{a[0], a[1]}, {a[1], a[2]}, {a[2], a[0]}};
  double pb[3][2] = {{b[0], b[1]}, {b[1], b[2]}, {b[2], b[0]}};
  double pc[3][2] = {{c[0], c[1]}, {c[1], c[2]}, {c[2], c[0]}};
  for (int k = 0; k < 3; ++k)
    if (orient2d(pa[k], pb[k], pc[k]) != 0) return false;
  return true;
}

// Strictly between a and c on their common line (b known collinear with them).
bool between3(const double* a, const double* b, const double* c) {
  for (int k = 0; k < 3; ++k)
    if (a[k] != c[k]) return (a[k] < b[k] && b[k] < c[k]) || (c[k] < b[k] && b[k] < a[k]);
  return false;
}

// Vertices of the triangulated hull surface that are not extreme points: the middle of a
// flat star, or strictly between two neighbours on a line.
std::vector<std::uint8_t> non_extreme(const double* xyz, std::size_t n,
                                      const std::vector<std::array<std::uint32_t, 3>>& tris) {
  auto P = [&](std::uint32_t i) { return xyz + 3 * std::size_t(i); };
  std::vector<std::uint32_t> off(n + 1, 0);
  for (const auto& t : tris)
    for (std::uint32_t v : t) ++off[v + 1];
  for (std::size_t i = 0; i < n; ++i) off[i + 1] += off[i];
  std::vector<std::uint32_t> inc(off[n]), fill(off.begin(), off.end() - 1);
  for (std::uint32_t f = 0; f < tris.size(); ++f)
    for (std::uint32_t v : tris[f]) inc[fill[v]++] = f;
  std::vector<std::uint8_t> bad(n, 0);
  std::vector<std::uint32_t> nbrs;
  for (std::uint32_t v = 0; v < n; ++v) {
    if (off[v] == off[v + 1]) continue;
    nbrs.clear();
    for (std::uint32_t k = off[v]; k < off[v + 1]; ++k)
      for (std::uint32_t w : tris[inc[k]])
        if (w != v) nbrs.push_back(w);
    std::sort(nbrs.begin(), nbrs.end());
    nbrs.erase(std::unique(nbrs.begin(), nbrs.end()), nbrs.end());
    const auto& f0 = tris[inc[off[v]]];
    bool flat = true;
    for (std::uint32_t w : nbrs)
      if (orient3d(P(f0[0]), P(f0[1]), P(f0[2]), P(w)) != 0) {
        flat = false;
        break;
      }
    bool on_line = false;
    for (std::size_t i = 0; i < nbrs.size() && !flat && !on_line; ++i)
      for (std::size_t j = i + 1; j < nbrs.size() && !on_line; ++j)
        on_line =
            collinear3(P(nbrs[i]), P(v), P(nbrs[j])) && between3(P(nbrs[i]), P(v), P(nbrs[j]));
    bad[v] = flat || on_line;
  }
  return bad;
}

}  // namespace

Hull3Result convex_hull_3d(std::span<const Eigen::Vector3d> given) {
  check_finite(given);
  std::vector<Eigen::Vector3d> scaled;
  const std::span<const Eigen::Vector3d> points = in_predicate_range(given, scaled);
  Hull3Result res;
  const std::size_t n = points.size();
  if (n == 0) return res;
  if (n >= kNone)
    throw InvalidArgument("convex_hull_3d: too many points (" + std::to_string(n) + ")");
  const double* xyz = points.data()->data();
  auto P = [&](std::uint32_t i) { return xyz + 3 * std::size_t(i); };
  // Initial simplex: the lexicographic minimum, the point farthest from it, the point
  // farthest from their line, the point farthest from their plane (distances only choose;
  // exact tests confirm).
  std::uint32_t i0 = 0;
  for (std::uint32_t i = 1; i < n; ++i)
    if (std::lexicographical_compare(P(i), P(i) + 3, P(i0), P(i0) + 3)) i0 = i;
  std::uint32_t i1 = kNone;
  double best = -1;
  for (std::uint32_t i = 0; i < n; ++i) {
    double d = (points[i] - points[i0]).squaredNorm();
    if (!same3(P(i), P(i0)) && d > best) best = d, i1 = i;
  }
  if (i1 == kNone) {
    res.dimension = 0;
    res.vertices = {i0};
    return res;
  }
  std::uint32_t i2 = kNone;
  best = -1;
  const Eigen::Vector3d d01 = points[i1] - points[i0];
  for (std::uint32_t i = 0; i < n; ++i) {
    double d = d01.cross(points[i] - points[i0]).squaredNorm();
    if (d > best && !collinear3(P(i0), P(i1), P(i))) best = d, i2 = i;
  }
  if (i2 == kNone) {
    res.dimension = 1;
    std::uint32_t lo = i0, hi = i0;
    for (std::uint32_t i = 0; i < n; ++i) {
      if (std::lexicographical_compare(P(i), P(i) + 3, P(lo), P(lo) + 3)) lo = i;
      if (std::lexicographical_compare(P(hi), P(hi) + 3, P(i), P(i) + 3)) hi = i;
    }
    res.vertices = {std::min(lo, hi), std::max(lo, hi)};
    // Keep the first copy of each endpoint.
    for (std::uint32_t& v : res.vertices)
      for (std::uint32_t i = 0; i < v; ++i)
        if (same3(P(i), P(v))) {
          v = i;
          break;
        }
    std::sort(res.vertices.begin(), res.vertices.end());
    return res;
  }
  std::uint32_t i3 = kNone;
  best = -1;
  const Eigen::Vector3d nrm = d01.cross(points[i2] - points[i0]);
  for (std::uint32_t i = 0; i < n; ++i) {
    double d = std::fabs(nrm.dot(points[i] - points[i0]));
    if (d > best && orient3d(P(i0), P(i1), P(i2), P(i), res.predicates) != 0) best = d, i3 = i;
  }
  if (i3 == kNone) {
    // Coplanar: the 2D hull in a coordinate projection that keeps the plane non-degenerate.
    res.dimension = 2;
    res.planar = true;
    int drop = 2;
    for (int k = 2; k >= 0; --k) {
      int x = (k + 1) % 3, y = (k + 2) % 3;
      double a[2] = {P(i0)[x], P(i0)[y]}, b[2] = {P(i1)[x], P(i1)[y]}, c[2] = {P(i2)[x], P(i2)[y]};
      if (orient2d(a, b, c) != 0) drop = k;
    }
    const int x = (drop + 1) % 3, y = (drop + 2) % 3;
    std::vector<Eigen::Vector2d> q(n);
    for (std::uint32_t i = 0; i < n; ++i) q[i] = {P(i)[x], P(i)[y]};
    Hull2Result h = convex_hull_2d(q);
    res.predicates += h.predicates;
    res.polygon = h.vertices;
    // (x, y, drop) is a right-handed frame, so counter-clockwise in the projection is
    // counter-clockwise seen from +drop.
    res.projection_axis = drop;
    res.vertices = res.polygon;
    std::sort(res.vertices.begin(), res.vertices.end());
    return res;
  }
  res.dimension = 3;
  Quickhull qh(xyz, res.predicates);
  std::vector<std::uint32_t> ids(n);
  for (std::uint32_t i = 0; i < n; ++i) ids[i] = i;
  auto tet = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
    std::array<std::uint32_t, 4> t = {a, b, c, d};
    if (orient3d(P(a), P(b), P(c), P(d)) < 0) std::swap(t[1], t[2]);
    return t;
  };
  auto tris = qh.run(ids, tet(i0, i1, i2, i3), n);
  std::vector<std::uint8_t> bad = non_extreme(xyz, n, tris);
  std::vector<std::uint32_t> keep;
  std::vector<std::uint8_t> is_vertex(n, 0);
  for (const auto& t : tris)
    for (std::uint32_t v : t) is_vertex[v] = 1;
  for (std::uint32_t i = 0; i < n; ++i)
    if (is_vertex[i] && !bad[i])
      keep.push_back(i);
    else if (is_vertex[i])
      ++res.non_extreme_removed;
  if (res.non_extreme_removed > 0) {
    // The extreme points span the same solid; any four non-coplanar ones start the pass.
    std::uint32_t a = keep[0], b = keep[1], c = kNone, d = kNone;
    for (std::uint32_t i : keep)
      if (!collinear3(P(a), P(b), P(i))) {
        c = i;
        break;
      }
    for (std::uint32_t i : keep)
      if (orient3d(P(a), P(b), P(c), P(i)) != 0) {
        d = i;
        break;
      }
    tris = qh.run(keep, tet(a, b, c, d), n);
  }
  // Report the first copy of each repeated extreme point.
  {
    struct H {
      const double* xyz;
      std::size_t operator()(std::uint32_t i) const {
        std::size_t h = 0;
        for (int k = 0; k < 3; ++k) h = h * 1000003u ^ std::hash<double>()(xyz[3 * i + k]);
        return h;
      }
    };
    struct Eq {
      const double* xyz;
      bool operator()(std::uint32_t a, std::uint32_t b) const {
        return same3(xyz + 3 * a, xyz + 3 * b);
      }
    };
    std::unordered_map<std::uint32_t, std::uint32_t, H, Eq> copy(16, H{xyz}, Eq{xyz});
    for (const auto& t : tris)
      for (std::uint32_t v : t) copy.emplace(v, v);
    for (std::uint32_t i = 0; i < n; ++i) {
      auto it = copy.find(i);
      if (it != copy.end() && i < it->second) it->second = i;
    }
    for (auto& t : tris)
      for (std::uint32_t& v : t) v = copy.find(v)->second;
  }
  res.triangles = std::move(tris);
  for (const auto& t : res.triangles)
    for (std::uint32_t v : t) res.vertices.push_back(v);
  std::sort(res.vertices.begin(), res.vertices.end());
  res.vertices.erase(std::unique(res.vertices.begin(), res.vertices.end()), res.vertices.end());
  return res;
}

SurfaceMesh hull_mesh(std::span<const Eigen::Vector3d> points, const Hull3Result& hull) {
  SurfaceMesh mesh;
  if (hull.dimension < 3) return mesh;
  std::unordered_map<std::uint32_t, Vertex> map;
  for (std::uint32_t v : hull.vertices) map[v] = mesh.add_vertex(points[v]);
  for (const auto& t : hull.triangles) mesh.add_triangle(map[t[0]], map[t[1]], map[t[2]]);
  return mesh;
}

}  // namespace geom
