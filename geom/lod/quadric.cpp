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

Eigen::Matrix3d Quadric::matrix() const {
  Eigen::Matrix3d m;
  m << a00, a01, a02, a01, a11, a12, a02, a12, a22;
  return m;
}

Eigen::Vector3d Quadric::minimizer_singular(const Eigen::Vector3d& reference,
                                            const Eigen::Vector3d& r,
                                            double relative_tolerance) const {
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
