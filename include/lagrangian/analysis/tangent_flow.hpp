#pragma once
/// \file tangent_flow.hpp
/// The Jacobian of the equations of motion with respect to the state, by
/// automatic differentiation: the tangent flow of an unconstrained model.
///
/// With x = (q, q̇) the motion is ẋ = f(x, t) = (q̇, q̈(q, q̇, t)), where
///   M q̈ = r,   M = ∂²L/∂q̇²,
///   r = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t + Q,   Q = Q_model − ∂D/∂q̇
/// (dynamics.hpp). A small change δx of the state evolves by the
/// variational equations δẋ = J(x, t) δx with
///   J = [[0, I], [∂q̈/∂q, ∂q̈/∂q̇]],
/// and differentiating M q̈ = r along the state variable x_j gives
///   M ∂q̈/∂x_j = ∂r/∂x_j − (∂M/∂x_j) q̈.
/// ∂M/∂x_j and ∂r/∂x_j are third derivatives of L (∂r/∂q contains
/// ∂³L/∂q̇∂q∂q): L is evaluated once on nested numbers, a second-order
/// ad::Jet over (q, q̇, t) whose values are first-order ad::Jets over (q, q̇),
/// so every entry of M and r carries its gradient in the state. Q is
/// evaluated on the first-order numbers, ∂D/∂q̇ on a first-order Jet over q̇
/// of them. No finite differences: the result is exact to rounding.
///
/// Units: ∂q̈/∂q in 1/s² (per unit of the coordinate: rad/s² per rad,
/// m/s² per m), ∂q̈/∂q̇ in 1/s.
///
/// Scope: models with a fixed number of coordinates (n ≤ 6: the nested
/// numbers grow as n³) and without constraints or contacts (their tangent
/// flow, kept in the constraint manifold and carried across impacts, is not
/// derived here); such models are refused with AnalysisError.

#include <sstream>
#include <string>
#include <type_traits>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "lagrangian/ad.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/constraint_counts.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

namespace detail {
/// AnalysisError (its message starting with `prefix`) unless the model has
/// neither constraints nor contacts: the tangent flow is derived only for
/// such models.
template <class M>
void require_no_constraints(const M& model, const std::string& prefix) {
  if (has_constraints(model) || unilateral_count(model) > 0)
    throw AnalysisError(prefix +
                        "the tangent flow is derived for models without constraints or contacts; this model declares " +
                        std::to_string(constraint_count(model)) + " constraint rows and " +
                        std::to_string(unilateral_count(model)) + " contacts");
}
}  // namespace detail

/// Largest number of coordinates state_jacobian() takes.
inline constexpr int kMaxTangentFlowCoordinates = 6;

