// Constrained Delaunay triangulation: segments are forced into the Delaunay triangulation by
// flipping the edges they cross (Sloan), then Lawson flips restore the constrained Delaunay
// property. Segments that pass exactly through vertices are split there.

#include <geom/compgeom/hull2.h>
#include <geom/compgeom/triangulation2.h>
#include <geom/core/errors.h>

#include <algorithm>
#include <deque>
#include <string>
#include <unordered_map>

namespace geom {

namespace {

using detail::kInfinite;
using detail::Triangulation2;

std::uint64_t key(std::uint32_t a, std::uint32_t b) {
  if (a > b) std::swap(a, b);
  return (std::uint64_t(a) << 32) | b;
}

std::string seg_name(std::size_t i, const Segment& s) {
  return "segment " + std::to_string(i) + " (" + std::to_string(s.a) + ", " + std::to_string(s.b) +
         ")";
}

class Constrainer {
 public:
  Constrainer(Triangulation2& tr, std::span<const Segment> segs) : tr_(tr), segs_(segs) {
    vtri_.assign(tr.n_points, detail::kNoTriangle);
    for (std::uint32_t t = 0; t < tr.v.size(); ++t)
      if (!tr.dead[t])
        for (std::uint32_t x : tr.v[t])
          if (x != kInfinite) vtri_[x] = t;
  }

  int orient(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    return orient2d(tr_.p(a), tr_.p(b), tr_.p(c), tr_.stats);
  }

  // Strictly between a and b, given collinear.
  bool between(std::uint32_t a, std::uint32_t b, std::uint32_t c) const {
    int k = tr_.p(a)[0] != tr_.p(b)[0] ? 0 : 1;
    double pa = tr_.p(a)[k], pb = tr_.p(b)[k], pc = tr_.p(c)[k];
    return (pa < pc && pc < pb) || (pb < pc && pc < pa);
  }

  // Triangle holding the directed edge x -> y, or kNoTriangle.
  std::uint32_t find_edge(std::uint32_t x, std::uint32_t y, int& i_out) const {
    std::uint32_t t0 = vtri_[x], t = t0;
    do {
      int i = tr_.index_of(t, x);
      if (tr_.v[t][(i + 1) % 3] == y) {
        i_out = i;  // edge (x, y) is opposite v[t][(i + 2) % 3]
        return t;
      }
      t = tr_.nb[t][(i + 1) % 3];  // next triangle counter-clockwise around x
    } while (t != t0);
    return detail::kNoTriangle;
  }

  void do_flip(std::uint32_t t, int i) {
    std::uint32_t u = tr_.nb[t][i];
    detail::flip(tr_, t, i);
    for (std::uint32_t x : tr_.v[t])
      if (x != kInfinite) vtri_[x] = t;
    for (std::uint32_t x : tr_.v[u])
      if (x != kInfinite) vtri_[x] = u;
  }

  void insert(std::size_t si, std::uint32_t a, std::uint32_t b, ConstrainedDelaunayResult& res) {
    bool split = false;
    while (a != b) {
      std::uint32_t stop = b;  // end of the piece handled in this round
      int unused;
      if (find_edge(a, b, unused) == detail::kNoTriangle) {
        // Around a: a neighbour on the segment, or the triangle the segment leaves a through.
        std::uint32_t t0 = vtri_[a], t = t0, first = detail::kNoTriangle;
        do {
          int i = tr_.index_of(t, a);
          std::uint32_t x = tr_.v[t][(i + 1) % 3], y = tr_.v[t][(i + 2) % 3];
          if (x != kInfinite && orient(a, b, x) == 0 && between(a, b, x)) {
            stop = x;
            first = detail::kNoTriangle;
            break;
          }
          if (x != kInfinite && y != kInfinite && orient(a, x, b) > 0 && orient(a, y, b) < 0)
            first = t;
          t = tr_.nb[t][(i + 1) % 3];
        } while (t != t0);
        if (stop == b) {
          if (first == detail::kNoTriangle)
            throw Error("constrained_delaunay_2d: " + seg_name(si, segs_[si]) +
                        " leaves the triangulation");
          stop = force(si, a, b, first);
        }
      }
      if (stop != b) split = true;
      std::uint64_t k = key(a, stop);
      auto it = owner_.find(k);
      if (it == owner_.end()) {
        owner_.emplace(k, si);
        res.constrained_edges.push_back({a, stop});
      }
      a = stop;
    }
    if (split) ++res.split_segments;
  }

