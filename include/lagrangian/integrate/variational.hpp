#pragma once
/// \file variational.hpp
/// A variational integrator for any Lagrangian L(q, q̇, t) (separable or
/// not), with holonomic constraints held by discrete multipliers.
///
/// Position–momentum form. From (q_k, p_k) at t_k a step of h (s) solves
///
///   p_k + D1 L_d(q_k, q_{k+1}) + G(q_k)ᵀ λ = 0,     g(q_{k+1}, t_{k+1}) = 0        (1)
///
/// for q_{k+1} and the discrete multipliers λ (N·s per unit of ∇g: an
/// impulse over the step), then sets the momentum
///
///   p_{k+1} = D2 L_d(q_k, q_{k+1}) + G(q_{k+1})ᵀ μ                                (2)
///
/// (D2 L_d evaluated as p_k + D1 L_d + D2 L_d + G(q_k)ᵀλ, equal by (1), so
/// that the rounding of q_{k+1} does not enter the momentum)
/// with μ such that the velocity q̇_{k+1} of that momentum — the solution of
/// the continuous Legendre transform ∂L/∂q̇(q_{k+1}, q̇_{k+1}, t_{k+1}) = p_{k+1}
/// — satisfies the velocity constraint G(q_{k+1}) q̇_{k+1} + ∂g/∂t = 0. This
/// is RATTLE when L_d is the trapezoidal rule and L is natural, and without
/// constraints (λ = μ = 0) it is the discrete Euler–Lagrange equation
/// D2 L_d(q_{k−1}, q_k) + D1 L_d(q_k, q_{k+1}) = 0. L_d is midpoint or
/// trapezoidal (discrete.hpp).
///
/// Properties: the map (q_k, p_k) → (q_{k+1}, p_{k+1}) is symplectic; the
/// momentum of a coordinate that L does not contain (and no constraint
/// involves) is conserved exactly — D1 + D2 of L_d vanish in that slot —
/// so it changes only by the Newton residual; the energy error of an
/// autonomous system stays bounded (no drift) for step sizes that resolve
/// the motion; constraints hold to the Newton tolerance at every step.
///
/// Newton's method: (1) is solved with the Jacobian [[D12 L_d, G(q_k)ᵀ],
/// [G(q_{k+1}), 0]] from AD (second-order Jets over (q_k, q_{k+1})) by a
/// complete orthogonal decomposition (minimum-norm steps, so duplicated
/// constraints are harmless); the start is q_k + h q̇_k. It stops when the
/// update satisfies ‖Δq‖∞ ≤ tolerance · (1 + ‖q‖∞); the Legendre transform
/// (2) is solved likewise with [[M, −Gᵀ], [G, 0]]. When `max_iterations`
/// do not converge, or the iterate is not finite, the step throws
/// DynamicsError naming t, the state and the last update — never a NaN state.

#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>

#include <Eigen/Core>

#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/mechanics/detail/min_norm_solver.hpp"
#include "lagrangian/integrate/discrete.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// Stopping rule of the Newton solves of an implicit step.
struct NewtonSettings {
  double tolerance = 1e-12;  ///< ‖Δq‖∞ ≤ tolerance · (1 + ‖q‖∞) (and likewise for q̇)
  int max_iterations = 50;   ///< a step needing more fails with a DynamicsError
};

/// True when the variational integrator can run the model: a compile-time
/// number of coordinates, holonomic constraints only (no Pfaffian or
/// unilateral ones).
template <class M>
inline constexpr bool variational_supported_v =
    coordinate_count_v<M> != Dynamic && pfaffian_count_v<M> == 0 && unilateral_count_v<M> == 0;

/// The integrator of the file comment for one model. Holds (q, p, t) and
/// the velocity q̇ that belongs to p.
template <class M>
class VariationalIntegrator {
 public:
  static constexpr int n = coordinate_count_v<M>;
  static constexpr int m = holonomic_count_v<M>;
  static_assert(variational_supported_v<M>,
                "lagrangian: the variational integrator needs a compile-time number of coordinates and no Pfaffian or unilateral "
                "constraints");