/// q̈ and its derivatives along K directions of the state: the n × K matrix
/// JV = (∂q̈/∂(q, q̇)) V for a 2n × K matrix V (rows δq_0 … δq_{n−1}, then
/// δq̇_0 … δq̇_{n−1}), at (q, q̇, t), without forming J: the inner numbers
/// carry K derivatives, seeded with the rows of V, so a single direction
/// (K = 1) costs a fraction of the whole Jacobian (K = 2n, V = I; see
/// state_jacobian()). With `seeded`, the same model with parameters of type
/// ad::Jet<double, K, 1> carrying derivatives along the K directions too
/// (sensitivity.hpp), L is evaluated on it, and column c of JV is the
/// derivative of q̈ along the state direction V_c and the parameter
/// direction of its seeds together: (∂q̈/∂x) V_c + (∂q̈/∂p) δp_c. Throws
/// DynamicsError when M is not positive definite there, AnalysisError for a
/// model with constraints or contacts.
template <int K, class M, class E = M>
void state_jvp(const M& model, const Vec<double, coordinate_count_v<M>>& q, const Vec<double, coordinate_count_v<M>>& qd,
               double t, const Eigen::Matrix<double, 2 * coordinate_count_v<M>, K>& v,
               Vec<double, coordinate_count_v<M>>& qdd, Eigen::Matrix<double, coordinate_count_v<M>, K>& jv,
               const E* seeded = nullptr) {
  check_model<M>();
  constexpr int n = coordinate_count_v<M>;
  static_assert(n != Dynamic, "state_jvp: the tangent flow is derived for models with a fixed coordinate_count");
  static_assert(n <= kMaxTangentFlowCoordinates,
                "state_jvp: the tangent flow is derived for models of at most kMaxTangentFlowCoordinates "
                "coordinates");
  static_assert(K >= 1 && K <= 2 * n, "state_jvp: between 1 and 2n directions");
  detail::require_no_constraints(model, "");
  using I = ad::Jet<double, K, 1>;     // a value and its derivatives along the K directions
  const E& eval = [&]() -> const E& {
    if constexpr (std::is_same_v<E, M>) {
      return model;
    } else {
      static_assert(std::is_same_v<E, typename M::template with_parameter_type<I>>,
                    "state_jvp: the seeded model is the model with parameters of type ad::Jet<double, K, 1>");
      return *seeded;
    }
  }();

  using O = ad::Jet<I, 2 * n + 1, 2>;  // second order in (q, q̇, t), each entry an I
  Vec<I, n> qi, qdi;
  Vec<O, n> qo, qdo;
  for (int k = 0; k < n; ++k) {
    qi[k] = I(q[k]);
    qdi[k] = I(qd[k]);
    for (int c = 0; c < K; ++c) {
      qi[k].g[c] = v(k, c);
      qdi[k].g[c] = v(n + k, c);
    }
    qo[k] = O::variable(qi[k], k);
    qdo[k] = O::variable(qdi[k], n + k);
  }
  const I ti(t);
  const O l = detail::lagrangian_of(eval, qo, qdo, O::variable(ti, 2 * n));

  Mat<double, n> mass;
  Eigen::Matrix<double, n, K> dmass[n];  // row i: the derivatives of M_ij along V (as dmass[i](j, ·))
  Vec<I, n> r;
  for (int i = 0; i < n; ++i) {
    I ri = l.g[i] - l.hess(n + i, 2 * n);
    for (int j = 0; j < n; ++j) {
      ri -= l.hess(n + i, j) * qdi[j];
      const I& mij = l.hess(n + i, n + j);
      mass(i, j) = mij.v;
      for (int c = 0; c < K; ++c) dmass[i](j, c) = mij.g[c];
    }
    r[i] = ri;
  }
  if constexpr (has_generalized_forces_v<M>) {
    if (uses_generalized_forces(model)) {
      const Vec<I, n> f = eval.generalized_forces(qi, qdi, ti);
      for (int i = 0; i < n; ++i) r[i] += f[i];
    }
  }
  if constexpr (has_dissipation_v<M>) {
    if (uses_dissipation(model)) {
      using D = ad::Jet<I, n, 1>;  // first order in q̇, each entry an I
      Vec<D, n> qD, qdD;
      for (int k = 0; k < n; ++k) {
        qD[k] = D(qi[k]);
        qdD[k] = D::variable(qdi[k], k);
      }
      const D d = D(eval.dissipation(qD, qdD));
      for (int i = 0; i < n; ++i) r[i] -= d.g[i];
    }
  }

  const Eigen::LLT<Mat<double, n>> llt(mass);
  const double big = mass.cwiseAbs().maxCoeff();
  bool positive = llt.info() == Eigen::Success && big > 0;
  if (positive) {
    const Vec<double, n> d = llt.matrixL().toDenseMatrix().diagonal();
    positive = d.minCoeff() * d.minCoeff() >= singular_mass_tolerance * d.maxCoeff() * d.maxCoeff();
  }
  if (!positive) {
    std::ostringstream os;
    os.precision(17);
    os << "tangent flow: the mass matrix M = d2L/dqd2 is singular or not positive definite at "
       << detail::describe_state(q, qd, t);
    throw DynamicsError(os.str());
  }
  Vec<double, n> rv;
  for (int i = 0; i < n; ++i) rv[i] = r[i].v;
  qdd = llt.solve(rv);
  // M (J V)_c = (∂r V)_c − (∂M V)_c q̈, the derivative of M q̈ = r along direction c.
  Eigen::Matrix<double, n, K> rhs;
  for (int c = 0; c < K; ++c)
    for (int i = 0; i < n; ++i) rhs(i, c) = r[i].g[c] - dmass[i].col(c).dot(qdd);
  jv = llt.solve(rhs);
}

/// q̈ and J_a = ∂q̈/∂(q, q̇) (n × 2n: the columns ∂/∂q_0 … ∂/∂q_{n−1}, then
/// ∂/∂q̇_0 … ∂/∂q̇_{n−1}) at (q, q̇, t): state_jvp() along the 2n unit
/// vectors. Throws DynamicsError when M is not positive definite there,
/// AnalysisError for a model with constraints or contacts.
template <class M>
void state_jacobian(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                    const Vec<double, coordinate_count_v<M>>& qd, double t, Vec<double, coordinate_count_v<M>>& qdd,
                    Eigen::Matrix<double, coordinate_count_v<M>, 2 * coordinate_count_v<M>>& jacobian) {
  constexpr int n = coordinate_count_v<M>;
  state_jvp<2 * n>(model, q, qd, t, Eigen::Matrix<double, 2 * n, 2 * n>::Identity(), qdd, jacobian);
}

/// ∂p/∂(q, q̇) at (q, q̇, t), p = ∂L/∂q̇: the n × 2n matrix [C, M] with
/// C_ij = ∂²L/∂q̇_i∂q_j and M = ∂²L/∂q̇² (one second-order ad::Jet pass over
/// (q, q̇)). It maps a tangent vector (δq, δq̇) to the canonical one
/// (δq, δp = C δq + M δq̇).
template <class M>
void momentum_jacobian(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                       const Vec<double, coordinate_count_v<M>>& qd, double t,
                       Eigen::Matrix<double, coordinate_count_v<M>, 2 * coordinate_count_v<M>>& out) {
  check_model<M>();
  constexpr int n = coordinate_count_v<M>;
  static_assert(n != Dynamic, "momentum_jacobian: for models with a fixed coordinate_count");
  using J = ad::Jet<double, 2 * n, 2>;
  Vec<J, n> qj, qdj;
  for (int k = 0; k < n; ++k) {
    qj[k] = J::variable(q[k], k);
    qdj[k] = J::variable(qd[k], n + k);
  }
  const J l = detail::lagrangian_of(model, qj, qdj, J(t));
  for (int i = 0; i < n; ++i)
    for (int c = 0; c < 2 * n; ++c) out(i, c) = l.hess(n + i, c);
}

}  // namespace lagrangian
