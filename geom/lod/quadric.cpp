#include <geom/lod/quadric.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace geom {

Quadric Quadric::plane(const Eigen::Vector3d& n, double d, double w) {
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

double Quadric::evaluate(const Eigen::Vector3d& p) const {
  const double x = p.x(), y = p.y(), z = p.z();
  const double v = a00 * x * x + a11 * y * y + a22 * z * z +
                   2 * (a01 * x * y + a02 * x * z + a12 * y * z) +
                   2 * (b0 * x + b1 * y + b2 * z) + c;
  return std::max(v, 0.0);
}

Eigen::Matrix3d Quadric::matrix() const {
  Eigen::Matrix3d m;
  m << a00, a01, a02, a01, a11, a12, a02, a12, a22;
  return m;
}

Eigen::Vector3d Quadric::minimizer(const Eigen::Vector3d& reference,
                                   double relative_tolerance) const {
  // Solve A δ = r with r = −(A·ref + b) and return ref + δ: working relative to the
  // reference keeps the answer near it where A is rank-deficient.
  const Eigen::Vector3d r = -(matrix() * reference + vector());
  const double trace = a00 + a11 + a22;
  if (!(trace > 0) || !std::isfinite(trace)) return reference;
  // Cofactors of the symmetric A; det ≤ λmin·trace², so det > tol·trace³ bounds the
  // condition number and the closed form is safe.
  const double c00 = a11 * a22 - a12 * a12;
  const double c01 = a02 * a12 - a01 * a22;
  const double c02 = a01 * a12 - a02 * a11;
  const double det = a00 * c00 + a01 * c01 + a02 * c02;
  if (det > relative_tolerance * 1e3 * trace * trace * trace) {
    const double c11 = a00 * a22 - a02 * a02;
    const double c12 = a01 * a02 - a00 * a12;
    const double c22 = a00 * a11 - a01 * a01;
    const double inv = 1.0 / det;
    const Eigen::Vector3d d((c00 * r.x() + c01 * r.y() + c02 * r.z()) * inv,
                            (c01 * r.x() + c11 * r.y() + c12 * r.z()) * inv,
                            (c02 * r.x() + c12 * r.y() + c22 * r.z()) * inv);
    return reference + d;
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect(matrix());
  const Eigen::Vector3d lambda = eig.eigenvalues();
  const double lmax = lambda.cwiseAbs().maxCoeff();
  if (!(lmax > 0) || !lambda.allFinite()) return reference;
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d& u = eig.eigenvectors();
  for (int k = 0; k < 3; ++k)
    if (lambda[k] > relative_tolerance * lmax) d += u.col(k) * (u.col(k).dot(r) / lambda[k]);
  if (!d.allFinite()) return reference;
  return reference + d;
}

}  // namespace geom
