#pragma once
/// \file modes.hpp
/// Small oscillations about a configuration: the normal modes of
/// K_t v = ω² M_t v on the tangent space and the linear model ẋ = A x
/// (see analysis.hpp for the equations).

#include <string>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/analysis/detail/rest_model.hpp"
#include "lagrangian/analysis/linearisation.hpp"
#include "lagrangian/model.hpp"

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

namespace detail {

/// small_oscillations() on the model frozen at its time (src/analysis/modes.cpp).
Modes modes_of(const RestModel& model, const Eigen::VectorXd& q, double zero_tolerance);

}  // namespace detail

/// The linearisation about q (normally an equilibrium; Modes::residual says
/// how far from one it is): M, K with the constraint curvature, the tangent
/// basis, normal modes and the state matrix A. Zero modes (|ω²| ≤
/// zero_tolerance · max|ω²|) are reported as ω = 0. Throws AnalysisError when
/// M_t is not positive definite.
template <class M>
Modes small_oscillations(const M& model, const Vec<double, coordinate_count_v<M>>& q, double t = 0.0,
                         double zero_tolerance = 1e-9) {
  check_model<M>();
  detail::refuse_for_equilibria(model);
  return detail::modes_of(detail::RestModelOf<M>(model, t), q, zero_tolerance);
}

}  // namespace lagrangian
