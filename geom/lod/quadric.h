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

  Quadric& operator+=(const Quadric& q) {
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
  double evaluate(const Eigen::Vector3d& x) const;

  Eigen::Matrix3d matrix() const;
  Eigen::Vector3d vector() const { return {b0, b1, b2}; }

  /// A minimiser of Q, choosing among equally good points the one nearest `reference`
  /// (Lindstrom's pseudo-inverse: eigenvalues below `relative_tolerance` × the largest are
  /// treated as zero). Always finite; returns reference when A is (near) zero.
  /// Complexity: O(1).
  Eigen::Vector3d minimizer(const Eigen::Vector3d& reference,
                            double relative_tolerance = 1e-7) const;
};

}  // namespace geom
