#include <geom/isosurface/mc_tables.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace geom::detail {

namespace {

Eigen::Vector3d corner_position(int c) {
  return Eigen::Vector3d(c & 1, (c >> 1) & 1, (c >> 2) & 1);
}

int edge_of(int a, int b) {
  if (a > b) std::swap(a, b);
  for (int e = 0; e < 12; ++e)
    if (kEdgeCorners[e][0] == a && kEdgeCorners[e][1] == b) return e;
  return -1;
}

struct FaceDef {
  std::array<int, 4> corners;  ///< counter-clockwise seen from outside the cube
  std::array<int, 4> edges;    ///< edges[k] joins corners[k] and corners[k + 1]
};

/// The six faces, each ordered counter-clockwise about its outward normal. Computed rather
/// than written out so the orientation cannot be mistyped.
std::array<FaceDef, 6> make_faces() {
  std::array<FaceDef, 6> faces{};
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      FaceDef& f = faces[2 * axis + side];
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      normal[axis] = side ? 1.0 : -1.0;
      std::vector<int> cs;
      for (int c = 0; c < 8; ++c)
        if (((c >> axis) & 1) == side) cs.push_back(c);
      Eigen::Vector3d center = Eigen::Vector3d::Zero();
      for (int c : cs) center += corner_position(c) / 4.0;
      // Sort by angle in the face plane, measured with a right-handed frame about normal.
      Eigen::Vector3d u = Eigen::Vector3d::Zero();
      u[(axis + 1) % 3] = 1.0;
      Eigen::Vector3d v = normal.cross(u);
      std::sort(cs.begin(), cs.end(), [&](int a, int b) {
        Eigen::Vector3d pa = corner_position(a) - center, pb = corner_position(b) - center;
        return std::atan2(pa.dot(v), pa.dot(u)) < std::atan2(pb.dot(v), pb.dot(u));
      });
      for (int k = 0; k < 4; ++k) {
        f.corners[k] = cs[k];
        f.edges[k] = edge_of(cs[k], cs[(k + 1) % 4]);
      }
    }
  return faces;
}

struct Crossing {
  int edge;
  bool up;  ///< below → above when walking the face counter-clockwise
};

/// Triangles (edge/centroid refs) for one case and one set of decisions, in loop order,
/// and the loops they were made from.
struct Triangulation {
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::uint16_t> centroids;
  std::uint8_t centroid_inward = 0;  ///< as McEntry::centroid_inward
  std::vector<std::vector<int>> loops;
  std::array<std::array<bool, 12>, 12> forbidden{};
};

/// A fan over the loop from an apex whose diagonals are all allowed, else from a centroid.
void fan(const std::vector<int>& loop, const std::array<std::array<bool, 12>, 12>& forbidden,
         Triangulation& out) {
  const int n = static_cast<int>(loop.size());
  int apex = -1;
  for (int a = 0; a < n && apex < 0; ++a) {
    bool ok = true;
    for (int j = 0; j < n && ok; ++j) {
      int gap = (j - a + n) % n;
      if (gap <= 1 || gap == n - 1) continue;
      if (forbidden[loop[a]][loop[j]]) ok = false;
    }
    if (ok) apex = a;
  }
  if (apex >= 0) {
    for (int k = 1; k + 1 < n; ++k)
      out.triangles.push_back({loop[apex], loop[(apex + k) % n], loop[(apex + k + 1) % n]});
    return;
  }
  std::uint16_t mask = 0;
  for (int e : loop) mask |= std::uint16_t(1u << e);
  int centre = 12 + static_cast<int>(out.centroids.size());
  out.centroids.push_back(mask);
  for (int k = 0; k < n; ++k) out.triangles.push_back({centre, loop[k], loop[(k + 1) % n]});
}

