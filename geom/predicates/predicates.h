#pragma once
/// \file
/// Exact geometric predicates on double coordinates: orient2d, incircle, orient3d,
/// insphere. Each returns the exact sign (+1, 0, -1) of its determinant, as if computed in
/// infinite precision. A floating-point evaluation with a certified error bound answers
/// almost every call; only when the bound cannot certify the sign does the exact expansion
/// arithmetic in predicates.cpp run. This is the only place in geom where numerical
/// tolerances are decided.
///
/// The *_sos variants add Simulation of Simplicity: an exactly degenerate configuration is
/// decided as if the points were perturbed infinitesimally, in an order fixed by their
/// indices, so cocircular, cospherical and collinear inputs give consistent, deterministic
/// answers.
///
/// Pre (all functions): finite coordinates, and no overflow or underflow of the
/// determinant's terms: for orient2d/incircle/orient3d/insphere the coordinate differences
/// should lie in [1e-60, 1e60] in magnitude (or be zero); products of 2, 4, 3 and 5
/// differences must stay within the double range.
///
/// Ref: J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast Robust
///      Geometric Predicates", Discrete & Computational Geometry 18(3), 1997.
///      H. Edelsbrunner, E. P. Mücke, "Simulation of Simplicity", ACM TOG 9(1), 1990.

#include <Eigen/Core>

#include <cmath>
#include <cstdint>

