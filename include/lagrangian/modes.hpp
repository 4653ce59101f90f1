#pragma once
/// \file modes.hpp
/// Small oscillations about a configuration: the normal modes of
/// K_t v = ω² M_t v on the tangent space and the linear model ẋ = A x
/// (see analysis.hpp for the equations).

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <nlopt.h>

#include "lagrangian/ad.hpp"
#include "lagrangian/constraints.hpp"
#include "lagrangian/discrete.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/linearisation.hpp"

namespace lagrangian {

/// The linearisation about a configuration q* (see the file comment).
struct Modes {
  Eigen::VectorXd q;               ///< the configuration linearised about
  Eigen::VectorXd multipliers;     ///< λ from ∇U = Gᵀλ (least squares)
  double residual = 0;             ///< ‖∇U − Gᵀλ‖∞: 0 at an equilibrium; otherwise q is not one
  Eigen::MatrixXd mass;            ///< M(q*) in the original coordinates (n×n)
  Eigen::MatrixXd stiffness;       ///< ∇²U − Σλ_i∇²g_i in the original coordinates (n×n)
  Eigen::MatrixXd gyroscopic;      ///< G_y = C − Cᵀ (n×n)
  Eigen::MatrixXd basis;           ///< Z: n×d, orthonormal columns spanning the tangent space (identity without constraints)
  Eigen::MatrixXd tangent_mass;    ///< M_t = Zᵀ M Z (d×d)
  Eigen::MatrixXd tangent_stiffness;  ///< K_t = Zᵀ K Z (d×d)
  Eigen::VectorXd omega_squared;   ///< ω² of K_t v = ω² M_t v, ascending (1/s²); negative: unstable direction
  Eigen::VectorXd omega;           ///< ω = √ω² (rad/s) where ω² ≥ 0 (zero modes exactly 0), NaN where ω² < 0
  Eigen::MatrixXd shapes;          ///< n×d: column j is Z v_j, v_jᵀ M_t v_j = 1
  Eigen::MatrixXd state_matrix;    ///< A (2d×2d), state [ξ; ξ̇] with q = q* + Z ξ
  Eigen::VectorXcd state_eigenvalues;  ///< eigenvalues of A (1/s): ±iω for normal modes
  bool gyroscopic_terms = false;   ///< G_y ≠ 0: the normal modes above ignore it; A and its eigenvalues include it
  int zero_modes = 0;              ///< |ω²| ≤ zero_tolerance · max |ω²|
};

/// The normal modes for a terminal: ω (rad/s), frequency (Hz), period (s)
/// and the M-normalised shapes, plus warnings (not an equilibrium, unstable
/// directions, gyroscopic terms).
std::string format_modes(const Modes& modes, const std::vector<std::string>& names,
                         const std::vector<std::string>& units);

/// The linearisation about q (normally an equilibrium; Modes::residual says
/// how far from one it is): M, K with the constraint curvature, the tangent
/// basis, normal modes and the state matrix A. Zero modes (|ω²| ≤
/// zero_tolerance · max|ω²|) are reported as ω = 0. Throws AnalysisError when
/// M_t is not positive definite.
template <class M>
Modes small_oscillations(const M& model, const Vec<double, M::dof>& q, double t = 0.0,
                         double zero_tolerance = 1e-9) {
  check_model<M>();
  detail::require_static_size<M>();
  detail::refuse_for_equilibria(model);
  constexpr int n = M::dof;
  const QuadraticLagrangian ql = quadratic_lagrangian(model, q, t);
  const detail::HolonomicDerivatives c = detail::holonomic_derivatives(model, q, t);
  Modes md;
  md.q = q;
  const Eigen::VectorXd grad = -ql.force;
  md.multipliers = detail::least_squares_multipliers(c.jacobian, grad);
  md.residual = (c.value.size() ? Eigen::VectorXd(grad - c.jacobian.transpose() * md.multipliers) : grad)
                    .template lpNorm<Eigen::Infinity>();
  md.mass = ql.mass;
  md.stiffness = ql.stiffness;
  for (int i = 0; i < c.value.size(); ++i) md.stiffness -= md.multipliers[i] * c.hessians[static_cast<std::size_t>(i)];
  md.gyroscopic = ql.mixed - ql.mixed.transpose();
  md.basis = detail::tangent_basis(c.jacobian, n);
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

}  // namespace lagrangian
