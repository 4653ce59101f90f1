#pragma once
/// \file dynamics.hpp
/// Quantities derived from a model by automatic differentiation.
///
/// For L(q, q̇, t) = T − V the Euler–Lagrange equations
///   d/dt ∂L/∂q̇ − ∂L/∂q = Q
/// expand to
///   M(q, q̇, t) q̈ = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t + Q,     M = ∂²L/∂q̇²,
/// where Q holds the non-conservative generalized forces, including
/// Q = −∂D/∂q̇ from a Rayleigh function D. Units: M in kg (or kg·m² for
/// angles), forces in N (or N·m), q̈ in m/s² (or rad/s²).
///
/// Derivatives come from two forward-mode passes per evaluation:
///  1. T (or L) with a second-order Jet in n + 1 directions: the n velocity
///     directions and the single path direction (δq, δt) = (q̇, 1). Its
///     Hessian holds M (velocity × velocity block) and the mixed term
///     (∂²L/∂q̇∂q) q̇ + ∂²L/∂q̇∂t (velocity × path column): a directional
///     derivative, never a third-order tensor.
///  2. L with a first-order Jet in the n position directions: ∂L/∂q.
/// V does not depend on q̇, so it enters only pass 2.
///
/// Every function takes a const model and (in the fast form) a Workspace
/// that the caller owns; nothing is allocated on the heap per call.

#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "lagrangian/ad.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"

#if defined(__GNUC__)
#define LAGRANGIAN_FLATTEN __attribute__((flatten))
#else
#define LAGRANGIAN_FLATTEN
#endif

