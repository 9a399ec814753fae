#include <geom/isosurface/mc_tables.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

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

/// Triangles (edge/centroid refs) for one case and one set of decisions, in loop order.
struct Triangulation {
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::uint16_t> centroids;
};

Triangulation triangulate(int case_index, const std::array<FaceDef, 6>& faces,
                          const std::array<int, 6>& face_decision) {
  auto above = [&](int c) { return ((case_index >> c) & 1) != 0; };
  std::array<int, 12> next;
  next.fill(-1);
  // Pairs of edges on a common four-crossing face: a fan diagonal between them could be
  // picked by the neighbouring cube too.
  std::array<std::array<bool, 12>, 12> forbidden{};
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
  Triangulation out;
  std::array<bool, 12> seen{};
  for (int start = 0; start < 12; ++start) {
    if (next[start] < 0 || seen[start]) continue;
    std::vector<int> loop;
    for (int e = start; !seen[e]; e = next[e]) {
      seen[e] = true;
      loop.push_back(e);
    }
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
        out.triangles.push_back(
            {loop[apex], loop[(apex + k) % n], loop[(apex + k + 1) % n]});
    } else {
      std::uint16_t mask = 0;
      for (int e : loop) mask |= std::uint16_t(1u << e);
      int centre = 12 + static_cast<int>(out.centroids.size());
      out.centroids.push_back(mask);
      for (int k = 0; k < n; ++k) out.triangles.push_back({centre, loop[k], loop[(k + 1) % n]});
    }
  }
  return out;
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
      McEntry entry;
      entry.first_ref = static_cast<std::uint32_t>(tables.refs.size());
      entry.n_triangles = static_cast<std::uint8_t>(t.triangles.size());
      entry.n_centroids = static_cast<std::uint8_t>(t.centroids.size());
      for (std::size_t j = 0; j < t.centroids.size(); ++j) entry.centroid_mask[j] = t.centroids[j];
      for (const auto& tri : t.triangles) {
        tables.refs.push_back(std::uint8_t(tri[0]));
        tables.refs.push_back(std::uint8_t(flip ? tri[2] : tri[1]));
        tables.refs.push_back(std::uint8_t(flip ? tri[1] : tri[2]));
      }
      tables.entries.push_back(entry);
    }
  }
  return tables;
}

}  // namespace

const McTables& mc_tables() {
  static const McTables tables = make_tables();
  return tables;
}

}  // namespace geom::detail
