#pragma once
// q̈ of a model that declares constant_mass_matrix (model.hpp): M is
// checked and factored once per run, and each evaluation needs only ∇V and
// the model's forces.

#include <string>
#include <utility>

#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian::detail {

/// DynamicsError for a model that declares constant_mass_matrix while its T
/// does not keep it (`why`), found at `where`.
[[noreturn]] inline void constant_mass_declaration_failure(const std::string& why, const std::string& where) {
  throw DynamicsError(
      "model declares constant_mass_matrix (T a quadratic in the velocities with constant coefficients), but " +
      why + " at " + where + "; remove the declaration (the general equations of motion then apply)");
}

/// The velocity q̇_k at which a constant_mass_matrix declaration is checked
/// (m/s or rad/s): nonzero, so that T's coefficients changing with q or t
/// show in ∂²T/∂q̇∂q and ∂²T/∂q̇∂t even at a state at rest.
constexpr double constant_mass_test_velocity(int k) { return 1.0 + 0.5 * k; }

template <class M>
class ConstantMassAccelerations {
 public:
  static constexpr int n = coordinate_count_v<M>;
  static_assert(n != Dynamic && !uses_block_passes<M>,
                "lagrangian: constant_mass_matrix is for models with a fixed coordinate_count of at most "
                "kMaxSinglePassDof (64)");
  static_assert(has_kinetic_for<M, double> && has_potential_for<M, double>,
                "lagrangian: constant_mass_matrix needs the model's kinetic() and potential(), not lagrangian()");

  /// Checks the declaration and factors M, at the run's first state (q, t):
  /// T's derivatives in q and its mixed term (∂²T/∂q̇∂q) q̇ + ∂²T/∂q̇∂t are
  /// exactly zero, and M is the same, at two velocities and two
  /// configurations (q and q shifted by a different amount per coordinate).
  /// Throws DynamicsError naming the declaration and the coordinate when
  /// they are not, or when M is singular.
  void prepare(const M& model, Workspace<n>& ws, const Vec<double, n>& q, const Vec<double, n>& qd, double t) {
    Vec<double, n> q2, v1, v2;
    for (int k = 0; k < n; ++k) {
      q2[k] = q[k] + 0.25 + 0.125 * k;
      v1[k] = constant_mass_test_velocity(k);
      v2[k] = -2.0 + 0.75 * k;
    }
    const Mat<double, n> mass = kinetic_mass(model, q, v1, t);
    for (const auto& [qc, vc] : {std::pair{q, v2}, std::pair{q2, v1}}) {
      const Mat<double, n> other = kinetic_mass(model, qc, vc, t);
      if (!((other - mass).cwiseAbs().maxCoeff() <= 1e-12 * mass.cwiseAbs().maxCoeff()))
        declaration_failure("its mass matrix M = d2T/dqd2 changes with the state", qc, vc, t);
    }
    ws.mass = mass;
    mass_ = mass;
    diagonal_ = diagonal_mass(mass);
    if (diagonal_) {
      check_diagonal_pivots(ws, q, qd, t);
    } else if constexpr (n == 2) {
      // The closed form of free_accelerations (no factorisation compiled).
      det_ = checked_determinant_2x2(ws, q, qd, t);
    } else {
      factor_mass_matrix(ws, q, qd, t);
      llt_ = ws.cholesky;
    }
  }

  /// q̈ from M q̈ = −∂V/∂q + Q − ∂D/∂q̇ (m/s² or rad/s²), into out.
  void operator()(const M& model, Workspace<n>& ws, const Vec<double, n>& q, const Vec<double, n>& qd, double t,
                  Vec<double, n>& out) const {
    using J = ad::Jet<double, n, 1>;
    Vec<J, n> qj;
    for (int k = 0; k < n; ++k) qj[k] = J::variable(q[k], k);
    const J v = J(model.potential(qj, J(t)));
    force_pass(model, ws, q, qd, t);
    for (int i = 0; i < n; ++i) ws.rhs[i] = ws.forces[i] - v.g[static_cast<std::size_t>(i)];
    if (diagonal_) {
      out = ws.rhs.cwiseQuotient(mass_.diagonal());
    } else if constexpr (n == 2) {
      solve_2x2(mass_, det_, ws.rhs, out);
    } else {
      llt_.solve(ws.rhs.data(), out.data());
    }
  }

 private:
  /// M of T alone at (q, q̇ = v, t), after checking that T's q-gradient and
  /// mixed term vanish there.
  static Mat<double, n> kinetic_mass(const M& model, const Vec<double, n>& q, const Vec<double, n>& v, double t) {
    using J = ad::EomJet<n>;
    Vec<J, n> qj, vj;
    for (int k = 0; k < n; ++k) {
      qj[k] = J::position(q[k], v[k], k);
      vj[k] = J::velocity(v[k], k);
    }
    J kinetic = J(model.kinetic(qj, vj, J::time(t)));
    for (int i = 0; i < n; ++i) {
      if (kinetic.grad_q(i) != 0)
        declaration_failure("dT/dq[" + std::to_string(i) + "] is not zero", q, v, t);
      if (kinetic.mixed(i) != 0)
        declaration_failure("T's coefficient of qd[" + std::to_string(i) + "] changes with q or t", q, v, t);
    }
    Mat<double, n> mass;
    kinetic.hessian_to(mass);
    return mass;
  }
  [[noreturn]] static void declaration_failure(const std::string& why, const Vec<double, n>& q,
                                               const Vec<double, n>& v, double t) {
    constant_mass_declaration_failure(why, "the test point " + describe_state(q, v, t) +
                                               " (the initial configuration, or it shifted, at test velocities)");
  }

  bool diagonal_ = false;
  Mat<double, n> mass_;             // M
  double det_ = 0;                  // det M (n = 2, not diagonal)
  MassCholesky<n> llt_;             // n > 2, not diagonal
};

}  // namespace lagrangian::detail