Triangulation triangulate(int case_index, const std::array<FaceDef, 6>& faces,
                          const std::array<int, 6>& face_decision) {
  auto above = [&](int c) { return ((case_index >> c) & 1) != 0; };
  std::array<int, 12> next;
  next.fill(-1);
  // Pairs of edges on a common four-crossing face: a fan diagonal between them could be
  // picked by the neighbouring cube too.
  Triangulation out;
  auto& forbidden = out.forbidden;
  for (int fi = 0; fi < 6; ++fi) {
    const FaceDef& f = faces[fi];
    std::vector<Crossing> xs;
    for (int k = 0; k < 4; ++k) {
      bool a0 = above(f.corners[k]), a1 = above(f.corners[(k + 1) % 4]);
      if (a0 != a1) xs.push_back({f.edges[k], a1});
    }
    if (xs.size() == 2) {
      const Crossing& u = xs[0].up ? xs[0] : xs[1];
      const Crossing& d = xs[0].up ? xs[1] : xs[0];
      next[u.edge] = d.edge;
    } else if (xs.size() == 4) {
      bool joined = face_decision[fi] != 0;
      for (int k = 0; k < 4; ++k) {
        if (!xs[k].up) continue;
        // Separated above corners: each up crossing pairs with the down crossing that
        // follows it (cutting off one above corner); joined: with the one before it.
        int partner = joined ? (k + 3) % 4 : (k + 1) % 4;
        next[xs[k].edge] = xs[partner].edge;
      }
      for (const Crossing& a : xs)
        for (const Crossing& b : xs)
          if (a.edge != b.edge) forbidden[a.edge][b.edge] = true;
    }
  }
  std::array<bool, 12> seen{};
  for (int start = 0; start < 12; ++start) {
    if (next[start] < 0 || seen[start]) continue;
    std::vector<int> loop;
    for (int e = start; !seen[e]; e = next[e]) {
      seen[e] = true;
      loop.push_back(e);
    }
    fan(loop, forbidden, out);
    out.loops.push_back(std::move(loop));
  }
  return out;
}

/// Patch id (a representative corner) of each corner on the cube's surface: corners of one
/// kind joined along cube edges, and across a four-crossing face along the diagonal its
/// decision joins.
std::array<int, 8> corner_patches(int ci, const std::array<FaceDef, 6>& faces,
                                  const std::array<int, 6>& decision) {
  std::array<int, 8> parent{0, 1, 2, 3, 4, 5, 6, 7};
  auto find = [&](int c) {
    while (parent[c] != c) c = parent[c];
    return c;
  };
  auto unite = [&](int a, int b) { parent[find(a)] = find(b); };
  auto above = [&](int c) { return ((ci >> c) & 1) != 0; };
  for (const auto& e : kEdgeCorners)
    if (above(e[0]) == above(e[1])) unite(e[0], e[1]);
  for (int fi = 0; fi < 6; ++fi) {
    const auto& c = faces[fi].corners;
    int changes = 0;
    for (int k = 0; k < 4; ++k) changes += above(c[k]) != above(c[(k + 1) % 4]);
    if (changes != 4) continue;
    const bool d0_above = above(c[0]);
    const bool join_d0 = (decision[fi] != 0) == d0_above;  // joined: the above diagonal
    if (join_d0)
      unite(c[0], c[2]);
    else
      unite(c[1], c[3]);
  }
  std::array<int, 8> patch{};
  for (int c = 0; c < 8; ++c) patch[c] = find(c);
  return patch;
}

/// A tube joining loops a and b: a is walked forward and b backward, so every loop edge
/// keeps the direction it has in the fan it replaces. Rungs (a_i, b_j) avoid the forbidden
/// diagonals; among the valid ladders the one with the shortest rungs (edge midpoints as
/// stand-ins for the vertices) wins. False when no ladder avoids them.
/// A ladder that makes all its a-steps at one rung is a fan (a disc), not a tube, and
/// repeats its first rung; starting with an a-step and ending with a b-step, and never
/// reaching the first rung's copies (m, 0) and (i < m, n), rules those out and still
/// reaches every tube from some starting rung.
/// Stand-in position of a vertex reference: an edge's midpoint, or the centroid of the
/// midpoints of a centroid vertex's edges.
Eigen::Vector3d ref_position(int ref, const std::vector<std::uint16_t>& centroids,
                             std::uint8_t inward = 0) {
  auto mid = [](int e) -> Eigen::Vector3d {
    return 0.5 * (corner_position(kEdgeCorners[e][0]) + corner_position(kEdgeCorners[e][1]));
  };
  if (ref < 12) return mid(ref);
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  int count = 0;
  for (int e = 0; e < 12; ++e)
    if ((centroids[ref - 12] >> e) & 1) p += mid(e), ++count;
  p /= count;
  return (inward >> (ref - 12)) & 1 ? Eigen::Vector3d(0.5 * (p + Eigen::Vector3d::Constant(0.5))) : p;
}

