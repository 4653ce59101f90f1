#pragma once
/// \file tangent_flow.hpp
/// The Jacobian of the equations of motion with respect to the state, by
/// automatic differentiation: the tangent flow of a model.
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
/// ∂³L/∂q̇∂q∂q), all along one direction at a time: L is evaluated once on
/// ad::EomJet numbers — the Euler–Lagrange pass of dynamics.hpp, which gives
/// M, ∂L/∂q and the mixed term without a Hessian over (q, q̇, t) — each
/// carrying its first derivatives along the K directions of the state asked
/// for (an ad::Jet of EomJets). The derivative of a coordinate q_k along a
/// direction (δq, δq̇) is δq_k, which moves along the path at the rate δq̇_k
/// (the path's direction q̇ moves with the state), and that of a velocity
/// q̇_k is δq̇_k; the derivative of every EomJet part then follows by the
/// chain rule, and M, r and their derivatives along each direction are read
/// off L. Q and D are evaluated on the same numbers (∂D/∂q̇ is an EomJet
/// part). A model that declares constant_mass_matrix (T of q̇ alone) takes
/// a shorter road: r = −∂V/∂q + Q − ∂D/∂q̇ on first-order Jets along the
/// directions, M and its derivative along a parameter (∂M/∂m) from T.
/// No finite differences: the result is exact to rounding.
///
/// Units: ∂q̈/∂q in 1/s² (per unit of the coordinate: rad/s² per rad,
/// m/s² per m), ∂q̈/∂q̇ in 1/s.
///
/// Holonomic and Pfaffian constraints: q̈ solves M q̈ = r + Cᵀλ, C q̈ = −γ
/// (constrained_accelerations.hpp, without stabilisation), and its
/// derivative along a direction solves the same saddle-point system with
/// right-hand sides δr − δM q̈ + δCᵀλ and −δγ − δC q̈; C, γ and their
/// derivatives along the directions come from the constraint functions on
/// ad::Jets of ad::Jets (analysis/detail/tangent_solve.hpp). J then maps
/// the tangent space of the constraint manifold (tangent vectors with
/// δg = δġ = δφ = 0) into itself; vectors off it have no meaning for the
/// constrained motion (lyapunov.hpp keeps its vectors on it).
///
/// Scope: models with a fixed number of coordinates (n ≤ 6: a number holds
/// K + 1 EomJets of n² entries each); constraint rows counted at compile
/// time, or at run time (a model stated as text) up to
/// kMaxRuntimeBilateralRows (more are refused with AnalysisError). A
/// model's contacts do not act between impacts, so J is that of its motion
/// under its holonomic and Pfaffian rows alone; the tangent runs
/// (lyapunov.hpp, sensitivity.hpp) cross each impact with its saltation
/// matrix (saltation.hpp), the rows kept through it.

#include <algorithm>
#include <array>
#include <sstream>
#include <string>
#include <type_traits>

#include <Eigen/Core>

#include "lagrangian/ad.hpp"
#include "lagrangian/analysis/detail/tangent_solve.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/constraint_counts.hpp"
#include "lagrangian/mechanics/detail/constant_mass.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

namespace detail {
/// AnalysisError (its message starting with `prefix`) for constraints the
/// tangent flow is not derived for: more than kMaxRuntimeBilateralRows
/// holonomic and Pfaffian rows counted at run time. (Such rows together
/// with contacts are kept through the impacts: saltation.hpp.)
template <class M>
void require_tangent_flow_constraints(const M& model, const std::string& prefix) {
  const int rows = holonomic_count(model) + pfaffian_count(model);
  if (bilateral_rows_v<M> == Dynamic && rows > kMaxRuntimeBilateralRows)
    throw AnalysisError(prefix + "the tangent flow takes at most " + std::to_string(kMaxRuntimeBilateralRows) +
                        " holonomic and Pfaffian rows counted at run time; this model declares " +
                        std::to_string(rows));
}
}  // namespace detail

/// Largest number of coordinates state_jacobian() takes.
inline constexpr int kMaxTangentFlowCoordinates = 6;
static_assert(kMaxTangentFlowCoordinates == 6,
              "src/analysis/tangent_solve.cpp compiles the tangent pass's linear algebra for n = 1 … 6");