  // Makes the piece of segment si from a towards b an edge, starting in triangle t (the
  // segment leaves a through t). Returns the piece's end: b, or the first vertex on the
  // segment.
  std::uint32_t force(std::size_t si, std::uint32_t a, std::uint32_t b, std::uint32_t t) {
    std::deque<std::pair<std::uint32_t, std::uint32_t>> crossing;
    const int i = tr_.index_of(t, a);
    std::uint32_t right = tr_.v[t][(i + 1) % 3], left = tr_.v[t][(i + 2) % 3];
    std::uint32_t end = b;
    for (;;) {
      check_free(si, right, left);
      crossing.push_back({right, left});
      // The neighbour across (right, left) is opposite the vertex that is neither.
      int opp = 0;
      while (tr_.v[t][opp] == right || tr_.v[t][opp] == left) ++opp;
      std::uint32_t u = tr_.nb[t][opp];
      int j = tr_.back_index(u, t);
      std::uint32_t z = tr_.v[u][j];
      if (z == b) break;
      if (z == kInfinite)
        throw Error("constrained_delaunay_2d: " + seg_name(si, segs_[si]) + " leaves the hull");
      int o = orient(a, b, z);
      if (o == 0) {
        end = z;
        break;
      }
      if (o < 0)
        right = z;
      else
        left = z;
      t = u;
    }
    // Sloan: flip crossing edges whose quadrilateral is convex until none crosses.
    std::vector<std::pair<std::uint32_t, std::uint32_t>> created;
    std::size_t guard = 0;
    while (!crossing.empty()) {
      auto [x, y] = crossing.front();
      crossing.pop_front();
      int k = 0;
      std::uint32_t tt = find_edge(x, y, k);
      if (tt == detail::kNoTriangle)
        throw Error("constrained_delaunay_2d: lost a crossing edge while forcing " +
                    seg_name(si, segs_[si]));
      int e = (k + 2) % 3;  // edge (x, y) is opposite v[tt][e]
      std::uint32_t c = tr_.v[tt][e];
      std::uint32_t u = tr_.nb[tt][e];
      std::uint32_t d = tr_.v[u][tr_.back_index(u, tt)];
      int o1 = orient(c, d, x), o2 = orient(c, d, y);
      bool convex = (o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0);
      if (!convex) {
        crossing.push_back({x, y});
        if (++guard > 64 * (crossing.size() + 16) * (crossing.size() + 16))
          throw Error("constrained_delaunay_2d: could not force " + seg_name(si, segs_[si]));
        continue;
      }
      do_flip(tt, e);
      // The new edge joins c and d.
      int oc = orient(a, end, c), od = orient(a, end, d);
      bool crosses = (oc > 0 && od < 0) || (oc < 0 && od > 0);
      if (crosses && !(c == a || d == a || c == end || d == end))
        crossing.push_back({c, d});
      else
        created.push_back({c, d});
    }
    // Lawson flips from the created edges restore the constrained Delaunay property.
    owner_.emplace(key(a, end), si);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> stack(created.begin(), created.end());
    while (!stack.empty()) {
      auto [x, y] = stack.back();
      stack.pop_back();
      if (owner_.count(key(x, y))) continue;
      int k = 0;
      std::uint32_t tt = find_edge(x, y, k);
      if (tt == detail::kNoTriangle) continue;
      int e = (k + 2) % 3;
      std::uint32_t u = tr_.nb[tt][e];
      if (tr_.infinite(tt) || tr_.infinite(u)) continue;
      std::uint32_t d = tr_.v[u][tr_.back_index(u, tt)];
      const auto& v = tr_.v[tt];
      int s = incircle(tr_.p(v[0]), tr_.p(v[1]), tr_.p(v[2]), tr_.p(d), tr_.stats);
      if (s == 0)
        s = detail::incircle_perturbed(tr_.p(v[0]), tr_.p(v[1]), tr_.p(v[2]), tr_.p(d),
                                       tr_.sos_index(v[0]), tr_.sos_index(v[1]),
                                       tr_.sos_index(v[2]), tr_.sos_index(d));
      if (s <= 0) continue;
      std::uint32_t c = v[e];
      do_flip(tt, e);
      stack.push_back({c, x});
      stack.push_back({x, d});
      stack.push_back({d, y});
      stack.push_back({y, c});
    }
    owner_.erase(key(a, end));
    return end;
  }