bool tube(const std::vector<int>& a, const std::vector<int>& b,
          const std::array<std::array<bool, 12>, 12>& forbidden,
          const std::vector<std::uint16_t>& centroids, std::uint8_t inward,
          std::vector<std::array<int, 3>>& triangles) {
  const int m = static_cast<int>(a.size()), n = static_cast<int>(b.size());
  auto mid = [&](int e) { return ref_position(e, centroids, inward); };
  const double inf = std::numeric_limits<double>::infinity();
  double best = inf;
  std::vector<std::array<int, 3>> best_tris;
  for (int start = 0; start < m * n; ++start) {
    const int sa = start / n, sb = start % n;
    auto ai = [&](int i) { return (sa + i) % m; };
    auto bj = [&](int s) { return ((sb - s) % n + n) % n; };
    auto rung = [&](int i, int s) -> double {
      if ((i == 0 && s > 0) || (i == m && s == 0) || (s == n && i < m)) return inf;
      int ea = a[ai(i)], eb = b[bj(s)];
      // Centroid vertices are inside the cube: no neighbour can share an edge to them.
      if (ea < 12 && eb < 12 && forbidden[ea][eb]) return inf;
      return (mid(ea) - mid(eb)).norm();
    };
    // cost[i][s]: cheapest ladder reaching rung (a_i, b_{start-s}).
    std::vector<std::vector<double>> cost(m + 1, std::vector<double>(n + 1, inf));
    cost[0][0] = rung(0, 0);
    for (int i = 0; i <= m; ++i)
      for (int s = 0; s <= n; ++s) {
        if (i == 0 && s == 0) continue;
        double r = rung(i, s);
        double prev = std::min(i > 0 ? cost[i - 1][s] : inf, s > 0 ? cost[i][s - 1] : inf);
        cost[i][s] = prev + r;
      }
    if (!(cost[m][n] < best)) continue;
    best = cost[m][n];
    best_tris.clear();
    for (int i = m, s = n; i > 0 || s > 0;) {
      const double r = rung(i, s);
      if (i > 0 && cost[i - 1][s] + r == cost[i][s]) {
        --i;
        best_tris.push_back({a[ai(i)], a[ai(i + 1)], b[bj(s)]});
      } else {
        --s;
        best_tris.push_back({b[bj(s + 1)], b[bj(s)], a[ai(i)]});
      }
    }
  }
  if (best == inf) return false;
  triangles.insert(triangles.end(), best_tris.begin(), best_tris.end());
  return true;
}

/// A tube whose every direct ladder would use a diagonal a neighbour may also pick (case
/// 13's loops lie on six ambiguous faces): two ladders through a ring of three centroid
/// vertices in the cube's interior, each the centroid of a third of one loop and the facing
/// third of the other. The ring is walked forward by the first ladder and backward by the
/// second, so its edges cancel.
bool ring_tube(const std::vector<int>& a, const std::vector<int>& b,
               const std::array<std::array<bool, 12>, 12>& forbidden, Triangulation& alt) {
  if (alt.centroids.size() + 3 > 4) return false;
  auto arc_mask = [](const std::vector<int>& loop, int k, int shift) {
    const int n = static_cast<int>(loop.size());
    std::uint16_t mask = 0;
    for (int i = k * n / 3; i < (k + 1) * n / 3; ++i) mask |= std::uint16_t(1u << loop[(i + shift) % n]);
    return mask;
  };
  auto centre = [](std::uint16_t mask) { return ref_position(12, {mask}); };
  // b runs against a through the tube, so a's k-th third faces one of b's thirds in reverse
  // order; pick the rotation whose thirds are nearest.
  double best = std::numeric_limits<double>::infinity();
  int best_r = 0;
  for (int r = 0; r < 3; ++r) {
    double d = 0;
    for (int k = 0; k < 3; ++k)
      d += (centre(arc_mask(a, k, 0)) - centre(arc_mask(b, (r - k + 3) % 3, 0))).norm();
    if (d < best) best = d, best_r = r;
  }
  std::vector<int> ring;
  for (int k = 0; k < 3; ++k) {
    alt.centroid_inward |= std::uint8_t(1u << alt.centroids.size());
    ring.push_back(12 + static_cast<int>(alt.centroids.size()));
    alt.centroids.push_back(arc_mask(a, k, 0) | arc_mask(b, (best_r - k + 3) % 3, 0));
  }
  std::vector<int> reversed(ring.rbegin(), ring.rend());
  std::vector<std::array<int, 3>> tris;
  if (!tube(a, ring, forbidden, alt.centroids, alt.centroid_inward, tris) ||
      !tube(b, reversed, forbidden, alt.centroids, alt.centroid_inward, tris)) {
    alt.centroids.resize(alt.centroids.size() - 3);
    alt.centroid_inward = 0;
    return false;
  }
  alt.triangles.insert(alt.triangles.end(), tris.begin(), tris.end());
  return true;
}