namespace lagrangian {

/// Scratch space and results of one dynamics evaluation for a model with n
/// coordinates. Allocate one per thread and reuse it for every call.
template <int N>
struct Workspace {
  Mat<double, N> mass;                ///< M = ∂²L/∂q̇² (kg, kg·m, kg·m²)
  Vec<double, N> momenta;             ///< p = ∂L/∂q̇
  Vec<double, N> dL_dq;               ///< ∂L/∂q
  Vec<double, N> mixed;               ///< (∂²L/∂q̇∂q) q̇ + ∂²L/∂q̇∂t
  Vec<double, N> forces;              ///< Q, non-conservative generalized forces
  Vec<double, N> rhs;                 ///< ∂L/∂q − mixed + Q
  Vec<double, N> accelerations;       ///< q̈ = M⁻¹ rhs
  double lagrangian = 0;              ///< L
  Eigen::LLT<Mat<double, N>> cholesky;  ///< factorisation of M
};

/// Relative pivot below which the mass matrix is reported singular:
/// min(diag L_chol)² / max(diag L_chol)² < 1e-14 (L_chol the Cholesky factor).
inline constexpr double singular_mass_tolerance = 1e-14;

namespace detail {

template <int N>
std::string describe_state(const Vec<double, N>& q, const Vec<double, N>& qd, double t) {
  std::ostringstream os;
  os.precision(17);
  os << "t = " << t << ", q = [";
  for (int i = 0; i < N; ++i) os << (i ? ", " : "") << q[i];
  os << "], qd = [";
  for (int i = 0; i < N; ++i) os << (i ? ", " : "") << qd[i];
  os << "]";
  return os.str();
}

template <class M, class S>
S lagrangian_of(const M& model, const Vec<S, M::dof>& q, const Vec<S, M::dof>& qd, const S& t) {
  if constexpr (has_kinetic_for<M, S> && has_potential_for<M, S>) {
    return S(model.kinetic(q, qd, t)) - S(model.potential(q, t));
  } else {
    return S(model.lagrangian(q, qd, t));
  }
}

/// Pass 1: M, p and the mixed term from T (or L) in n + 1 second-order directions.
template <class M>
LAGRANGIAN_FLATTEN void velocity_pass(const M& model, Workspace<M::dof>& ws, const Vec<double, M::dof>& q,
                                      const Vec<double, M::dof>& qd, double t) {
  constexpr int n = M::dof;
  using J = ad::Jet<double, n + 1, 2>;
  Vec<J, n> qj;
  Vec<J, n> qdj;
  for (int k = 0; k < n; ++k) {
    qj[k] = J(q[k]);
    qj[k].g[n] = qd[k];  // path direction δq = q̇
    qdj[k] = J::variable(qd[k], k);
  }
  J tj(t);
  tj.g[n] = 1.0;  // path direction δt = 1
  J e;
  if constexpr (has_kinetic_for<M, J>) {
    e = J(model.kinetic(qj, qdj, tj));
  } else {
    e = J(model.lagrangian(qj, qdj, tj));
  }
  for (int i = 0; i < n; ++i) {
    ws.momenta[i] = e.g[i];
    ws.mixed[i] = e.hess(i, n);
    for (int j = i; j < n; ++j) {
      ws.mass(i, j) = e.hess(i, j);
      ws.mass(j, i) = ws.mass(i, j);
    }
  }
}

/// Pass 2: ∂L/∂q and L in n first-order directions.
template <class M>
LAGRANGIAN_FLATTEN void position_pass(const M& model, Workspace<M::dof>& ws, const Vec<double, M::dof>& q,
                                      const Vec<double, M::dof>& qd, double t) {
  constexpr int n = M::dof;
  using J = ad::Jet<double, n, 1>;
  Vec<J, n> qj;
  Vec<J, n> qdj;
  for (int k = 0; k < n; ++k) {
    qj[k] = J::variable(q[k], k);
    qdj[k] = J(qd[k]);
  }
  const J l = lagrangian_of(model, qj, qdj, J(t));
  ws.lagrangian = l.v;
  for (int i = 0; i < n; ++i) ws.dL_dq[i] = l.g[i];
}

/// Q = generalized forces − ∂D/∂q̇.
template <class M>
LAGRANGIAN_FLATTEN void force_pass(const M& model, Workspace<M::dof>& ws, const Vec<double, M::dof>& q,
                                   const Vec<double, M::dof>& qd, double t) {
  constexpr int n = M::dof;
  if constexpr (has_generalized_forces_v<M>) {
    ws.forces = model.generalized_forces(q, qd, t);
  } else {
    ws.forces.setZero();
  }
  if constexpr (has_dissipation_v<M>) {
    using J = ad::Jet<double, n, 1>;
    Vec<J, n> qj;
    Vec<J, n> qdj;
    for (int k = 0; k < n; ++k) {
      qj[k] = J(q[k]);
      qdj[k] = J::variable(qd[k], k);
    }
    const J d = J(model.dissipation(qj, qdj));
    for (int i = 0; i < n; ++i) ws.forces[i] -= d.g[i];
  }
}

}  // namespace detail

/// Evaluates M, p, ∂L/∂q, Q and the right-hand side of M q̈ = rhs into `ws`
/// without solving for q̈.
template <class M>
void evaluate(const M& model, Workspace<M::dof>& ws, const Vec<double, M::dof>& q, const Vec<double, M::dof>& qd,
              double t) {
  check_model<M>();
  detail::velocity_pass(model, ws, q, qd, t);
  detail::position_pass(model, ws, q, qd, t);
  detail::force_pass(model, ws, q, qd, t);
  ws.rhs = ws.dL_dq - ws.mixed + ws.forces;
}

/// Generalized accelerations q̈ (m/s² or rad/s²) at (q, q̇, t), written into
/// ws.accelerations and returned by reference. Throws DynamicsError naming the
/// state when M is singular or not positive definite.
template <class M>
const Vec<double, M::dof>& accelerations(const M& model, Workspace<M::dof>& ws, const Vec<double, M::dof>& q,
                                         const Vec<double, M::dof>& qd, double t) {
  evaluate(model, ws, q, qd, t);
  ws.cholesky.compute(ws.mass);
  bool ok = ws.cholesky.info() == Eigen::Success;
  if (ok) {
    const auto d = ws.cholesky.matrixLLT().diagonal();
    const double lo = d.minCoeff();
    const double hi = d.maxCoeff();
    ok = std::isfinite(lo) && std::isfinite(hi) && lo > 0 && (lo * lo) >= singular_mass_tolerance * (hi * hi);
  }
  if (!ok) {
    std::ostringstream os;
    os.precision(17);
    os << "mass matrix M = d2L/dqd2 is singular or not positive definite at " << detail::describe_state(q, qd, t)
       << "; M = [";
    for (int i = 0; i < M::dof; ++i)
      for (int j = 0; j < M::dof; ++j) os << (i || j ? (j ? ", " : "; ") : "") << ws.mass(i, j);
    os << "]";
    throw DynamicsError(os.str());
  }
  ws.accelerations = ws.cholesky.solve(ws.rhs);
  return ws.accelerations;
}

/// Convenience form of accelerations() that allocates its own workspace.
template <class M>
Vec<double, M::dof> accelerations(const M& model, const Vec<double, M::dof>& q, const Vec<double, M::dof>& qd,
                                  double t = 0.0) {
  Workspace<M::dof> ws;
  return accelerations(model, ws, q, qd, t);
}

/// Generalized momenta p = ∂L/∂q̇ (kg·m/s, or kg·m²/s for angles).
template <class M>
Vec<double, M::dof> momenta(const M& model, const Vec<double, M::dof>& q, const Vec<double, M::dof>& qd,
                            double t = 0.0) {
  check_model<M>();
  constexpr int n = M::dof;
  using J = ad::Jet<double, n, 1>;
  Vec<J, n> qj = q.template cast<J>();
  Vec<J, n> qdj;
  for (int k = 0; k < n; ++k) qdj[k] = J::variable(qd[k], k);
  const J l = detail::lagrangian_of(model, qj, qdj, J(t));
  Vec<double, n> p;
  for (int i = 0; i < n; ++i) p[i] = l.g[i];
  return p;
}

/// Mass matrix M = ∂²L/∂q̇² (kg, kg·m, kg·m²).
template <class M>
Mat<double, M::dof> mass_matrix(const M& model, const Vec<double, M::dof>& q, const Vec<double, M::dof>& qd,
                                double t = 0.0) {
  check_model<M>();
  Workspace<M::dof> ws;
  detail::velocity_pass(model, ws, q, qd, t);
  return ws.mass;
}

/// The Lagrangian L(q, q̇, t) = T − V (J).
template <class M>
double lagrangian_value(const M& model, const Vec<double, M::dof>& q, const Vec<double, M::dof>& qd,
                        double t = 0.0) {
  check_model<M>();
  return detail::lagrangian_of(model, q, qd, t);
}

/// ∂L/∂t at (q, q̇, t) (W). Zero for all states ⇔ the Jacobi integral is conserved.
template <class M>
double lagrangian_time_derivative(const M& model, const Vec<double, M::dof>& q, const Vec<double, M::dof>& qd,
                                  double t) {
  check_model<M>();
  using J = ad::Jet<double, 1, 1>;
  const Vec<J, M::dof> qj = q.template cast<J>();
  const Vec<J, M::dof> qdj = qd.template cast<J>();
  return detail::lagrangian_of(model, qj, qdj, J::variable(t, 0)).g[0];
}

/// The energy function (Jacobi integral) h = p·q̇ − L (J). Conserved when
/// ∂L/∂t = 0 and Q = 0, even when T + V is not (moving constraints).
template <class M>
double energy_function(const M& model, const Vec<double, M::dof>& q, const Vec<double, M::dof>& qd,
                       double t = 0.0) {
  check_model<M>();
  constexpr int n = M::dof;
  using J = ad::Jet<double, n, 1>;
  const Vec<J, n> qj = q.template cast<J>();
  Vec<J, n> qdj;
  for (int k = 0; k < n; ++k) qdj[k] = J::variable(qd[k], k);
  const J l = detail::lagrangian_of(model, qj, qdj, J(t));
  double h = -l.v;
  for (int i = 0; i < n; ++i) h += l.g[i] * qd[i];
  return h;
}

/// Kinetic energy T (J); only for models that give T and V separately.
template <class M>
  requires has_kinetic_potential_v<M>
double kinetic_energy(const M& model, const Vec<double, M::dof>& q, const Vec<double, M::dof>& qd, double t = 0.0) {
  return model.kinetic(q, qd, t);
}

/// Potential energy V (J); only for models that give T and V separately.
template <class M>
  requires has_kinetic_potential_v<M>
double potential_energy(const M& model, const Vec<double, M::dof>& q, double t = 0.0) {
  return model.potential(q, t);
}

/// Total mechanical energy T + V (J); only for models that give T and V.
template <class M>
  requires has_kinetic_potential_v<M>
double total_energy(const M& model, const Vec<double, M::dof>& q, const Vec<double, M::dof>& qd, double t = 0.0) {
  return model.kinetic(q, qd, t) + model.potential(q, t);
}

/// Non-conservative generalized forces Q = Q_model − ∂D/∂q̇ at a state.
template <class M>
Vec<double, M::dof> nonconservative_forces(const M& model, const Vec<double, M::dof>& q,
                                           const Vec<double, M::dof>& qd, double t = 0.0) {
  check_model<M>();
  Workspace<M::dof> ws;
  detail::force_pass(model, ws, q, qd, t);
  return ws.forces;
}

}  // namespace lagrangian
