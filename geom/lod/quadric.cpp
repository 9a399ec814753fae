#include <geom/lod/quadric.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

namespace geom {

Eigen::Matrix3d Quadric::matrix() const {
  Eigen::Matrix3d m;
  m << a00, a01, a02, a01, a11, a12, a02, a12, a22;
  return m;
}

Eigen::Vector3d Quadric::minimizer_singular(const Eigen::Vector3d& reference,
                                            const Eigen::Vector3d& r,
                                            double relative_tolerance) const {
  // The iterative solver, not computeDirect(): the closed form's small eigenvalues of a
  // nearly rank-1 quadric are off by about 4e-9 of the largest (on fandisk it returned
  // negative ones for these positive semi-definite matrices), too coarse for a tolerance
  // below that. compute() resolves them to about machine epsilon.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.compute(matrix());
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