namespace detail {
/// The number of the tangent pass of an n-coordinate model along K
/// directions: an ad::EomJet<n> with its first derivatives along the K
/// directions (each itself an EomJet).
template <int n, int K>
using TangentNumber = ad::Jet<ad::EomJet<n>, K, 1>;

/// state_jvp() of a model that declares constant_mass_matrix: T depends on
/// q̇ alone, so M q̈ = r with r = −∂V/∂q + Q − ∂D/∂q̇, and only V, Q and D
/// are differentiated along the directions (first-order Jets of ad::Jets
/// along them); M and its derivative along the directions (non-zero only
/// along a parameter: ∂M/∂m) from T on a second-order Jet over q̇; the
/// declaration checked on T over (q, q̇, t) at the run's test velocities
/// (its q- and t-derivatives vanish).
template <int K, class M, class E, int n>
void constant_mass_jvp(const M& model, const E& eval, const Vec<double, n>& q, const Vec<double, n>& qd, double t,
                       const Eigen::Matrix<double, 2 * n, K>& v, Vec<double, n>& qdd, Eigen::Matrix<double, n, K>& jv) {
  using I = ad::Jet<double, K, 1>;  // a value and its derivatives along the K directions
  Vec<I, n> qi, qdi;
  along_directions(q, qd, v, qi, qdi);
  const I ti(t);
  // The declaration, on T to second order in (q, q̇, t) at the test
  // velocities of the run's check (there a T that changes with q or t shows
  // even when the state is at rest).
  {
    using C = ad::Jet<double, 2 * n + 1, 2>;
    Vec<C, n> qc, qdc;
    for (int k = 0; k < n; ++k) {
      qc[k] = C::variable(q[k], k);
      qdc[k] = C::variable(constant_mass_test_velocity(k), n + k);
    }
    const C kinetic = C(model.kinetic(qc, qdc, C::variable(t, 2 * n)));
    const auto where = [&] { return "the tangent flow's state " + describe_state(q, qd, t); };
    for (int i = 0; i < n; ++i) {
      if (kinetic.g[i] != 0.0) constant_mass_declaration_failure("dT/dq[" + std::to_string(i) + "] is not zero", where());
      if (kinetic.hess(n + i, 2 * n) != 0.0)
        constant_mass_declaration_failure("T's coefficient of qd[" + std::to_string(i) + "] changes with t", where());
      for (int j = 0; j < n; ++j)
        if (kinetic.hess(n + i, j) != 0.0)
          constant_mass_declaration_failure("T's coefficient of qd[" + std::to_string(i) + "] changes with q", where());
    }
  }
  // M and its derivatives along the directions (∂M/∂m along a parameter)
  // from T to second order in q̇ alone.
  using T2 = ad::Jet<I, n, 2>;
  Vec<T2, n> qt, qdt;
  for (int k = 0; k < n; ++k) {
    qt[k] = T2(qi[k]);
    qdt[k] = T2::variable(qdi[k], k);
  }
  const T2 kinetic = T2(eval.kinetic(qt, qdt, T2(ti)));
  Mat<double, n> mass;
  std::array<Mat<double, n>, K> dmass;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const I& mij = kinetic.hess(i, j);
      mass(i, j) = mij.v;
      for (int c = 0; c < K; ++c) dmass[c](i, j) = mij.g[c];
    }
  using G = ad::Jet<I, n, 1>;  // first order in q (for V) or q̇ (for D)
  Vec<G, n> qg;
  for (int k = 0; k < n; ++k) qg[k] = G::variable(qi[k], k);
  const G potential = G(eval.potential(qg, G(ti)));
  Eigen::Matrix<double, n, K + 1> r;  // column 0: r; column 1 + c: its derivative along V_c
  const auto put = [&r](int i, const I& x, double sign) {
    r(i, 0) += sign * x.v;
    for (int c = 0; c < K; ++c) r(i, c + 1) += sign * x.g[c];
  };
  r.setZero();
  for (int i = 0; i < n; ++i) put(i, potential.g[i], -1.0);
  if constexpr (has_generalized_forces_v<M>) {
    if (uses_generalized_forces(model)) {
      const Vec<I, n> f = eval.generalized_forces(qi, qdi, ti);
      for (int i = 0; i < n; ++i) put(i, f[i], 1.0);
    }
  }
  if constexpr (has_dissipation_v<M>) {
    if (uses_dissipation(model)) {
      Vec<G, n> qD, qdD;
      for (int k = 0; k < n; ++k) {
        qD[k] = G(qi[k]);
        qdD[k] = G::variable(qdi[k], k);
      }
      const G d = G(eval.dissipation(qD, qdD));
      for (int i = 0; i < n; ++i) put(i, d.g[i], -1.0);
    }
  }
  finish_tangent<n, K>(eval, mass, r, [&](int c) -> const Mat<double, n>& { return dmass[c]; }, q, qd, t, v, qdd,
                       jv);
}
/// The pass of eom_tangent_jvp(): L on TangentNumber<n, K>, returned, and
/// r = ∂L/∂q − mixed + Q − ∂D/∂q̇ (column 0) with its derivatives along the
/// K directions (columns 1 … K).
template <int K, class M, class E, int n>
inline TangentNumber<n, K> eom_tangent_pass(const M& model, const E& eval, const Vec<double, n>& q,
                                            const Vec<double, n>& qd, double t,
                                            const Eigen::Matrix<double, 2 * n, K>& v,
                                            Eigen::Matrix<double, n, K + 1>& r) {
  using B = ad::EomJet<n>;
  using X = TangentNumber<n, K>;
  Vec<X, n> qx, qdx;
  for (int k = 0; k < n; ++k) {
    qx[k] = X(B::position(q[k], qd[k], k));
    qdx[k] = X(B::velocity(qd[k], k));
    for (int c = 0; c < K; ++c) {
      qx[k].g[c] = B::moving(v(k, c), v(n + k, c));  // δq_k, moving at δq̇_k along the path
      qdx[k].g[c] = B(v(n + k, c));
    }
  }
  const X tx(B::time(t));
  X l = lagrangian_of(eval, qx, qdx, tx);
  const auto part = [](const X& x, int c) -> const B& { return c == 0 ? x.v : x.g[c - 1]; };
  for (int c = 0; c <= K; ++c)
    for (int i = 0; i < n; ++i) r(i, c) = part(l, c).grad_q(i) - part(l, c).mixed(i);
  if constexpr (has_generalized_forces_v<M>) {
    if (uses_generalized_forces(model)) {
      const Vec<X, n> f = eval.generalized_forces(qx, qdx, tx);
      for (int c = 0; c <= K; ++c)
        for (int i = 0; i < n; ++i) r(i, c) += part(f[i], c).v;
    }
  }
  if constexpr (has_dissipation_v<M>) {
    if (uses_dissipation(model)) {
      const X d = X(eval.dissipation(qx, qdx));
      for (int c = 0; c <= K; ++c)
        for (int i = 0; i < n; ++i) r(i, c) -= part(d, c).grad_qd(i);
    }
  }
  return l;
}