/// The tunnels an entry may take: pairs of loops that bound different patches of one kind
/// and the same patch of the other, each with the triangulation that joins them by a tube.
std::vector<std::pair<McTunnel, Triangulation>> tunnels_of(int ci, const std::array<FaceDef, 6>& faces,
                                                           const std::array<int, 6>& decision,
                                                           const Triangulation& t) {
  std::vector<std::pair<McTunnel, Triangulation>> out;
  const std::array<int, 8> patch = corner_patches(ci, faces, decision);
  const std::size_t n = t.loops.size();
  std::vector<int> up(n), down(n);
  for (std::size_t l = 0; l < n; ++l) {
    const auto& c = kEdgeCorners[t.loops[l][0]];
    const bool c0_above = ((ci >> c[0]) & 1) != 0;
    up[l] = patch[c0_above ? c[0] : c[1]];
    down[l] = patch[c0_above ? c[1] : c[0]];
  }
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j) {
      const bool above = down[i] == down[j] && up[i] != up[j];
      const bool below = up[i] == up[j] && down[i] != down[j];
      if (!above && !below) continue;
      Triangulation alt;
      alt.forbidden = t.forbidden;
      for (std::size_t l = 0; l < n; ++l)
        if (l != i && l != j) fan(t.loops[l], t.forbidden, alt);
      if (!tube(t.loops[i], t.loops[j], t.forbidden, alt.centroids, 0, alt.triangles) &&
          !ring_tube(t.loops[i], t.loops[j], t.forbidden, alt))
        continue;
      McTunnel tn;
      tn.above = above;
      tn.corner0 = std::uint8_t(above ? up[i] : down[i]);
      tn.corner1 = std::uint8_t(above ? up[j] : down[j]);
      out.push_back({tn, std::move(alt)});
    }
  return out;
}

McEntry make_entry(McTables& tables, const Triangulation& t, bool flip) {
  McEntry entry;
  entry.first_ref = static_cast<std::uint32_t>(tables.refs.size());
  entry.n_triangles = static_cast<std::uint8_t>(t.triangles.size());
  entry.n_centroids = static_cast<std::uint8_t>(t.centroids.size());
  for (std::size_t j = 0; j < t.centroids.size(); ++j) entry.centroid_mask[j] = t.centroids[j];
  entry.centroid_inward = t.centroid_inward;
  for (const auto& tri : t.triangles) {
    tables.refs.push_back(std::uint8_t(tri[0]));
    tables.refs.push_back(std::uint8_t(flip ? tri[2] : tri[1]));
    tables.refs.push_back(std::uint8_t(flip ? tri[1] : tri[2]));
  }
  return entry;
}

McTables make_tables() {
  const std::array<FaceDef, 6> faces = make_faces();

  // Orientation: the loops above face a fixed way; make triangles wind counter-clockwise
  // seen from the above side (normal toward increasing values) by checking case 1, where
  // only corner 0 is above.
  bool flip = false;
  {
    Triangulation t = triangulate(1, faces, {});
    auto mid = [](int e) -> Eigen::Vector3d {
      return 0.5 * (corner_position(kEdgeCorners[e][0]) + corner_position(kEdgeCorners[e][1]));
    };
    const auto& tri = t.triangles.at(0);
    Eigen::Vector3d n = (mid(tri[1]) - mid(tri[0])).cross(mid(tri[2]) - mid(tri[0]));
    flip = n.dot(Eigen::Vector3d(-1, -1, -1)) < 0;
  }

  McTables tables;
  struct Pending {
    std::size_t owner;
    int slot;
    Triangulation triangulation;
  };
  std::vector<Pending> pending;
  for (int ci = 0; ci < 256; ++ci) {
    McCase& mc = tables.cases[ci];
    auto above = [&](int c) { return ((ci >> c) & 1) != 0; };
    for (int e = 0; e < 12; ++e)
      if (above(kEdgeCorners[e][0]) != above(kEdgeCorners[e][1])) mc.edge_mask |= 1u << e;
    std::array<int, 6> ambiguous_face_ids{};
    for (int fi = 0; fi < 6; ++fi) {
      const FaceDef& f = faces[fi];
      int changes = 0;
      for (int k = 0; k < 4; ++k)
        changes += above(f.corners[k]) != above(f.corners[(k + 1) % 4]);
      if (changes != 4) continue;
      McAmbiguousFace af{};
      // Corners alternate, so corners[0], corners[2] are one diagonal.
      int d0a = f.corners[0], d0b = f.corners[2], d1a = f.corners[1], d1b = f.corners[3];
      if (above(d0a)) {
        af = {std::uint8_t(d0a), std::uint8_t(d0b), std::uint8_t(d1a), std::uint8_t(d1b)};
      } else {
        af = {std::uint8_t(d1a), std::uint8_t(d1b), std::uint8_t(d0a), std::uint8_t(d0b)};
      }
      ambiguous_face_ids[mc.n_ambiguous] = fi;
      mc.ambiguous[mc.n_ambiguous++] = af;
    }
    mc.first_entry = static_cast<std::uint32_t>(tables.entries.size());
    for (int bits = 0; bits < (1 << mc.n_ambiguous); ++bits) {
      std::array<int, 6> decision{};
      for (int j = 0; j < mc.n_ambiguous; ++j) decision[ambiguous_face_ids[j]] = (bits >> j) & 1;
      Triangulation t = triangulate(ci, faces, decision);
      McEntry entry = make_entry(tables, t, flip);
      auto tunnels = tunnels_of(ci, faces, decision, t);
      if (tunnels.size() > entry.tunnels.size()) throw std::logic_error("mc tables: too many tunnels");
      for (auto& tn : tunnels) {
        pending.push_back({tables.entries.size(), entry.n_tunnels, std::move(tn.second)});
        entry.tunnels[entry.n_tunnels++] = tn.first;
      }
      tables.entries.push_back(entry);
    }
  }
  // Tube entries go after every case's block so first_entry + decision bits stays dense.
  for (Pending& p : pending) {
    tables.entries[p.owner].tunnels[p.slot].entry = static_cast<std::uint32_t>(tables.entries.size());
    tables.entries.push_back(make_entry(tables, p.triangulation, flip));
  }
  return tables;
}

}  // namespace