  /// Starts from a state consistent with the constraints at time t.
  VariationalIntegrator(const M& model, const State<n>& start, double t, DiscreteRule rule = DiscreteRule::midpoint,
                        NewtonSettings newton = {})
      : model_(model), rule_(rule), newton_(newton), q_(start.q), qd_(start.qd), t_(t) {
    check_model<M>();
    p_ = momenta(model_, q_, qd_, t_);
  }

  /// One step of h (s) from the current time. Throws DynamicsError when a
  /// Newton solve fails (the state is left at the step's start).
  void step(double h) {
    const Vec<double, n> q1 = solve_positions(h);
    solve_momentum(q1, h);
    q_ = q1;
    t_ += h;
  }

  const Vec<double, n>& q() const { return q_; }    ///< positions q_k
  const Vec<double, n>& qd() const { return qd_; }  ///< velocities from the Legendre transform of p_k
  const Vec<double, n>& p() const { return p_; }    ///< momenta p_k (kg·m/s or kg·m²/s)
  double t() const { return t_; }                   ///< t_k (s)
  /// Newton iterations so far (both solves of every step).
  std::uint64_t newton_iterations() const { return iterations_; }
  /// Evaluations of L (or T and V) on AD numbers so far.
  std::uint64_t lagrangian_evaluations() const { return evaluations_; }

 private:
  using Kkt = Eigen::Matrix<double, n + m, n + m>;
  using KktVec = Vec<double, n + m>;

  /// Newton's method on a saddle-point system F(x, y) = 0 in x ∈ Rⁿ and
  /// the multipliers y ∈ Rᵐ: `assemble(x, y, K, F)` fills the residual F and
  /// its Jacobian K = ∂F/∂(x, y) at the iterate. Stops when the update of x
  /// satisfies ‖Δx‖∞ ≤ tolerance · (1 + ‖x‖∞); fails with a DynamicsError
  /// naming `what` on a non-finite iterate or after max_iterations.
  template <class Assemble>
  void newton(Vec<double, n>& x, Vec<double, m>& y, double h, const char* what, Assemble&& assemble) {
    double last = 0;
    for (int it = 0; it < newton_.max_iterations; ++it) {
      Kkt k = Kkt::Zero();
      KktVec f;
      assemble(x, y, k, f);
      ++evaluations_;
      ++iterations_;
      const KktVec dz = solve(k, f, x, t_ + h, what);
      x -= dz.template head<n>();
      if constexpr (m > 0) y -= dz.template tail<m>();
      last = dz.template head<n>().template lpNorm<Eigen::Infinity>();
      if (!x.allFinite()) fail(what, "gave a non-finite iterate", h, last);
      if (last <= newton_.tolerance * (1.0 + x.template lpNorm<Eigen::Infinity>())) return;
    }
    fail(what, "did not converge", h, last);
  }

  /// q_{k+1} and λ from (1), starting at q_k + h q̇_k.
  Vec<double, n> solve_positions(double h) {
    const double t1 = t_ + h;
    Vec<double, n> q1 = q_ + h * qd_;
    Vec<double, m> lambda = Vec<double, m>::Zero();
    [[maybe_unused]] Eigen::Matrix<double, m, n> g0;
    if constexpr (m > 0) g0 = constraint_state(model_, q_, Vec<double, n>::Zero().eval(), t_).jacobian;
    newton(q1, lambda, h, "discrete Euler-Lagrange equations",
           [&](const Vec<double, n>& x, const Vec<double, m>& y, Kkt& k, KktVec& f) {
             const DiscreteLagrangian<n> dl = discrete_lagrangian_derivatives(model_, q_, x, t_, h, rule_);
             k.template topLeftCorner<n, n>() = dl.d12;
             f.template head<n>() = p_ + dl.d1;
             if constexpr (m > 0) {
               const auto cs = constraint_state(model_, x, Vec<double, n>::Zero().eval(), t1);
               f.template head<n>() += g0.transpose() * y;
               f.template tail<m>() = cs.position;
               k.template topRightCorner<n, m>() = g0.transpose();
               k.template bottomLeftCorner<m, n>() = cs.jacobian;
             }
           });
    if constexpr (m > 0) impulse_ = g0.transpose() * lambda;
    return q1;
  }