/// Largest model eom_tangent_pass_flat() is taken for: its numbers keep
/// every part in full storage; above, the inlined pass measured slower.
inline constexpr int kFlatTangentPassMax = 4;

/// eom_tangent_pass() `flatten`ed, as the q̈ pass is: every operation of T
/// and V inlined into it (a direction of the double pendulum takes a
/// quarter of the instructions; docs/performance.md). Taken for one
/// direction of the state (K = 1: the largest Lyapunov exponent, MEGNO) of
/// a model of at most kFlatTangentPassMax coordinates; not for K > 1 nor a
/// seeded twin, whose inlined passes took ten times as long to compile, nor
/// for models that declare inline_passes = false (an interpreter of
/// expressions, as text models are).
template <int K, class M, class E, int n>
LAGRANGIAN_FLATTEN TangentNumber<n, K> eom_tangent_pass_flat(const M& model, const E& eval, const Vec<double, n>& q,
                                                             const Vec<double, n>& qd, double t,
                                                             const Eigen::Matrix<double, 2 * n, K>& v,
                                                             Eigen::Matrix<double, n, K + 1>& r) {
  return eom_tangent_pass<K>(model, eval, q, qd, t, v, r);
}

/// state_jvp() of any other model: L on TangentNumber<n, K> (the file
/// comment), evaluated on `eval` (the model itself or its seeded twin).
template <int K, class M, class E, int n>
void eom_tangent_jvp(const M& model, const E& eval, const Vec<double, n>& q, const Vec<double, n>& qd, double t,
                     const Eigen::Matrix<double, 2 * n, K>& v, Vec<double, n>& qdd, Eigen::Matrix<double, n, K>& jv) {
  Eigen::Matrix<double, n, K + 1> r;
  const TangentNumber<n, K> l = [&] {
    if constexpr (K == 1 && n <= kFlatTangentPassMax && std::is_same_v<E, M> && inline_passes_v<M>) {
      return eom_tangent_pass_flat<K>(model, eval, q, qd, t, v, r);
    } else {
      return eom_tangent_pass<K>(model, eval, q, qd, t, v, r);
    }
  }();
  Mat<double, n> mass, dmass;
  l.v.hessian_to(mass);
  finish_tangent<n, K>(
      eval, mass, r,
      [&](int c) -> const Mat<double, n>& {
        l.g[c].hessian_to(dmass);
        return dmass;
      },
      q, qd, t, v, qdd, jv);
}
}  // namespace detail

/// Most directions state_jacobian() seeds in one pass (it takes the 2n
/// columns of J in passes of this many).
inline constexpr int kTangentPassDirections = 4;