bool interior_connected(const double f[8], int c0, int c1, bool above) {
  // g = f on the above side, −f on the below side; the region is g ≥ 0 (above: ties count
  // as above) or g > 0 (below).
  const double s = above ? 1.0 : -1.0;
  auto in = [&](double v) { return above ? v >= 0 : v > 0; };
  double g0[4], g1[4], lo[4], hi[4];
  bool has[4];
  for (int j = 0; j < 4; ++j) {
    g0[j] = s * f[j];
    g1[j] = s * f[j + 4];
    const bool a = in(g0[j]), b = in(g1[j]);
    has[j] = a || b;
    const double cross = a != b ? g0[j] / (g0[j] - g1[j]) : 0.0;
    lo[j] = a ? 0.0 : cross;
    hi[j] = b ? 1.0 : cross;
  }
  auto g = [&](int j, double t) { return (1.0 - t) * g0[j] + t * g1[j]; };
  int parent[4] = {0, 1, 2, 3};
  auto find = [&](int c) {
    while (parent[c] != c) c = parent[c];
    return c;
  };
  static constexpr int kSides[4][2] = {{0, 1}, {2, 3}, {0, 2}, {1, 3}};
  for (const auto& sd : kSides)
    if (has[sd[0]] && has[sd[1]] && std::max(lo[sd[0]], lo[sd[1]]) <= std::min(hi[sd[0]], hi[sd[1]]))
      parent[find(sd[0])] = find(sd[1]);
  static constexpr int kDiagonals[2][4] = {{0, 3, 1, 2}, {1, 2, 0, 3}};
  for (const auto& d : kDiagonals) {
    const int j = d[0], k = d[1], m = d[2], n = d[3];
    if (!has[j] || !has[k]) continue;
    const double t0 = std::max(lo[j], lo[k]), t1 = std::min(hi[j], hi[k]);
    if (t0 > t1) continue;
    // The slice's decider q(t) = g_j g_k − g_m g_n is quadratic; its maximum over [t0, t1]
    // is at an end or at the vertex.
    auto q = [&](double t) { return g(j, t) * g(k, t) - g(m, t) * g(n, t); };
    double best = std::max(q(t0), q(t1));
    const double dj = g1[j] - g0[j], dk = g1[k] - g0[k], dm = g1[m] - g0[m], dn = g1[n] - g0[n];
    const double qa = dj * dk - dm * dn;
    const double qb = g0[j] * dk + g0[k] * dj - g0[m] * dn - g0[n] * dm;
    if (qa < 0) {
      const double tv = -qb / (2 * qa);
      if (tv > t0 && tv < t1) best = std::max(best, q(tv));
    }
    if (above ? best >= 0 : best > 0) parent[find(j)] = find(k);
  }
  return find(c0 & 3) == find(c1 & 3);
}

const McTables& mc_tables() {
  static const McTables tables = make_tables();
  return tables;
}

}  // namespace geom::detail