  /// p_{k+1} from D2 L_d (and μ), q̇_{k+1} from the Legendre transform.
  void solve_momentum(const Vec<double, n>& q1, double h) {
    const double t1 = t_ + h;
    const DiscreteLagrangian<n> dl = discrete_lagrangian_derivatives(model_, q_, q1, t_, h, rule_);
    ++evaluations_;
    // p̂ = D2 L_d(q_k, q_{k+1}), written as p_k + D1 + D2 + G(q_k)ᵀλ (equal
    // at the solution of (1)): the rounding of q_{k+1} then does not leak
    // into the momentum, and a slot that L does not contain (D1 + D2 = 0
    // exactly in the AD arithmetic) keeps its momentum to the last bit.
    Vec<double, n> p_hat = p_ + dl.d1 + dl.d2;
    if constexpr (m > 0) p_hat += impulse_;
    Vec<double, n> v = (q1 - q_) / h;
    Vec<double, m> mu = Vec<double, m>::Zero();
    newton(v, mu, h, "Legendre transform p = dL/dqd",
           [&](const Vec<double, n>& x, const Vec<double, m>& y, Kkt& k, KktVec& f) {
             detail::eom_pass(model_, ws_, q1, x, t1);
             k.template topLeftCorner<n, n>() = ws_.mass;
             f.template head<n>() = ws_.momenta - p_hat;
             if constexpr (m > 0) {
               const auto cs = constraint_state(model_, q1, x, t1);
               f.template head<n>() -= cs.jacobian.transpose() * y;
               f.template tail<m>() = cs.velocity;
               k.template topRightCorner<n, m>() = -cs.jacobian.transpose();
               k.template bottomLeftCorner<m, n>() = cs.jacobian;
             }
           });
    if constexpr (m > 0) {
      p_ = p_hat + constraint_state(model_, q1, v, t1).jacobian.transpose() * mu;
    } else {
      p_ = p_hat;
    }
    qd_ = v;
  }

  KktVec solve(const Kkt& k, const KktVec& f, const Vec<double, n>& x, double t1, const char* what) {
    if (!k.allFinite() || !f.allFinite()) {
      std::ostringstream os;
      os.precision(17);
      os << "variational step: non-finite Jacobian or residual of the " << what << " at t = " << t1 << " (iterate ["
         << x.transpose() << "]) from " << detail::describe_state(q_, qd_, t_);
      throw DynamicsError(os.str());
    }
    const int rank = kkt_.factorize(k.data());
    if (rank < n) {
      std::ostringstream os;
      os.precision(17);
      os << "variational step: the Jacobian of the " << what << " is singular (rank " << rank << " of " << n + m
         << ") at " << detail::describe_state(q_, qd_, t_) << "; the mass matrix is singular or the step is too large";
      throw DynamicsError(os.str());
    }
    KktVec z;
    kkt_.solve(f.data(), z.data());
    return z;
  }

  [[noreturn]] void fail(const char* what, const char* how, double h, double last) const {
    std::ostringstream os;
    os.precision(17);
    os << "variational step of h = " << h << " s failed: the " << what << " " << how << " after at most "
       << newton_.max_iterations << " Newton iterations (last update " << last << ", tolerance "
       << newton_.tolerance << ") from " << detail::describe_state(q_, qd_, t_) << "; try a smaller dt";
    throw DynamicsError(os.str());
  }

  const M& model_;
  DiscreteRule rule_;
  NewtonSettings newton_;
  Vec<double, n> q_, qd_, p_;
  double t_;
  std::uint64_t iterations_ = 0, evaluations_ = 0;
  Workspace<n> ws_;                          ///< the Legendre transform's pass over L
  detail::MinNormSolver kkt_{n + m};          ///< the Newton steps' saddle-point solves
  [[maybe_unused]] Vec<double, n> impulse_ = Vec<double, n>::Zero();  ///< G(q_k)ᵀλ of the last position solve
};

}  // namespace lagrangian
