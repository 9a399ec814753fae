#include <geom/core/geometry.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace geom {

namespace {

// Error-free transformations (Knuth's two-sum, and the product error through fma). With
// them a determinant of coordinate differences is evaluated exactly as a sum of doubles.
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  double bv = x - a;
  double av = x - bv;
  y = (a - av) + (b - bv);
}

inline void two_prod(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

// A nonoverlapping expansion grown one double at a time (Shewchuk's Grow-Expansion). Sum
// of doubles represented exactly; its sign is the sign of the largest nonzero component.
struct Expansion {
  std::array<double, 40> c{};
  int n = 0;
  void add(double b) {
    double q = b;
    for (int i = 0; i < n; ++i) {
      double x, y;
      two_sum(q, c[i], x, y);
      c[i] = y;
      q = x;
    }
    c[n++] = q;
  }
  int sign() const {
    for (int i = n - 1; i >= 0; --i)
      if (c[i] != 0.0) return c[i] > 0 ? 1 : -1;
    return 0;
  }
};

// Exact sign of (bx-ax)(cy-ay) - (by-ay)(cx-ax).
int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  double d[4][2];
  two_sum(bx, -ax, d[0][0], d[0][1]);
  two_sum(cy, -ay, d[1][0], d[1][1]);
  two_sum(by, -ay, d[2][0], d[2][1]);
  two_sum(cx, -ax, d[3][0], d[3][1]);
  Expansion e;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      double x, y;
      two_prod(d[0][i], d[1][j], x, y);
      e.add(x);
      e.add(y);
      two_prod(d[2][i], d[3][j], x, y);
      e.add(-x);
      e.add(-y);
    }
  return e.sign();
}

// Filtered orient2d sign: +1/-1 when the double evaluation is certain, 0 when it is not.
// The relative bound is Shewchuk's ccwerrboundA rounded up; the absolute term covers
// products that underflow, and overflow yields NaN/inf, which is never "certain".
int orient2d_filter(double ax, double ay, double bx, double by, double cx, double cy) {
  double l = (bx - ax) * (cy - ay);
  double r = (by - ay) * (cx - ax);
  double det = l - r;
  double bound = 4.0e-16 * (std::abs(l) + std::abs(r)) + 1.0e-290;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return 0;
}

bool finite(const Point& p) { return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.z()); }

double corner_angle(const Point& p, const Point& a, const Point& b) {
  Eigen::Vector3d u = a - p, w = b - p;
  return std::atan2(u.cross(w).norm(), u.dot(w));
}

Eigen::Vector3d newell(const SurfaceMesh& mesh, Face f) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (Halfedge h : mesh.halfedges(f)) {
    const Point& a = mesh.position(mesh.from_vertex(h));
    const Point& b = mesh.position(mesh.to_vertex(h));
    n += a.cross(b);
  }
  return n;
}

}  // namespace

bool is_collinear(const Point& p, const Point& q, const Point& r) {
  // Nearly every call is decided by one filtered projection.
  if (orient2d_filter(p.x(), p.y(), q.x(), q.y(), r.x(), r.y()) != 0 ||
      orient2d_filter(p.y(), p.z(), q.y(), q.z(), r.y(), r.z()) != 0 ||
      orient2d_filter(p.z(), p.x(), q.z(), q.x(), r.z(), r.x()) != 0)
    return false;
  if (!finite(p) || !finite(q) || !finite(r)) return false;
  // Collinearity is scale-invariant: scaling by a power of two (exact) brings the largest
  // coordinate near 1, so the exact products neither overflow nor underflow.
  double m = std::max({p.cwiseAbs().maxCoeff(), q.cwiseAbs().maxCoeff(), r.cwiseAbs().maxCoeff()});
  if (m == 0) return true;
  const int e = std::ilogb(m);
  Point ps, qs, rs;
  for (int i = 0; i < 3; ++i) {
    ps[i] = std::ldexp(p[i], -e);
    qs[i] = std::ldexp(q[i], -e);
    rs[i] = std::ldexp(r[i], -e);
  }
  // Collinear in 3D exactly when all three axis-aligned projections are collinear.
  return orient2d_exact(ps.x(), ps.y(), qs.x(), qs.y(), rs.x(), rs.y()) == 0 &&
         orient2d_exact(ps.y(), ps.z(), qs.y(), qs.z(), rs.y(), rs.z()) == 0 &&
         orient2d_exact(ps.z(), ps.x(), qs.z(), qs.x(), rs.z(), rs.x()) == 0;
}

