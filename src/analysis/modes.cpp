// Small oscillations (modes.hpp) on the RestModel interface, compiled once:
// M, K with the constraint curvature, the tangent basis, the generalized
// eigenproblem K_t v = ω² M_t v and the state matrix A.

#include "lagrangian/analysis/modes.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "lagrangian/errors.hpp"

namespace lagrangian::detail {

Modes modes_of(const RestModel& model, const Eigen::VectorXd& q, double zero_tolerance) {
  const int n = model.coordinate_count();
  const QuadraticLagrangian ql = model.quadratic(q);
  const HolonomicDerivatives c = model.holonomic(q);
  Modes md;
  md.q = q;
  const Eigen::VectorXd grad = -ql.force;
  md.multipliers = least_squares_multipliers(c.jacobian, grad);
  md.residual = (c.value.size() ? Eigen::VectorXd(grad - c.jacobian.transpose() * md.multipliers) : grad)
                    .lpNorm<Eigen::Infinity>();
  md.mass = ql.mass;
  md.stiffness = ql.stiffness;
  for (int i = 0; i < c.value.size(); ++i) md.stiffness -= md.multipliers[i] * c.hessians[static_cast<std::size_t>(i)];
  md.gyroscopic = ql.mixed - ql.mixed.transpose();
  md.basis = tangent_basis(c.jacobian, n);
  const Eigen::MatrixXd& Z = md.basis;
  const int d = static_cast<int>(Z.cols());
  md.tangent_mass = Z.transpose() * md.mass * Z;
  md.tangent_stiffness = Z.transpose() * md.stiffness * Z;
  md.tangent_mass = 0.5 * (md.tangent_mass + md.tangent_mass.transpose()).eval();
  md.tangent_stiffness = 0.5 * (md.tangent_stiffness + md.tangent_stiffness.transpose()).eval();
  const Eigen::MatrixXd Gt = Z.transpose() * md.gyroscopic * Z;
  const double mscale = md.mass.cwiseAbs().maxCoeff();
  md.gyroscopic_terms = Gt.cwiseAbs().maxCoeff() > 1e-12 * std::max(1.0, mscale);
  if (d == 0) return md;
  Eigen::LLT<Eigen::MatrixXd> llt(md.tangent_mass);
  if (llt.info() != Eigen::Success)
    throw AnalysisError("small oscillations: the mass matrix on the tangent space is not positive definite");
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> ges(md.tangent_stiffness, md.tangent_mass);
  if (ges.info() != Eigen::Success) throw AnalysisError("small oscillations: the eigenproblem K v = w^2 M v failed");
  md.omega_squared = ges.eigenvalues();
  const double wscale = md.omega_squared.cwiseAbs().maxCoeff();
  md.omega.resize(d);
  for (int j = 0; j < d; ++j) {
    double& w2 = md.omega_squared[j];
    if (std::abs(w2) <= zero_tolerance * wscale) {
      w2 = 0.0;
      ++md.zero_modes;
    }
    md.omega[j] = w2 >= 0 ? std::sqrt(w2) : std::numeric_limits<double>::quiet_NaN();
  }
  // Eigen normalises generalized eigenvectors to vᵀ M v = 1.
  md.shapes = Z * ges.eigenvectors();
  for (int j = 0; j < d; ++j) {  // sign: largest component positive
    Eigen::Index imax = 0;
    md.shapes.col(j).cwiseAbs().maxCoeff(&imax);
    if (md.shapes(imax, j) < 0) md.shapes.col(j) *= -1.0;
  }
  md.state_matrix.setZero(2 * d, 2 * d);
  md.state_matrix.topRightCorner(d, d).setIdentity();
  md.state_matrix.bottomLeftCorner(d, d) = -llt.solve(md.tangent_stiffness);
  md.state_matrix.bottomRightCorner(d, d) = -llt.solve(Gt);
  Eigen::EigenSolver<Eigen::MatrixXd> es(md.state_matrix, false);
  md.state_eigenvalues = es.eigenvalues();
  return md;
}

}  // namespace lagrangian::detail
