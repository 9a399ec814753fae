#include <geom/lod/quadric.h>

#include <Eigen/Eigenvalues>

#include <cmath>

namespace geom {

Eigen::Matrix3d Quadric::matrix() const {
  Eigen::Matrix3d m;
  m << a00, a01, a02, a01, a11, a12, a02, a12, a22;
  return m;
}

namespace {

// The eigenpairs of the symmetric A by deflation: one eigenvector u by power iteration on m
// (A itself when one eigenvalue dominates, converging as λ2/λ1; A's adjugate when one is far
// below the others, as λ3/λ2), the other two from the 2×2 matrix of A on the plane normal to
// u by a Jacobi rotation. Their eigenvalues come out within a few ε·trace, as the iterative
// eigensolver's, at about 0.6-0.7× its cost. False when u does not settle within 8 steps (two
// close eigenvalues on the side iterated towards).
bool deflated_eigenpairs(const Eigen::Matrix3d& a, const Eigen::Matrix3d& m,
                         Eigen::Vector3d& lambda, Eigen::Matrix3d& vectors) {
  const double trace = a.trace();
  int j = 0;
  m.diagonal().maxCoeff(&j);
  Eigen::Vector3d u = m.col(j);
  double rho = 0;
  for (int step = 0, settled = 0; settled < 2; ++step) {
    const double n = u.norm();
    if (!(n > 0) || !std::isfinite(n) || step == 9) return false;
    u /= n;
    const Eigen::Vector3d au = a * u;
    rho = u.dot(au);
    // A residual of 1e-14·trace (about 50 ε) is not yet enough: the coupling it leaves
    // between u and the plane errs a kept eigenvalue μ by up to 1e-14·trace/μ (3% at
    // μ = 3.5e-13·trace). One more step after it, which shrinks the coupling by the
    // iteration's ratio again, brings that to round-off.
    if (settled > 0 || (au - rho * u).squaredNorm() <= 1e-28 * trace * trace) ++settled;
    if (settled < 2) u = m * u;
  }
  int k = 0;
  u.cwiseAbs().minCoeff(&k);
  const Eigen::Vector3d p = u.cross(Eigen::Vector3d::Unit(k)).normalized(), q = u.cross(p);
  const double alpha = p.dot(a * p), beta = p.dot(a * q), gamma = q.dot(a * q);
  lambda = {rho, alpha, gamma};
  vectors << u, p, q;
  if (beta != 0) {
    const double tau = (gamma - alpha) / (2 * beta);
    const double t = (tau >= 0 ? 1.0 : -1.0) / (std::abs(tau) + std::sqrt(1 + tau * tau));
    const double c = 1 / std::sqrt(1 + t * t), s = t * c;
    lambda = {rho, alpha - t * beta, gamma + t * beta};
    vectors << u, c * p - s * q, s * p + c * q;
  }
  return true;
}

}  // namespace

Eigen::Vector3d Quadric::minimizer_singular(const Eigen::Vector3d& reference,
                                            const Eigen::Vector3d& r, const Adjugate& c,
                                            double relative_tolerance) const {
  const Eigen::Matrix3d a = matrix();
  const double trace = a00 + a11 + a22;
  const double tol = relative_tolerance;
  const double sigma2 = c.sigma2();
  // Flat regions settle from the invariants alone (with λ1 ≥ λ2 ≥ λ3 ≥ 0, λ1 ≥ trace/3 and
  // λ1λ2 ≤ σ₂): σ₂ ≤ tol·trace²/9 gives λ2 ≤ 3σ₂/trace ≤ tol·λ1, so only the largest
  // eigenvalue counts, and A·r / trace² is its term u1(u1·r)/λ1 up to a relative tol. σ₂'s
  // round-off, a few ε·trace², stays far below that bound for any tolerance from 1e-13 up.
  if (sigma2 <= tol * trace * trace / 9) {
    const Eigen::Vector3d d = a * r / (trace * trace);
    return d.allFinite() ? Eigen::Vector3d(reference + d) : reference;
  }
  // Otherwise one eigenvalue nearly always stands apart from the other two: the largest on a
  // nearly flat patch (σ₂ small), the smallest at a crease. Iterate towards it; the
  // eigensolver only when that does not settle.
  Eigen::Matrix3d m = a;
  if (sigma2 > 1e-2 * trace * trace)
    m << c.c00, c.c01, c.c02, c.c01, c.c11, c.c12, c.c02, c.c12, c.c22;
  Eigen::Vector3d lambda;
  Eigen::Matrix3d v;
  if (!deflated_eigenpairs(a, m, lambda, v)) {
    // The iterative solver, not computeDirect(): the closed form's small eigenvalues of a
    // nearly rank-1 quadric are off by about 4e-9 of the largest (on fandisk it returned
    // negative ones for these positive semi-definite matrices), too coarse for a tolerance
    // below that. compute() resolves them to about machine epsilon.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    eig.compute(a);
    lambda = eig.eigenvalues();
    v = eig.eigenvectors();
  }
  const double lmax = lambda.cwiseAbs().maxCoeff();
  if (!(lmax > 0) || !lambda.allFinite()) return reference;
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k)
    if (lambda[k] > tol * lmax) d += v.col(k) * (v.col(k).dot(r) / lambda[k]);
  if (!d.allFinite()) return reference;
  return reference + d;
}

}  // namespace geom