namespace geom {

/// Counts of predicate calls and of calls that needed the exact fallback.
struct PredicateStats {
  std::uint64_t calls = 0;
  std::uint64_t exact = 0;
  /// Fraction of calls that fell back to exact arithmetic (0 when there were none).
  double exact_rate() const { return calls ? double(exact) / double(calls) : 0.0; }
  PredicateStats& operator+=(const PredicateStats& o) {
    calls += o.calls;
    exact += o.exact;
    return *this;
  }
};

namespace detail {
constexpr double kEps = 0x1p-53;  // half an ulp of 1: the unit roundoff
constexpr double kOrient2dBound = (3.0 + 16.0 * kEps) * kEps;
constexpr double kOrient3dBound = (7.0 + 56.0 * kEps) * kEps;
constexpr double kIncircleBound = (10.0 + 96.0 * kEps) * kEps;
constexpr double kInsphereBound = (16.0 + 224.0 * kEps) * kEps;

int orient2d_exact(const double* a, const double* b, const double* c);
int orient3d_exact(const double* a, const double* b, const double* c, const double* d);
int incircle_exact(const double* a, const double* b, const double* c, const double* d);
int insphere_exact(const double* a, const double* b, const double* c, const double* d,
                   const double* e);

inline int sign_of(double x) { return (x > 0) - (x < 0); }

/// The floating-point value of orient2d and whether its sign is certified.
inline double orient2d_filter(const double* a, const double* b, const double* c, bool& sure) {
  double l = (a[0] - c[0]) * (b[1] - c[1]);
  double r = (a[1] - c[1]) * (b[0] - c[0]);
  double det = l - r;
  sure = std::fabs(det) > kOrient2dBound * (std::fabs(l) + std::fabs(r));
  return det;
}

inline double orient3d_filter(const double* a, const double* b, const double* c, const double* d,
                              bool& sure) {
  double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
  double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
  double adz = a[2] - d[2], bdz = b[2] - d[2], cdz = c[2] - d[2];
  double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  double cdxady = cdx * ady, adxcdy = adx * cdy;
  double adxbdy = adx * bdy, bdxady = bdx * ady;
  double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  double perm = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * std::fabs(adz) +
                (std::fabs(cdxady) + std::fabs(adxcdy)) * std::fabs(bdz) +
                (std::fabs(adxbdy) + std::fabs(bdxady)) * std::fabs(cdz);
  sure = std::fabs(det) > kOrient3dBound * perm;
  return det;
}

inline double incircle_filter(const double* a, const double* b, const double* c, const double* d,
                              bool& sure) {
  double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
  double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
  double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  double cdxady = cdx * ady, adxcdy = adx * cdy;
  double adxbdy = adx * bdy, bdxady = bdx * ady;
  double alift = adx * adx + ady * ady;
  double blift = bdx * bdx + bdy * bdy;
  double clift = cdx * cdx + cdy * cdy;
  double det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
  double perm = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * alift +
                (std::fabs(cdxady) + std::fabs(adxcdy)) * blift +
                (std::fabs(adxbdy) + std::fabs(bdxady)) * clift;
  sure = std::fabs(det) > kIncircleBound * perm;
  return det;
}

double insphere_filter(const double* a, const double* b, const double* c, const double* d,
                       const double* e, bool& sure);
/// incircle_sos for a configuration already known to be exactly cocircular.
int incircle_perturbed(const double* a, const double* b, const double* c, const double* d,
                       std::int64_t ia, std::int64_t ib, std::int64_t ic, std::int64_t id);
}  // namespace detail

/// Sign of the area of triangle abc: +1 when a, b, c turn counter-clockwise, -1 when
/// clockwise, 0 when collinear. Exact.
/// Complexity: O(1); a few hundred flops in the exact fallback.
inline int orient2d(const double* a, const double* b, const double* c) {
  bool sure;
  double det = detail::orient2d_filter(a, b, c, sure);
  return sure ? detail::sign_of(det) : detail::orient2d_exact(a, b, c);
}

/// +1 when d lies below the plane through a, b, c (a, b, c appear counter-clockwise seen
/// from above, i.e. from the side (b - a) x (c - a) points to), -1 above, 0 coplanar. Exact.
/// Equivalently the sign of det[a - d; b - d; c - d].
inline int orient3d(const double* a, const double* b, const double* c, const double* d) {
  bool sure;
  double det = detail::orient3d_filter(a, b, c, d, sure);
  return sure ? detail::sign_of(det) : detail::orient3d_exact(a, b, c, d);
}

/// +1 when d lies strictly inside the circle through a, b, c (which must be
/// counter-clockwise; the sign flips for clockwise), -1 outside, 0 on it. Exact.
inline int incircle(const double* a, const double* b, const double* c, const double* d) {
  bool sure;
  double det = detail::incircle_filter(a, b, c, d, sure);
  return sure ? detail::sign_of(det) : detail::incircle_exact(a, b, c, d);
}

/// +1 when e lies strictly inside the sphere through a, b, c, d (with orient3d(a,b,c,d) > 0;
/// the sign flips otherwise), -1 outside, 0 on it. Exact.
inline int insphere(const double* a, const double* b, const double* c, const double* d,
                    const double* e) {
  bool sure;
  double det = detail::insphere_filter(a, b, c, d, e, sure);
  return sure ? detail::sign_of(det) : detail::insphere_exact(a, b, c, d, e);
}

// Counting variants: identical results, and `stats` records whether the fallback ran.
inline int orient2d(const double* a, const double* b, const double* c, PredicateStats& stats) {
  ++stats.calls;
  bool sure;
  double det = detail::orient2d_filter(a, b, c, sure);
  if (sure) return detail::sign_of(det);
  ++stats.exact;
  return detail::orient2d_exact(a, b, c);
}
inline int orient3d(const double* a, const double* b, const double* c, const double* d,
                    PredicateStats& stats) {
  ++stats.calls;
  bool sure;
  double det = detail::orient3d_filter(a, b, c, d, sure);
  if (sure) return detail::sign_of(det);
  ++stats.exact;
  return detail::orient3d_exact(a, b, c, d);
}
inline int incircle(const double* a, const double* b, const double* c, const double* d,
                    PredicateStats& stats) {
  ++stats.calls;
  bool sure;
  double det = detail::incircle_filter(a, b, c, d, sure);
  if (sure) return detail::sign_of(det);
  ++stats.exact;
  return detail::incircle_exact(a, b, c, d);
}
inline int insphere(const double* a, const double* b, const double* c, const double* d,
                    const double* e, PredicateStats& stats) {
  ++stats.calls;
  bool sure;
  double det = detail::insphere_filter(a, b, c, d, e, sure);
  if (sure) return detail::sign_of(det);
  ++stats.exact;
  return detail::insphere_exact(a, b, c, d, e);
}

/// Eigen conveniences.
inline int orient2d(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c) {
  return orient2d(a.data(), b.data(), c.data());
}
inline int incircle(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                    const Eigen::Vector2d& d) {
  return incircle(a.data(), b.data(), c.data(), d.data());
}
inline int orient3d(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    const Eigen::Vector3d& d) {
  return orient3d(a.data(), b.data(), c.data(), d.data());
}
inline int insphere(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                    const Eigen::Vector3d& d, const Eigen::Vector3d& e) {
  return insphere(a.data(), b.data(), c.data(), d.data(), e.data());
}

// ---- Simulation of Simplicity ---------------------------------------------------------
// Each point carries an index (distinct per distinct point); a larger index means a larger
// infinitesimal perturbation. The results never return 0 except where documented.

/// orient2d where point i is moved by (e_i, e_i^2), e_i infinitesimal and larger for larger
/// indices. Returns 0 only if two of the points coincide and carry the same index.
/// Pre: indices distinct unless the points are equal.
/// Complexity: O(1) (at most a few exact orient2d-sized evaluations).
int orient2d_sos(const double* a, const double* b, const double* c, std::int64_t ia,
                 std::int64_t ib, std::int64_t ic);

/// incircle where each point's lifted coordinate x^2 + y^2 is raised by an infinitesimal
/// that is larger for larger indices: a point on the circle counts as outside when it has
/// the largest index of the four. Returns 0 only when all four points are collinear.
/// Pre: a, b, c counter-clockwise for the usual meaning; indices distinct.
int incircle_sos(const double* a, const double* b, const double* c, const double* d,
                 std::int64_t ia, std::int64_t ib, std::int64_t ic, std::int64_t id);

/// insphere with the same lifting perturbation as incircle_sos. Returns 0 only when all
/// five points are coplanar.
int insphere_sos(const double* a, const double* b, const double* c, const double* d,
                 const double* e, std::int64_t ia, std::int64_t ib, std::int64_t ic,
                 std::int64_t id, std::int64_t ie);

}  // namespace geom