/// q̈ and its derivatives along K directions of the state: the n × K matrix
/// JV = (∂q̈/∂(q, q̇)) V for a 2n × K matrix V (rows δq_0 … δq_{n−1}, then
/// δq̇_0 … δq̇_{n−1}), at (q, q̇, t), without forming J: one pass over T and
/// V (or L) on detail::TangentNumber<n, K>, so a single direction (K = 1)
/// costs a fraction of the whole Jacobian (see state_jacobian()). With
/// `seeded`, the same model with parameters of type ad::Jet<double, K, 1>
/// carrying derivatives along the K directions too (sensitivity.hpp), L
/// and the constraint rows are evaluated on it, and column c of JV is the
/// derivative of q̈ along the state direction V_c and the parameter
/// direction of its seeds together: (∂q̈/∂x) V_c + (∂q̈/∂p) δp_c (a model
/// whose rows are counted at run time takes K = 1 then: AnalysisError
/// otherwise). Throws DynamicsError when M is not
/// positive definite there, AnalysisError for constraints the tangent flow
/// is not derived for (require_tangent_flow_constraints(); contacts are
/// ignored: the free motion's J).
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
  detail::require_tangent_flow_constraints(model, "");
  if constexpr (!std::is_same_v<E, M> && detail::bilateral_rows_v<M> == Dynamic && K > 1) {
    if (holonomic_count(model) + pfaffian_count(model) > 0)
      throw AnalysisError(
          "state_jvp: derivatives along a parameter of a model whose constraint rows are counted at run time are "
          "taken one direction at a time (K = 1), not K = " +
          std::to_string(K));
  }
  const E& eval = [&]() -> const E& {
    if constexpr (std::is_same_v<E, M>) {
      return model;
    } else {
      static_assert(std::is_same_v<E, typename M::template with_parameter_type<ad::Jet<double, K, 1>>>,
                    "state_jvp: the seeded model is the model with parameters of type ad::Jet<double, K, 1>");
      return *seeded;
    }
  }();
  if constexpr (constant_mass_matrix_v<M>) {
    detail::constant_mass_jvp<K>(model, eval, q, qd, t, v, qdd, jv);
  } else {
    detail::eom_tangent_jvp<K>(model, eval, q, qd, t, v, qdd, jv);
  }
}

/// q̈ and J_a = ∂q̈/∂(q, q̇) (n × 2n: the columns ∂/∂q_0 … ∂/∂q_{n−1}, then
/// ∂/∂q̇_0 … ∂/∂q̇_{n−1}) at (q, q̇, t): state_jvp() along the 2n unit
/// vectors, kTangentPassDirections of them per pass. Throws DynamicsError
/// when M is not positive definite there, AnalysisError for constraints the
/// tangent flow is not derived for (state_jvp()).
template <class M>
void state_jacobian(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                    const Vec<double, coordinate_count_v<M>>& qd, double t, Vec<double, coordinate_count_v<M>>& qdd,
                    Eigen::Matrix<double, coordinate_count_v<M>, 2 * coordinate_count_v<M>>& jacobian) {
  constexpr int n = coordinate_count_v<M>;
  constexpr int w = std::min(2 * n, kTangentPassDirections);
  for (int first = 0; first < 2 * n; first += w) {
    const int count = std::min(w, 2 * n - first);
    Eigen::Matrix<double, 2 * n, w> unit = Eigen::Matrix<double, 2 * n, w>::Zero();
    for (int c = 0; c < count; ++c) unit(first + c, c) = 1.0;
    Eigen::Matrix<double, n, w> columns;
    state_jvp<w>(model, q, qd, t, unit, qdd, columns);
    jacobian.middleCols(first, count) = columns.leftCols(count);
  }
}

/// ∂p/∂(q, q̇) at (q, q̇, t), p = ∂L/∂q̇: the n × 2n matrix [C, M] with
/// C_ij = ∂²L/∂q̇_i∂q_j and M = ∂²L/∂q̇² (one second-order ad::Jet pass over
/// (q, q̇)). It maps a tangent vector (δq, δq̇) to the canonical one
/// (δq, δp = C δq + M δq̇). With `lagrangian_gradient`, ∂L/∂q (n values,
/// N or N·m) from the same pass.
template <class M>
void momentum_jacobian(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                       const Vec<double, coordinate_count_v<M>>& qd, double t,
                       Eigen::Matrix<double, coordinate_count_v<M>, 2 * coordinate_count_v<M>>& out,
                       Vec<double, coordinate_count_v<M>>* lagrangian_gradient = nullptr) {
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
  if (lagrangian_gradient != nullptr)
    for (int i = 0; i < n; ++i) (*lagrangian_gradient)[i] = l.g[i];
}

}  // namespace lagrangian
