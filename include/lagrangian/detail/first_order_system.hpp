#pragma once
// The first-order system x = [q; q̇], ẋ = [q̇; q̈(q, q̇, t)] that simulate()
// hands to Boost.Odeint, with its state storage, and the sub-step used to
// locate events inside steps of steppers without dense output.

#include <algorithm>
#include <array>
#include <cstdint>
#include <type_traits>
#include <vector>

#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

#include "lagrangian/constraints.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian::detail {

/// Storage of the first-order state x = [q; q̇]: a fixed array, or a vector
/// for run-time sized models.
template <int N>
struct state_buffer {
  using type = std::array<double, 2 * N>;
};
template <>
struct state_buffer<Dynamic> {
  using type = std::vector<double>;
};
template <int N>
using StateBuffer = typename state_buffer<N>::type;

template <int N>
StateBuffer<N> make_buffer(int n) {
  if constexpr (N == Dynamic) {
    return StateBuffer<N>(static_cast<std::size_t>(2 * n), 0.0);
  } else {
    (void)n;
    return StateBuffer<N>{};
  }
}

/// h = p·q̇ − L, with p returned too.
template <class M>
double energy_and_momenta(const M& model, const Vec<double, M::dof>& q, const Vec<double, M::dof>& qd, double t,
                          Vec<double, M::dof>& p) {
  p = momenta(model, q, qd, t);
  return p.dot(qd) - lagrangian_value(model, q, qd, t);
}

/// Splits x = [q; q̇] (2n values) into q and q̇.
template <int N>
void split_state(const double* x, Vec<double, N>& q, Vec<double, N>& qd) {
  const auto n = q.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    q[i] = x[i];
    qd[i] = x[n + i];
  }
}

/// Per-run state of a constrained model's right-hand side.
template <class M>
struct ConstraintContext {
  ConstraintWorkspace<M::dof, constraint_count_v<M>> cw;
  double omega = 0;               ///< Baumgarte rate (1/s), 0 when not stabilising that way
  ActiveSet active = all_active;  ///< unilateral constraints in contact
};

/// The first-order system ẋ = f(x, t) handed to Odeint, counting evaluations.
template <class M>
struct FirstOrderSystem {
  static constexpr int n = M::dof;
  const M* model;
  Workspace<n>* ws;
  std::uint64_t* evaluations;
  std::conditional_t<has_constraints_v<M>, ConstraintContext<M>*, None> constraints{};

  template <class X, class DX>
  void operator()(const X& x, DX& dxdt, double t) const {
    evaluate(x, dxdt, t);
  }
  template <class X, class DX>
  [[gnu::always_inline]] inline void evaluate(const X& x, DX& dxdt, double t) const {
    if constexpr (n == Dynamic) {
      const int size = static_cast<int>(ws->scratch_q.size());
      split_state(x.data(), ws->scratch_q, ws->scratch_qd);
      evaluate_into(ws->scratch_q, ws->scratch_qd, t, ws->scratch_qdd);
      for (int i = 0; i < size; ++i) {
        dxdt[i] = x[size + i];
        dxdt[size + i] = ws->scratch_qdd[i];
      }
    } else {
      Vec<double, n> q;
      Vec<double, n> qd;
      split_state(x.data(), q, qd);
      Vec<double, n> qdd;  // a local: a store to the workspace and reload costs ~35% here
      evaluate_into(q, qd, t, qdd);
      for (int i = 0; i < n; ++i) {
        dxdt[i] = qd[i];
        dxdt[n + i] = qdd[i];
      }
    }
    ++*evaluations;
  }
  void evaluate_into(const Vec<double, n>& q, const Vec<double, n>& qd, double t, Vec<double, n>& qdd) const {
    if constexpr (has_constraints_v<M>) {
      constrained_accelerations(*model, *ws, constraints->cw, q, qd, t, qdd, constraints->omega, constraints->active);
    } else if constexpr (has_explicit_accelerations_v<M>) {
      model->accelerations(q, qd, t, qdd);
    } else {
      accelerations(*model, *ws, q, qd, t, qdd);
    }
  }
};

/// The same system, always inlined into the stepper's stages. For rk4 and the
/// controlled steppers without dense output (cash_karp54, fehlberg78) the
/// compiler otherwise left it an out-of-line call from each stage, with the
/// state passed through memory: 13 % more instructions than Odeint's own
/// loop with the same hand-coded q̈ (docs/performance.md); likewise for rk4
/// (22 % more before, 11 % after). Not for dopri5 with an AD model: there
/// the larger stage code stopped the step itself being inlined (+5 %). (A
/// flattened loop, flat_loop_v below, inlines the plain system as well.)
template <class M>
struct InlinedSystem {
  FirstOrderSystem<M> sys;
  template <class X, class DX>
  [[gnu::always_inline]] inline void operator()(const X& x, DX& dxdt, double t) const {
    sys.evaluate(x, dxdt, t);
  }
};

/// A copy of the model in the run loop's own frame, which `sys` then points
/// to, for models that are trivially copyable and small. Stores to the state
/// and the stages cannot alias a local object, so the compiler may keep the
/// model's parameters in registers across the right-hand-side calls that it
/// inlines instead of reloading them after every store (as it does for a
/// hand-written Odeint system held by value). Other models are used in place.
template <class M>
class LoopModel {
 public:
  static constexpr bool copied = std::is_trivially_copyable_v<M> && sizeof(M) <= 512;
  explicit LoopModel(FirstOrderSystem<M>& sys) : copy_(init(sys)) {
    if constexpr (copied) sys.model = &copy_;
  }
  LoopModel(const LoopModel&) = delete;
  LoopModel& operator=(const LoopModel&) = delete;

 private:
  using Copy = std::conditional_t<copied, M, None>;
  static Copy init(const FirstOrderSystem<M>& sys) {
    if constexpr (copied) {
      return *sys.model;
    } else {
      (void)sys;
      return None{};
    }
  }
  Copy copy_;
};

/// The state inside an accepted step for steppers without dense output:
/// Runge–Kutta–Fehlberg 7(8) from the step's start (t0, x0) to t, with its
/// error controlled to the run's rtol and atol (used only while locating an
/// event). A single uncontrolled step would do for short steps, but
/// Bulirsch–Stoer takes steps of a large fraction of an orbit, over which one
/// 7(8) step is far less accurate than the tolerance the run asked for (the
/// work-precision bench found this: Kepler with periapsis events lost up to
/// three orders of magnitude).
template <class M, class X>
struct SubStep {
  const FirstOrderSystem<M>& sys;
  X x0;
  double t0;
  double rtol, atol;
  void operator()(double t, double* out) const {
    if (t == t0) {
      std::copy(x0.begin(), x0.end(), out);
      return;
    }
    namespace odeint = boost::numeric::odeint;
    using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<X>>;
    Controlled stepper{typename Controlled::error_checker_type(atol, rtol)};
    X x = x0;
    double tc = t0, dt = t - t0;
    while (tc < t) {
      const bool last = tc + dt >= t;
      double dt_try = last ? t - tc : dt;
      if (stepper.try_step(sys, x, tc, dt_try) == odeint::success) {
        if (last) tc = t;
        dt = dt_try;
      } else {
        dt = dt_try;
        if (!(dt > 0) || tc + dt == tc) break;  // underflow: keep what we have
      }
    }
    std::copy(x.begin(), x.end(), out);
  }
};

}  // namespace lagrangian::detail
