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

namespace {

// The symmetric 3×3 system B·d = p by Cramer's rule, or nothing when B is too
// ill-conditioned for it (Quadric::kConditioned, as in minimizer()).
bool solve_conditioned(const Eigen::Matrix3d& b, const Eigen::Vector3d& p, Eigen::Vector3d& d) {
  const double trace = b.trace();
  const double c00 = b(1, 1) * b(2, 2) - b(1, 2) * b(1, 2);
  const double c01 = b(0, 2) * b(1, 2) - b(0, 1) * b(2, 2);
  const double c02 = b(0, 1) * b(1, 2) - b(0, 2) * b(1, 1);
  const double det = b(0, 0) * c00 + b(0, 1) * c01 + b(0, 2) * c02;
  if (!(det > Quadric::kConditioned * trace * trace * trace)) return false;
  const double c11 = b(0, 0) * b(2, 2) - b(0, 2) * b(0, 2);
  const double c12 = b(0, 1) * b(0, 2) - b(0, 0) * b(1, 2);
  const double c22 = b(0, 0) * b(1, 1) - b(0, 1) * b(0, 1);
  d = Eigen::Vector3d(c00 * p.x() + c01 * p.y() + c02 * p.z(),
                      c01 * p.x() + c11 * p.y() + c12 * p.z(),
                      c02 * p.x() + c12 * p.y() + c22 * p.z()) /
      det;
  return d.allFinite();
}

}  // namespace

Eigen::Vector3d Quadric::minimizer_singular(const Eigen::Vector3d& reference,
                                            const Eigen::Vector3d& r,
                                            double relative_tolerance) const {
  const Eigen::Matrix3d a = matrix();
  const double trace = a00 + a11 + a22;
  // The adjugate (cofactors) of A, its determinant and σ₂, the sum of its principal minors.
  const double c00 = a11 * a22 - a12 * a12, c01 = a02 * a12 - a01 * a22,
               c02 = a01 * a12 - a02 * a11, c11 = a00 * a22 - a02 * a02,
               c12 = a01 * a02 - a00 * a12, c22 = a00 * a11 - a01 * a01;
  const double sigma2 = c00 + c11 + c22;
  const double det = a00 * c00 + a01 * c01 + a02 * c02;
  const double tol = relative_tolerance;
  // Two cases settle from these invariants alone, with λ1 ≥ λ2 ≥ λ3 ≥ 0, λ1 ≥ trace/3 and
  // λ1λ2 ≤ σ₂ ≤ 3λ1λ2: flat regions (rank 1) and creases (rank 2), most of the singular
  // quadrics of CAD meshes, without the eigensolver. σ₂'s round-off is a few ε·trace², far
  // below the rank-1 bound for any tolerance from 1e-13 up.
  if (sigma2 <= tol * trace * trace / 9) {
    // λ2 ≤ 3σ₂/trace ≤ tol·λ1: only the largest eigenvalue counts, and A·r / trace² is its
    // term u1(u1·r)/λ1 up to a relative tol.
    const Eigen::Vector3d d = a * r / (trace * trace);
    return d.allFinite() ? Eigen::Vector3d(reference + d) : reference;
  }
  // λ3 ≤ 3·det/σ₂ ≤ tol·λ1, while λ2 ≥ σ₂/trace − 2·tol·trace > tol·λ1: rank 2. The test
  // on det is trusted only 100× above det's round-off.
  if (det <= tol * trace * sigma2 / 9 && sigma2 >= 9 * tol * trace * trace &&
      tol * sigma2 >= 9e-13 * trace * trace) {
    // The adjugate is λ1λ2·u3u3ᵀ plus terms in λ3: its largest column is the null direction
    // u3. Lifting u3's eigenvalue to the trace leaves the other two, so the lifted matrix
    // solved on r without its u3 part gives the pseudo-inverse's answer.
    Eigen::Vector3d u = c00 >= c11 && c00 >= c22 ? Eigen::Vector3d(c00, c01, c02)
                        : c11 >= c22             ? Eigen::Vector3d(c01, c11, c12)
                                                 : Eigen::Vector3d(c02, c12, c22);
    u.normalize();
    Eigen::Vector3d d;
    if (u.allFinite() && solve_conditioned(a + trace * u * u.transpose(), r - u * u.dot(r), d))
      return reference + d;
  }
  // The iterative solver, not computeDirect(): the closed form's small eigenvalues of a
  // nearly rank-1 quadric are off by about 4e-9 of the largest (on fandisk it returned
  // negative ones for these positive semi-definite matrices), too coarse for a tolerance
  // below that. compute() resolves them to about machine epsilon.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.compute(a);
  const Eigen::Vector3d lambda = eig.eigenvalues();
  const double lmax = lambda.cwiseAbs().maxCoeff();
  if (!(lmax > 0) || !lambda.allFinite()) return reference;
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  const Eigen::Matrix3d& v = eig.eigenvectors();
  for (int k = 0; k < 3; ++k)
    if (lambda[k] > tol * lmax) d += v.col(k) * (v.col(k).dot(r) / lambda[k]);
  if (!d.allFinite()) return reference;
  return reference + d;
}

}  // namespace geom
