#pragma once
/// \file
/// Garland–Heckbert error quadrics: the sum of squared distances to a set of weighted
/// planes, stored as the 10 distinct coefficients of a symmetric 4×4 matrix, with an
/// optimal-placement solver that cannot blow up on singular quadrics (flat or straight
/// regions).
///
/// Ref: Garland, Heckbert, "Surface Simplification Using Quadric Error Metrics", SIGGRAPH
/// 1997; Lindstrom, "Out-of-Core Simplification of Large Polygonal Models", SIGGRAPH 2000
/// (pseudo-inverse placement relative to a reference point).

#include <Eigen/Core>

#include <cmath>

namespace geom {

/// Q(x) = xᵀAx + 2bᵀx + c for symmetric A.
struct Quadric {
  double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0;
  double b0 = 0, b1 = 0, b2 = 0;
  double c = 0;

  /// The quadric of the plane n·x + d = 0 times weight w (n need not be unit; the
  /// distance is then scaled by |n|).
  static Quadric plane(const Eigen::Vector3d& n, double d, double w = 1.0);
  /// The plane through point p with normal n (unit), times weight w.
  static Quadric plane_through(const Eigen::Vector3d& p, const Eigen::Vector3d& n, double w = 1.0) {
    return plane(n, -n.dot(p), w);
  }

  // Forced inline: simplification's setup adds three per face, and out of line each was a
  // call that also kept the sums out of SIMD registers.
  [[gnu::always_inline]] Quadric& operator+=(const Quadric& q) {
    a00 += q.a00, a01 += q.a01, a02 += q.a02, a11 += q.a11, a12 += q.a12, a22 += q.a22;
    b0 += q.b0, b1 += q.b1, b2 += q.b2, c += q.c;
    return *this;
  }
  friend Quadric operator+(Quadric a, const Quadric& b) { return a += b; }
  Quadric& operator*=(double s) {
    a00 *= s, a01 *= s, a02 *= s, a11 *= s, a12 *= s, a22 *= s;
    b0 *= s, b1 *= s, b2 *= s, c *= s;
    return *this;
  }

  /// Q(x); clamped at 0 (round-off can make it slightly negative).
  double evaluate(const Eigen::Vector3d& x) const {
    const double px = x.x(), py = x.y(), pz = x.z();
    const double v = a00 * px * px + a11 * py * py + a22 * pz * pz +
                     2 * (a01 * px * py + a02 * px * pz + a12 * py * pz) +
                     2 * (b0 * px + b1 * py + b2 * pz) + c;
    return v < 0.0 ? 0.0 : v;
  }

  /// The same quadric about the origin moved by t: Q'(y) = Q(y + t). Translating by a short
  /// vector keeps a quadric stored relative to a nearby point small in every term, so its
  /// evaluation does not cancel (Q far from the origin is a difference of large terms).
  Quadric translated(const Eigen::Vector3d& t) const {
    Quadric q = *this;
    const double x = t.x(), y = t.y(), z = t.z();
    const double ax = a00 * x + a01 * y + a02 * z;
    const double ay = a01 * x + a11 * y + a12 * z;
    const double az = a02 * x + a12 * y + a22 * z;
    q.b0 = b0 + ax, q.b1 = b1 + ay, q.b2 = b2 + az;
    q.c = c + ((ax + 2 * b0) * x + (ay + 2 * b1) * y + (az + 2 * b2) * z);
    return q;
  }

  Eigen::Matrix3d matrix() const;
  Eigen::Vector3d vector() const { return {b0, b1, b2}; }

  /// A minimiser of Q, choosing among equally good points the one nearest `reference`
  /// (Lindstrom's pseudo-inverse: eigenvalues below `relative_tolerance` × the largest are
  /// treated as zero). Always finite; returns reference when A is (near) zero.
  /// Complexity: O(1).
  Eigen::Vector3d minimizer(const Eigen::Vector3d& reference,
                            double relative_tolerance = 1e-7) const;

  /// Whether minimizer() takes the closed-form inverse for A with this trace, determinant
  /// and sum of principal 2×2 minors (σ₂): every eigenvalue is above the tolerance (λmin ≥
  /// det/σ₂, λmax ≤ trace), so the pseudo-inverse is the inverse, and det ≥ kConditioned·
  /// trace³, so the determinant's round-off (a few ε·trace³) stays below 1e-5 of it.
  static bool closed_form_ok(double trace, double det, double sigma2, double relative_tolerance) {
    return det > kConditioned * trace * trace * trace && det > relative_tolerance * trace * sigma2;
  }
  static constexpr double kConditioned = 1e-10;

 private:
  // A's adjugate (its cofactors, symmetric), shared by minimizer() and its singular path.
  struct Adjugate {
    double c00, c01, c02, c11, c12, c22;
    double sigma2() const { return c00 + c11 + c22; }  // the sum of A's principal 2×2 minors
  };
  Adjugate adjugate() const {
    return {a11 * a22 - a12 * a12, a02 * a12 - a01 * a22, a01 * a12 - a02 * a11,
            a00 * a22 - a02 * a02, a01 * a02 - a00 * a12, a00 * a11 - a01 * a01};
  }
  // The pseudo-inverse for an ill-conditioned A (most quadrics on flat CAD faces and smooth
  // dense scans), out of line: a rank-1 shortcut, deflation, an eigensolver as the fallback.
  Eigen::Vector3d minimizer_singular(const Eigen::Vector3d& reference, const Eigen::Vector3d& r,
                                     const Adjugate& adj, double relative_tolerance) const;
};

// Inline: simplification calls it for every face at the start.
inline Quadric Quadric::plane(const Eigen::Vector3d& n, double d, double w) {
  Quadric q;
  q.a00 = w * n.x() * n.x();
  q.a01 = w * n.x() * n.y();
  q.a02 = w * n.x() * n.z();
  q.a11 = w * n.y() * n.y();
  q.a12 = w * n.y() * n.z();
  q.a22 = w * n.z() * n.z();
  q.b0 = w * n.x() * d;
  q.b1 = w * n.y() * d;
  q.b2 = w * n.z() * d;
  q.c = w * d * d;
  return q;
}

// Inline: simplification calls it for every edge it evaluates.
inline Eigen::Vector3d Quadric::minimizer(const Eigen::Vector3d& reference,
                                          double relative_tolerance) const {
  // Solve A δ = r with r = −(A·ref + b) and return ref + δ: working relative to the
  // reference keeps the answer near it where A is rank-deficient.
  const double x = reference.x(), y = reference.y(), z = reference.z();
  const Eigen::Vector3d r(-(a00 * x + a01 * y + a02 * z + b0), -(a01 * x + a11 * y + a12 * z + b1),
                          -(a02 * x + a12 * y + a22 * z + b2));
  const double trace = a00 + a11 + a22;
  if (!(trace > 0) || !std::isfinite(trace)) return reference;
  const Adjugate c = adjugate();
  const double det = a00 * c.c00 + a01 * c.c01 + a02 * c.c02;
  if (!closed_form_ok(trace, det, c.sigma2(), relative_tolerance))
    return minimizer_singular(reference, r, c, relative_tolerance);
  const double inv = 1.0 / det;
  return {x + (c.c00 * r.x() + c.c01 * r.y() + c.c02 * r.z()) * inv,
          y + (c.c01 * r.x() + c.c11 * r.y() + c.c12 * r.z()) * inv,
          z + (c.c02 * r.x() + c.c12 * r.y() + c.c22 * r.z()) * inv};
}

}  // namespace geom