bool is_zero_area_polygon(std::span<const Point> points) {
  if (points.size() < 3) return true;
  const Point& p = points[0];
  std::size_t qi = 1;
  while (qi < points.size() && points[qi] == p) ++qi;
  if (qi == points.size()) return true;
  for (std::size_t i = qi + 1; i < points.size(); ++i)
    if (!is_collinear(p, points[qi], points[i])) return false;
  return true;
}

Normal face_normal(const SurfaceMesh& mesh, Face f) {
  Eigen::Vector3d n = newell(mesh, f);
  double len = n.norm();
  return len > 0 ? Normal(n / len) : Normal::Zero();
}

double face_area(const SurfaceMesh& mesh, Face f) { return 0.5 * newell(mesh, f).norm(); }

Point face_centroid(const SurfaceMesh& mesh, Face f) {
  Point c = Point::Zero();
  std::size_t n = 0;
  for (Vertex v : mesh.vertices(f)) {
    c += mesh.position(v);
    ++n;
  }
  return n ? Point(c / static_cast<double>(n)) : c;
}

Normal vertex_normal(const SurfaceMesh& mesh, Vertex v) {
  Normal n = Normal::Zero();
  if (mesh.is_isolated(v)) return n;
  const Point& p = mesh.position(v);
  for (Halfedge h : mesh.outgoing(v)) {
    Face f = mesh.face(h);
    if (!f.is_valid()) continue;
    const Point& a = mesh.position(mesh.to_vertex(h));
    const Point& b = mesh.position(mesh.from_vertex(mesh.prev(h)));
    n += corner_angle(p, a, b) * face_normal(mesh, f);
  }
  double len = n.norm();
  return len > 0 ? Normal(n / len) : Normal::Zero();
}

Eigen::AlignedBox3d bounds(const SurfaceMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (Vertex v : mesh.vertices()) box.extend(mesh.position(v));
  return box;
}

double edge_length(const SurfaceMesh& mesh, Edge e) {
  return (mesh.position(mesh.vertex(e, 0)) - mesh.position(mesh.vertex(e, 1))).norm();
}

double mean_edge_length(const SurfaceMesh& mesh) {
  double sum = 0;
  std::size_t n = 0;
  for (Edge e : mesh.edges()) {
    sum += edge_length(mesh, e);
    ++n;
  }
  return n ? sum / static_cast<double>(n) : 0.0;
}

double dihedral_angle(const SurfaceMesh& mesh, Edge e) {
  if (mesh.is_boundary(e)) return 0.0;
  Halfedge h0 = SurfaceMesh::halfedge(e, 0);
  Normal n0 = face_normal(mesh, mesh.face(h0));
  Normal n1 = face_normal(mesh, mesh.face(SurfaceMesh::opposite(h0)));
  if (n0.isZero() || n1.isZero()) return 0.0;
  Eigen::Vector3d d = mesh.position(mesh.to_vertex(h0)) - mesh.position(mesh.from_vertex(h0));
  double len = d.norm();
  if (len == 0) return 0.0;
  // Seen along h0 (face 0 on its left), a convex fold turns n0 towards n1 counter-clockwise
  // about h0's direction, which makes (n0 × n1)·d positive.
  return std::atan2(n0.cross(n1).dot(d / len), n0.dot(n1));
}

double surface_area(const SurfaceMesh& mesh) {
  double a = 0;
  for (Face f : mesh.faces()) a += face_area(mesh, f);
  return a;
}

std::vector<std::array<std::uint32_t, 3>> triangulate_fan(const SurfaceMesh& mesh, Face f) {
  std::uint32_t n = static_cast<std::uint32_t>(mesh.valence(f));
  std::vector<std::array<std::uint32_t, 3>> out;
  if (n < 3) return out;
  out.reserve(n - 2);
  for (std::uint32_t i = 1; i + 1 < n; ++i) out.push_back({0u, i, i + 1});
  return out;
}

std::vector<std::array<Vertex, 3>> triangulate_fan_vertices(const SurfaceMesh& mesh, Face f) {
  std::vector<Vertex> corners;
  for (Vertex v : mesh.vertices(f)) corners.push_back(v);
  std::vector<std::array<Vertex, 3>> out;
  if (corners.size() < 3) return out;
  out.reserve(corners.size() - 2);
  for (std::size_t i = 1; i + 1 < corners.size(); ++i)
    out.push_back({corners[0], corners[i], corners[i + 1]});
  return out;
}

}  // namespace geom