  void check_free(std::size_t si, std::uint32_t x, std::uint32_t y) {
    auto it = owner_.find(key(x, y));
    if (it != owner_.end())
      throw InvalidArgument("constrained_delaunay_2d: " + seg_name(si, segs_[si]) + " crosses " +
                            seg_name(it->second, segs_[it->second]));
  }

 private:
  Triangulation2& tr_;
  std::span<const Segment> segs_;
  std::vector<std::uint32_t> vtri_;
  std::unordered_map<std::uint64_t, std::size_t> owner_;  // constrained edge -> segment
};

}  // namespace

ConstrainedDelaunayResult constrained_delaunay_2d(std::span<const Eigen::Vector2d> given,
                                                  std::span<const Segment> segments,
                                                  const DelaunayOptions& options) {
  check_finite(given);
  std::vector<Eigen::Vector2d> scaled;
  const std::span<const Eigen::Vector2d> points = in_predicate_range(given, scaled);
  const std::size_t n = points.size();
  for (std::size_t i = 0; i < segments.size(); ++i)
    if (segments[i].a >= n || segments[i].b >= n)
      throw InvalidArgument("constrained_delaunay_2d: " + seg_name(i, segments[i]) +
                            " references a point index >= " + std::to_string(n));
  ConstrainedDelaunayResult res;
  if (n == 0) {
    res.collinear = true;
    return res;
  }
  detail::Triangulation2 tr;
  detail::build_delaunay(tr, points.data()->data(), n, options.exact);
  for (std::size_t i = 0; i < segments.size(); ++i)
    if (tr.vertex_of[segments[i].a] == tr.vertex_of[segments[i].b])
      throw InvalidArgument("constrained_delaunay_2d: " + seg_name(i, segments[i]) +
                            " has coincident endpoints");
  if (tr.collinear) {
    // Every segment lies on the line: its constrained edges are the chain edges it covers.
    std::vector<std::uint32_t> pos(n);
    for (std::uint32_t k = 0; k < tr.chain.size(); ++k) pos[tr.chain[k]] = k;
    std::vector<std::uint8_t> used(tr.chain.size(), 0);
    for (const Segment& s : segments) {
      std::uint32_t p = pos[tr.vertex_of[s.a]], q = pos[tr.vertex_of[s.b]];
      if (p > q) std::swap(p, q);
      if (q - p > 1) ++res.split_segments;
      for (std::uint32_t k = p; k < q; ++k) used[k] = 1;
    }
    for (std::uint32_t k = 0; k + 1 < tr.chain.size(); ++k)
      if (used[k]) res.constrained_edges.push_back({tr.chain[k], tr.chain[k + 1]});
  } else {
    Constrainer c(tr, segments);
    for (std::size_t i = 0; i < segments.size(); ++i)
      c.insert(i, tr.vertex_of[segments[i].a], tr.vertex_of[segments[i].b], res);
  }
  res.triangles = tr.finite_triangles();
  res.vertex_of = tr.vertex_of;
  res.collinear = tr.collinear;
  res.chain = tr.chain;
  res.cocircular = tr.cocircular;
  res.predicates = tr.stats;
  for (std::uint32_t i = 0; i < n; ++i) res.duplicates += res.vertex_of[i] != i;
  res.vertices = n - res.duplicates;
  return res;
}

}  // namespace geom
