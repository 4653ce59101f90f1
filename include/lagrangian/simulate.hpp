#pragma once
/// \file simulate.hpp
/// Integration of the AD-derived equations of motion with Boost.Odeint.
///
/// The state is x = [q; q̇] (length 2n) and the first-order system is
///   ẋ = [q̇; q̈(q, q̇, t)],
/// with q̈ from accelerations(). `simulate` drives an Odeint stepper chosen by
/// name, sends samples to an observer, watches the energy function and the
/// momenta of cyclic coordinates, and returns a RunReport.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <boost/numeric/odeint/stepper/bulirsch_stoer.hpp>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_cash_karp54.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>
#include <boost/numeric/odeint/stepper/symplectic_rkn_sb3a_mclachlan.hpp>
#include <boost/numeric/odeint/stepper/velocity_verlet.hpp>

#include "lagrangian/constraints.hpp"
#include "lagrangian/detail/roots.hpp"
#include "lagrangian/detail/stiff.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/fpe.hpp"
#include "lagrangian/impact.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/observers.hpp"
#include "lagrangian/report.hpp"
#include "lagrangian/variational.hpp"

namespace lagrangian {

/// Indices of coordinates whose momenta are conserved: cyclic (∂L/∂q_i = 0,
/// Q_i = 0) and, for constrained models, untouched by every constraint (the
/// column i of the constraint Jacobian is zero), at the given state and at
/// three nearby states (a fixed, deterministic perturbation). This is
/// a sampled check: a coordinate that drops out of L only on those states
/// would be misreported, which is why the run reports the momentum drift so
/// the claim can be seen to hold.
template <class M>
std::vector<int> cyclic_coordinates(const M& model, const State<M::dof>& s, double t = 0.0);

/// True when ∂L/∂t = 0 at the given (state, t) and at three nearby states and
/// later times (sampled check, same caveat as cyclic_coordinates()).
template <class M>
bool is_autonomous(const M& model, const State<M::dof>& s, double t = 0.0);

/// True when the model declares `static constexpr bool separable`.
template <class M>
concept declares_separable = requires {
  { M::separable } -> std::convertible_to<bool>;
};

/// Why the model is not separable, or an empty string when it is: the
/// symplectic steppers need L = ½ q̇ᵀ M q̇ − V(q) with a constant mass matrix
/// M, no constraints, no generalized forces or dissipation and ∂L/∂t = 0.
/// A model may declare `static constexpr bool separable = true;` (trusted)
/// or `false`; otherwise the property is checked at the given state and at
/// three nearby states (M equal to 1e-12 relative, p = M q̇ to 1e-12
/// relative: no velocity-linear terms; sampled, like cyclic_coordinates()).
template <class M>
std::string separability_problem(const M& model, const State<M::dof>& s, double t = 0.0);

/// Time tolerance of located events (impacts, lift-offs, watched events):
/// the TOMS 748 bracket is narrowed to event_time_tolerance · max(1 s, |t|),
/// i.e. 1e-12 relative with an absolute floor of 1e-12 s.
inline constexpr double event_time_tolerance = 1e-12;

namespace detail {

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

/// The sampled states used by cyclic_coordinates() and is_autonomous().
template <int N>
std::array<State<N>, 4> probe_states(const State<N>& s) {
  std::array<State<N>, 4> out{s, s, s, s};
  std::uint64_t lcg = 0x9E3779B97F4A7C15ull;
  auto next = [&lcg]() {
    lcg = lcg * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(lcg >> 11) * 0x1.0p-53 - 0.5;  // in [-0.5, 0.5)
  };
  for (int k = 1; k < 4; ++k) {
    out[k] = s;
    for (int i = 0; i < s.q.size(); ++i) {
      out[k].q[i] += 0.1 * next() * (1.0 + std::abs(s.q[i]));
      out[k].qd[i] += 0.1 * next() * (1.0 + std::abs(s.qd[i]));
    }
  }
  return out;
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

/// True when every constraint is scleronomic and workless: C q̇ + c has
/// c = 0 (no ∂g/∂t, no a(q, t)) at the sampled states and times.
template <class M>
bool constraints_workless(const M& model, const State<M::dof>& s, double t) {
  if constexpr (!has_constraints_v<M>) {
    (void)model;
    (void)s;
    (void)t;
    return true;
  } else {
    const auto probes = probe_states(s);
    for (std::size_t k = 0; k < probes.size(); ++k) {
      const double tk = t + 0.37 * static_cast<double>(k) * (1.0 + std::abs(t));
      const auto cs = constraint_state(model, probes[k].q, Vec<double, M::dof>::Zero().eval(), tk);
      if (!cs.velocity.isZero(0.0)) return false;
    }
    return true;
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

template <class O>
concept observer_with_begin = requires(O& o, const Columns& c) { o.begin(c); };
template <class O>
concept observer_with_finish = requires(O& o) { o.finish(); };

/// A non-owning, type-erased observer: the run loops are compiled once per
/// model, not once per (model, observer) pair. One indirect call per sample.
template <int N>
struct ObserverRef {
  void* object = nullptr;
  void (*sample)(void*, const Sample<N>&) = nullptr;
  void (*begin)(void*, const Columns&) = nullptr;

  template <class O>
  static ObserverRef of(O& o) {
    ObserverRef r;
    r.object = &o;
    r.sample = [](void* p, const Sample<N>& s) { (*static_cast<O*>(p))(s); };
    if constexpr (observer_with_begin<O>) r.begin = [](void* p, const Columns& c) { static_cast<O*>(p)->begin(c); };
    return r;
  }
  void operator()(const Sample<N>& s) const { sample(object, s); }
};

/// Bookkeeping shared by all stepper loops: samples, drift monitors, limits.
template <class M, class Observer = ObserverRef<M::dof>>
class RunState {
 public:
  static constexpr int n = M::dof;
  /// The model declares contacts or watched events (the event code is compiled only then).
  static constexpr bool has_events_v = unilateral_count_v<M> > 0 || event_count_v<M> > 0;

  RunState(const M& model, const SimulationOptions& opt, Observer& obs, RunReport& report)
      : model_(model),
        opt_(opt),
        obs_(obs),
        report_(report),
        size_(model_size(model)),
        buf_(make_buffer<n>(size_)) {}

  /// Sets up the monitors and emits the first sample. Contacts that touch
  /// and approach at t0 are resolved first (impacts at t0); the state the
  /// run continues from is returned.
  State<n> start(State<n> x0) {
    Columns columns{coordinate_names(model_), {}, has_kinetic_potential_v<M>};
    if constexpr (has_constraints_v<M>) start_constraints(x0, columns);
    if constexpr (event_count_v<M> > 0) specs_ = event_specs(model_);
    if constexpr (has_particles_v<M>) {
      int k = 0;
      for (const Particle& part : model_.particles()) {
        if (!(part.mass > 0) || !std::isfinite(part.mass))
          throw ParameterError(model_name(model_) + ": particle " + std::to_string(k) + " has mass " +
                               std::to_string(part.mass) + "; it must be positive and finite");
        for (int i : part.axes)
          if (i < -1 || i >= size_)
            throw ParameterError(model_name(model_) + ": particle " + std::to_string(k) + " names coordinate " +
                                 std::to_string(i) + ", outside [0, " + std::to_string(size_) + ")");
        ++k;
      }
    }
    if constexpr (has_events_v) event_buf_.assign(static_cast<std::size_t>(2 * size_), 0.0);
    const std::vector<int> cyclic = cyclic_coordinates(model_, x0, opt_.t0);
    cyclic_.assign(cyclic.begin(), cyclic.end());
    Vec<double, n> p(size_);
    h0_ = energy_and_momenta(model_, x0.q, x0.qd, opt_.t0, p);  // after any impact at t0
    pending_shifts_.clear();
    double scale = std::abs(h0_);
    if constexpr (has_kinetic_potential_v<M>) {
      const double t0 = model_.kinetic(x0.q, x0.qd, opt_.t0);
      const double v0 = model_.potential(x0.q, opt_.t0);
      e0_ = t0 + v0;
      scale = std::max(scale, std::abs(t0) + std::abs(v0));
      report_.has_total_energy = true;
      report_.total_energy_initial = e0_;
    }
    report_.energy_scale = scale > 0 && std::isfinite(scale) ? scale : 1.0;
    report_.energy_initial = h0_;
    for (int i : cyclic_) report_.conserved_momenta.push_back({columns.coordinates[static_cast<std::size_t>(i)], p[i], 0, 0});
    if (obs_.begin) obs_.begin(obs_.object, columns);
    next_output_index_ = 1;
    update_next_output();
    last_t_ = opt_.t0;
    emit(opt_.t0, x0.q.data(), x0.qd.data());
    return x0;
  }

  /// Next time a sample is due (infinity when sampling every step or never).
  double next_output_time() const { return next_output_; }

  /// Called after every accepted step ending at t with state x (2n values).
  /// `interpolate(t_out, buffer)` fills the state at an earlier time when the
  /// stepper has dense output; otherwise steps end on output times.
  ///
  /// Inlined into the stepper loops: one combined test per step (state
  /// finite, max_steps not reached, no sample due); all else, including the
  /// errors, is in accepted_slow().
  template <class Interp>
  [[gnu::always_inline]] inline void accepted(double t_old, double t, const double* x, Interp&& interpolate) {
    ++report_.steps;
    recent_steps_[report_.steps % 2] = t - t_old;
    last_t_ = t;
    // No sample is due while t + tol < next output time, with the tolerance
    // of accepted_slow(), tol = 1e-12 max(|t|, Δt_out) ≤ 1e-12 (|t| + Δt_out).
    const bool finite = all_finite(x);
    const bool within = report_.steps <= opt_.max_steps;
    const bool no_sample = sample_due_ > t + 1e-12 * std::abs(t) + sample_slack_;
    if (!(finite & within & no_sample)) [[unlikely]]
      accepted_slow(t_old, t, x, interpolate);
  }

  /// Constrained models: projection (when chosen) and residual monitoring
  /// after an accepted step ending at t with state x; true when x changed.
  bool stabilize(double* x, double t, bool allow_projection = true) {
    if constexpr (!has_constraints_v<M>) {
      (void)x;
      (void)t;
      (void)allow_projection;
      return false;
    } else {
      ConstraintReport& cr = report_.constraints;
      constexpr bool only_contacts = holonomic_count_v<M> + pfaffian_count_v<M> == 0;
      if (only_contacts && (active() & unilateral_mask_v<M>) == 0) return false;  // free flight: nothing to hold
      Vec<double, n> q, qd;
      split_state(x, q, qd);
      bool changed = false;
      if (allow_projection && opt_.stabilization == Stabilization::projection) {
        const auto start = std::chrono::steady_clock::now();
        try {
          cr.projection_iterations += static_cast<std::uint64_t>(
              project_positions(model_, q, t, opt_.projection_tolerance, 20, active()));
        } catch (const ConstraintError& e) {
          throw SimulationError(std::string("projection failed: ") + e.what(), t);
        }
        project_velocities(model_, ws_, q, qd, t, active());
        ++cr.projections;
        for (int i = 0; i < n; ++i) {
          changed = changed || x[i] != q[i] || x[n + i] != qd[i];
          x[i] = q[i];
          x[n + i] = qd[i];
        }
        cr.stabilization_time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      }
      auto cs = constraint_state(model_, q, qd, t);
      for (int j = 0; j < unilateral_count_v<M>; ++j) {
        const int row = holonomic_count_v<M> + j;
        if (!((active() >> j) & 1u) && cs.position[row] < -1e-9 * (1.0 + q.template lpNorm<Eigen::Infinity>())) {
          std::ostringstream os;
          os.precision(17);
          os << "unilateral constraint " << cr.names[static_cast<std::size_t>(row)] << " is violated at t = " << t
             << " (g = " << cs.position[row]
             << ") without a located contact event; the step passed through the contact (try a smaller dt or "
                "tighter tolerances)";
          throw SimulationError(os.str(), t);
        }
      }
      if constexpr (holonomic_count_v<M> + pfaffian_count_v<M> > 0) monitor_conditioning(cs, t);
      drop_inactive<M>(cs, active());
      const double pos = position_rows_v<M> > 0
                             ? cs.position.head(position_rows_v<M>).template lpNorm<Eigen::Infinity>()
                             : 0.0;
      const double vel = cs.velocity.template lpNorm<Eigen::Infinity>();
      cr.max_position_residual = std::max(cr.max_position_residual, pos);
      cr.max_velocity_residual = std::max(cr.max_velocity_residual, vel);
      cr.final_position_residual = pos;
      cr.final_velocity_residual = vel;
      return changed;
    }
  }
  /// Tracks σ_r/σ_1 of the bilateral constraint Jacobian (r = rank at t0)
  /// at accepted steps and samples, and warns once when it falls below
  /// 1e-3: a singular configuration is near (the multipliers grow without
  /// bound there, and the motion may switch assembly branches).
  template <class CS>
  void monitor_conditioning(CS cs, double t) {
    ConstraintReport& cr = report_.constraints;
    drop_inactive<M>(cs, ActiveSet{0});
    std::vector<double>& sv = singular_values_;
    detail::numeric_rank(cs.jacobian, &sv);
    const int r = cr.initial_rank;
    if (r < 1 || sv.empty() || !(sv[0] > 0)) return;
    const double ratio = static_cast<std::size_t>(r) <= sv.size() ? sv[static_cast<std::size_t>(r - 1)] / sv[0] : 0.0;
    if (ratio < cr.min_conditioning) {
      cr.min_conditioning = ratio;
      cr.min_conditioning_time = t;
    }
    if (ratio < 1e-3 && !warned_conditioning_) {
      warned_conditioning_ = true;
      std::ostringstream os;
      os.precision(6);
      os << "near-singular configuration at t = " << t << ": the constraint Jacobian's singular values fall to "
         << ratio << " of the largest (rank " << r << " at t0); multipliers may be large there";
      cr.warnings.push_back(os.str());
    }
  }
  void extra_rhs_evaluation() {
    if constexpr (has_constraints_v<M>) ++report_.constraints.extra_rhs_evaluations;
  }
  void attach(ConstraintContext<M>* ctx) { ctx_ = ctx; }
  ActiveSet active() const { return ctx_ ? ctx_->active : all_active; }

  /// Events in the step just taken from (t_old, x_old) to (t, x): lift-off
  /// of resting contacts (their multiplier turns negative), contacts closing
  /// (the gap φ falls through zero, or dips below zero and back inside the
  /// step), and watched event functions crossing zero in their direction.
  /// Each crossing is located with Boost.Math's TOMS 748 on the step's
  /// continuous extension `interp` (dopri5's dense output, or a Fehlberg 7(8)
  /// sub-step from the step's start), the bracket narrowed to
  /// event_time_tolerance · max(1 s, |t|). The earliest event is applied:
  /// the step end moves to it (t and x are overwritten) and true is
  /// returned, so the caller restarts its stepper there; later events in
  /// the step are found by the following steps, so events are handled in
  /// time order. Truly simultaneous contacts are resolved together by
  /// resolve_contacts().
  template <class Interp>
  bool handle_events(double t_old, const double* x_old, double& t, double* x, const Interp& interp) {
    if constexpr (!has_events_v) {
      (void)t_old, (void)x_old, (void)t, (void)x, (void)interp;
      return false;
    } else {
      return handle_events_erased(t_old, x_old, t, x, interpolator(interp));  // one instantiation per model
    }
  }
  // Instantiated only for models with events (called from handle_events).
  bool handle_events_erased(double t_old, const double* x_old, double& t, double* x, Interpolator interp) {
    auto root = [](const auto& f, double a, double b, double fa, double fb) {
      return bracket_root(time_function(f), a, b, fa, fb, event_time_tolerance);
    };
    // Candidate: kind 0 release, 1 contact (at the step start), 2 contact, 3 watched.
    int best_kind = -1, best_index = -1;
    double best_t = std::numeric_limits<double>::infinity();
    auto consider = [&](double tc, int kind, int index) {
      if (tc < best_t) {
        best_t = tc;
        best_kind = kind;
        best_index = index;
      }
    };
    std::vector<double>& buf = event_buf_;
    if constexpr (unilateral_count_v<M> > 0) {
      const ActiveSet act = ctx_->active;
      // Lift-off: an active contact whose multiplier is negative at the step end.
      if ((act & unilateral_mask_v<M>) != 0) {
        auto multipliers_at = [&](const double* xs, double ts) {
          Vec<double, n> q, qd, qdd;
          split_state(xs, q, qd);
          constrained_accelerations(model_, ws_, cw_, q, qd, ts, qdd, 0.0, act);
          return cw_.multipliers;
        };
        const auto lam_end = multipliers_at(x, t);
        for (int j = 0; j < unilateral_count_v<M>; ++j) {
          const int row = holonomic_count_v<M> + j;
          if (!((act >> j) & 1u) || !(lam_end[row] < 0)) continue;
          auto f = [&](double ts) {
            if (ts == t) return lam_end[row];
            interp(ts, buf.data());
            return multipliers_at(buf.data(), ts)[row];
          };
          const double fa = f(t_old);
          double tj = t_old;
          if (fa > 0) tj = root(f, t_old, t, fa, lam_end[row]).second;
          consider(tj, 0, j);  // upper end: λ < 0 from there on
        }
      }
      // Closing contacts among the inactive ones.
      Vec<double, unilateral_count_v<M>> ga, ra, gb, rb;
      gaps_at(x_old, t_old, ga, ra);
      gaps_at(x, t, gb, rb);
      const double touch = contact_touch_tolerance(x);
      for (int j = 0; j < unilateral_count_v<M>; ++j) {
        if ((act >> j) & 1u) continue;
        if (ga[j] < -touch) {
          std::ostringstream os;
          os.precision(17);
          os << "contact " << contact_name(j) << " is penetrated at t = " << t_old << " (gap " << ga[j]
             << ") without a located closing; the run was stopped";
          throw SimulationError(os.str(), t_old);
        }
        // φ_j and φ̇_j at a time inside the step.
        auto gap_rate = [&](double ts) {
          if (ts == t) return std::pair{gb[j], rb[j]};
          if (ts == t_old) return std::pair{ga[j], ra[j]};
          interp(ts, buf.data());
          Vec<double, unilateral_count_v<M>> g, r;
          gaps_at(buf.data(), ts, g, r);
          return std::pair{g[j], r[j]};
        };
        auto gap = [&](double ts) { return gap_rate(ts).first; };
        auto rate = [&](double ts) { return gap_rate(ts).second; };
        // The bracket [lo, hi] of a closing: φ(lo) > 0 > φ(hi).
        double lo = t_old, hi = t;
        bool crossing = ga[j] > 0 && gb[j] < 0;
        auto rate_root = [&] {
          const auto r = root(rate, t_old, t, ra[j], rb[j]);
          return 0.5 * (r.first + r.second);
        };
        if (!crossing && ga[j] >= 0 && gb[j] >= 0 && ra[j] < 0 && rb[j] > 0) {
          hi = rate_root();  // a dip inside the step: below zero at the gap's minimum?
          crossing = gap(hi) < 0;
        } else if (!crossing && ga[j] <= 0 && ra[j] > 0 && gb[j] < 0 && rb[j] < 0) {
          lo = rate_root();  // leaves the contact and comes back within the step
          crossing = gap(lo) > 0;
        }
        if (crossing) {
          const double tj = root(gap, lo, hi, gap(lo), gap(hi)).first;
          // A slow touch that stays within the tolerance is not an impact.
          if (-rate(tj) <= opt_.contact_touch_speed && gb[j] >= -touch) continue;
          consider(tj, 2, j);  // lower end: φ ≥ 0, just before contact
        } else if ((ga[j] <= touch && ra[j] < -opt_.contact_touch_speed) ||
                   (ga[j] < 0 && gb[j] < -touch && gb[j] < ga[j])) {
          consider(t_old, 1, j);  // touching at the step start and approaching or pressing in
        }
      }
    }
    if constexpr (event_count_v<M> > 0) {
      Vec<double, event_count_v<M>> fa = watched_at(x_old, t_old), fb = watched_at(x, t);
      for (int k = 0; k < event_count_v<M>; ++k) {
        const Direction d = specs_[static_cast<std::size_t>(k)].direction;
        const bool falls = fa[k] > 0 && fb[k] <= 0, rises = fa[k] < 0 && fb[k] >= 0;
        if (!((falls && d != Direction::rising) || (rises && d != Direction::falling))) continue;
        auto f = [&](double ts) {
          if (ts == t) return fb[k];
          interp(ts, buf.data());
          return watched_at(buf.data(), ts)[k];
        };
        consider(root(f, t_old, t, fa[k], fb[k]).second, 3, k);
      }
    }
    if (best_kind < 0) return false;
    // Guard against an event that changes nothing being found again and again.
    if (best_t == last_event_time_ && best_t == t_old) {
      if (++events_without_progress_ > 100) {
        std::ostringstream os;
        os.precision(17);
        os << "event handling made no progress at t = " << best_t << " (more than 100 events at this instant)";
        throw SimulationError(os.str(), best_t);
      }
    } else {
      events_without_progress_ = 0;
    }
    last_event_time_ = best_t;
    if (best_t < t) {
      interp(best_t, buf.data());
      std::copy(buf.begin(), buf.end(), x);
      t = best_t;
    }
    if (best_kind == 0) {
      if constexpr (unilateral_count_v<M> > 0) {
        ctx_->active &= ~(ActiveSet{1} << best_index);
        log_simple(EventKind::release, contact_name(best_index), t, x);
      }
    } else if (best_kind == 1 || best_kind == 2) {
      resolve_contacts(x, t, best_index);
    } else {
      const EventSpec& s = specs_[static_cast<std::size_t>(best_index)];
      log_simple(EventKind::watched, s.name, t, x);
      if (s.action == EventAction::stop) {
        log_simple(EventKind::stop, s.name, t, x);
        stopped_ = true;
        report_.stopped_at = t;
        report_.stopped_by = s.name;
      }
    }
    return true;
  }

  /// True once a watched event with action stop has fired (a compile-time
  /// false without events, so the loops carry no extra branch).
  bool stopped() const {
    if constexpr (has_events_v) {
      return stopped_;
    } else {
      return false;
    }
  }

  /// Resolves every contact that is touching (|φ| within the touch
  /// tolerance) and approaching faster than contact_touch_speed at (x, t),
  /// one pair at a time: the one approaching fastest first, by Newton's law
  /// of restitution (apply_impact), until none approaches (the sequential
  /// rule for simultaneous impacts; each step conserves momentum, and kinetic
  /// energy when e = 1). Zeno accumulations are resolved plastically (see
  /// SimulationOptions::zeno_speed_ratio). Afterwards the contacts that took
  /// part (and `trigger`) are resting (active) when they do not separate,
  /// and active contacts that separate are released.
  void resolve_contacts(double* x, double t, int trigger) {
    if constexpr (unilateral_count_v<M> > 0) {
      constexpr int u = unilateral_count_v<M>;
      Vec<double, n> q, qd;
      split_state(x, q, qd);
      const double touch = contact_touch_tolerance(x);
      Vec<double, u> g, r;
      std::array<bool, u> involved{};
      std::array<bool, u> rested{};
      involved[static_cast<std::size_t>(trigger)] = true;
      const int max_impacts = 1000 * u;
      int count = 0;
      for (;; ++count) {
        contact_gaps(model_, q, qd, t, g, r);
        int j = -1;
        for (int i = 0; i < u; ++i)
          if ((i == trigger || g[i] <= touch) && r[i] < -opt_.contact_touch_speed && (j < 0 || r[i] < r[j])) j = i;
        if (j < 0) break;
        if (count >= max_impacts) {
          std::ostringstream os;
          os.precision(17);
          os << "simultaneous impacts at t = " << t << " did not settle after " << max_impacts
             << " pairwise impacts (contact " << contact_name(j) << " still approaching at " << -r[j] << ")";
          throw SimulationError(os.str(), t);
        }
        const std::size_t js = static_cast<std::size_t>(j);
        if constexpr (!has_restitution_v<M>) {
          std::ostringstream os;
          os.precision(17);
          os << "contact " << contact_name(j) << " closed at t = " << t << " with approach speed " << -r[j]
             << "; the model declares no restitution(), so the impact cannot be resolved";
          throw SimulationError(os.str(), t);
        }
        const double approach = -r[j];
        // An accumulation needs the forces to press the contact shut
        // (d²φ/dt² < 0 in free motion); free bodies that graze never rest.
        const bool zeno = (approach <= opt_.zeno_speed_ratio * approach_max_[js] ||
                           t - last_impact_[js] <= opt_.zeno_min_interval * std::max(1.0, std::abs(t))) &&
                          gap_acceleration(q, qd, t, j) < 0;
        const double e = zeno ? 0.0 : restitution_[js];
        const double h_before = energy_function(model_, q, qd, t);
        ImpactResult<n> res;
        try {
          res = apply_impact(model_, ws_, q, qd, t, j, e);
        } catch (const DynamicsError& err) {
          throw SimulationError(std::string("impact failed: ") + err.what(), t);
        }
        approach_max_[js] = std::max(approach_max_[js], approach);
        last_impact_[js] = t;
        involved[js] = true;
        rested[js] = zeno;
        EventRecord rec;
        rec.t = t;
        rec.kind = zeno ? EventKind::rest : EventKind::impact;
        rec.name = contact_name(j);
        rec.impulse = res.impulse;
        rec.approach_speed = res.approach_speed;
        rec.separation_speed = res.separation_speed;
        rec.kinetic_energy_before = res.kinetic_energy_before;
        rec.kinetic_energy_after = res.kinetic_energy_after;
        report_.events.push_back(rec);
        if (!zeno) ++report_.impacts;
        report_.impact_energy_loss += res.kinetic_energy_before - res.kinetic_energy_after;
        shift_reference_energy(q, qd, t, h_before, res.kinetic_energy_after - res.kinetic_energy_before);
      }
      contact_gaps(model_, q, qd, t, g, r);
      ActiveSet& active = ctx_->active;
      for (int j = 0; j < u; ++j) {
        const std::size_t js = static_cast<std::size_t>(j);
        const ActiveSet bit = ActiveSet{1} << j;
        const bool resting = (j == trigger || g[j] <= touch) && r[j] <= opt_.contact_touch_speed;
        if ((active & bit) && !resting) {
          active &= ~bit;
          log_simple(EventKind::release, contact_name(j), t, x);
        } else if (!(active & bit) && involved[js] && resting) {
          active |= bit;
          if (!rested[js]) log_simple(EventKind::rest, contact_name(j), t, x);
        }
      }
      for (int i = 0; i < n; ++i) x[n + i] = qd[i];
    } else {
      (void)x, (void)t, (void)trigger;
    }
  }

  void rejected(double t, double dt) {
    ++report_.rejected_steps;
    if (++consecutive_rejections_ > 1000 || !(dt > 1e-15 * std::max(1.0, std::abs(t)))) {
      std::ostringstream os;
      os.precision(17);
      os << "step size underflow at t = " << t << " (dt = " << dt << " after " << consecutive_rejections_
         << " rejected steps); the problem may be stiff (try method rosenbrock4) or singular";
      throw SimulationError(os.str(), t);
    }
  }
  void reset_rejections() { consecutive_rejections_ = 0; }
  /// The larger of the last two accepted step sizes (s): the step size at
  /// the end of the run even when the last step was cut short to end on t_end.
  double recent_step() const { return std::max(recent_steps_[0], recent_steps_[1]); }

  /// Final bookkeeping: sample the end state if not done yet.
  /// x: the state at the end of the last accepted step (2n values).
  void finish(const double* x) {
    report_.t_final = last_t_;
    if constexpr (has_events_v) apply_pending_shifts(last_t_);
    if (opt_.output_interval != 0 && last_emitted_ != last_t_) emit(last_t_, x, x + size_);
    report_.energy_drift_final = std::abs(h_last_ - h0_) / report_.energy_scale;
    if (report_.has_total_energy) report_.total_energy_drift_final = std::abs(e_last_ - e0_) / report_.energy_scale;
    report_.energy_final = h_last_;
  }

 private:
  void emit(double t, const double* q, const double* qd) {
    if constexpr (has_events_v) apply_pending_shifts(t);
    Sample<n> s;
    s.t = t;
    s.q.resize(size_);
    s.qd.resize(size_);
    for (int i = 0; i < size_; ++i) {
      s.q[i] = q[i];
      s.qd[i] = qd[i];
    }
    Vec<double, n> p(size_);
    s.energy = energy_and_momenta(model_, s.q, s.qd, t, p);
    h_last_ = s.energy;
    report_.energy_drift_max = std::max(report_.energy_drift_max, std::abs(s.energy - h0_) / report_.energy_scale);
    if constexpr (has_kinetic_potential_v<M>) {
      s.total_energy = model_.kinetic(s.q, s.qd, t) + model_.potential(s.q, t);
      e_last_ = s.total_energy;
      report_.total_energy_drift_max =
          std::max(report_.total_energy_drift_max, std::abs(s.total_energy - e0_) / report_.energy_scale);
    }
    if constexpr (has_constraints_v<M>) sample_constraints(s);
    if constexpr (has_particles_v<M>) sample_particles(s);
    if constexpr (has_reference_v<M>) {
      if (s.t == opt_.t0) {
        reference_initial_.q = s.q;
        reference_initial_.qd = s.qd;
      }
      const State<n> ref = model_.reference(reference_initial_, s.t - opt_.t0);
      report_.has_reference = true;
      report_.reference_error_final = (s.q - ref.q).template lpNorm<Eigen::Infinity>();
      report_.reference_error_max = std::max(report_.reference_error_max, report_.reference_error_final);
    }
    for (std::size_t k = 0; k < cyclic_.size(); ++k) {
      MomentumDrift& d = report_.conserved_momenta[k];
      d.final_abs_drift = std::abs(p[cyclic_[k]] - d.initial);
      d.max_abs_drift = std::max(d.max_abs_drift, d.final_abs_drift);
    }
    obs_(s);
    ++report_.samples;
    last_emitted_ = t;
  }

  /// P = Σ m v and L = Σ m (r − r₀) × v of a particle system at a sample.
  void sample_particles(const Sample<n>& s) {
    std::array<double, 3> P{}, L{};
    const auto& r0 = opt_.angular_momentum_point;
    for (const Particle& part : model_.particles()) {
      std::array<double, 3> r{}, v{};
      for (int a = 0; a < 3; ++a) {
        const int i = part.axes[static_cast<std::size_t>(a)];
        if (i >= 0) {
          r[static_cast<std::size_t>(a)] = s.q[i] - r0[static_cast<std::size_t>(a)];
          v[static_cast<std::size_t>(a)] = s.qd[i];
        } else {
          r[static_cast<std::size_t>(a)] = -r0[static_cast<std::size_t>(a)];
        }
      }
      for (int a = 0; a < 3; ++a) P[static_cast<std::size_t>(a)] += part.mass * v[static_cast<std::size_t>(a)];
      L[0] += part.mass * (r[1] * v[2] - r[2] * v[1]);
      L[1] += part.mass * (r[2] * v[0] - r[0] * v[2]);
      L[2] += part.mass * (r[0] * v[1] - r[1] * v[0]);
    }
    if (!report_.has_particles) {
      report_.has_particles = true;
      report_.linear_momentum_initial = P;
      report_.angular_momentum_initial = L;
    }
    auto dist = [](const std::array<double, 3>& a, const std::array<double, 3>& b) {
      return std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) + (a[2] - b[2]) * (a[2] - b[2]));
    };
    report_.linear_momentum_drift_final = dist(P, report_.linear_momentum_initial);
    report_.angular_momentum_drift_final = dist(L, report_.angular_momentum_initial);
    report_.linear_momentum_drift_max = std::max(report_.linear_momentum_drift_max, report_.linear_momentum_drift_final);
    report_.angular_momentum_drift_max =
        std::max(report_.angular_momentum_drift_max, report_.angular_momentum_drift_final);
  }

  void start_constraints(State<n>& x0, Columns& columns) {
    if constexpr (has_constraints_v<M>) {
      ConstraintReport& cr = report_.constraints;
      report_.constrained = true;
      cr.names = constraint_names(model_);
      columns.constraints = cr.names;
      cr.stabilization = to_string(opt_.stabilization);
      cr.baumgarte_omega = opt_.stabilization == Stabilization::baumgarte ? opt_.baumgarte_omega : 0.0;
      const DofReport dof = dof_report(model_, x0, opt_.t0);
      cr.initial_rank = cr.min_rank = dof.velocity_rank;
      if constexpr (M::dof == Dynamic) static_assert(M::dof != Dynamic, "constraints need a compile-time dof");
      // Full rank leaves no motion unless the constraints themselves move (a
      // prescribed, rheonomic motion with 0 degrees of freedom).
      if (dof.holonomic_rank >= n && constraints_workless(model_, x0, opt_.t0))
        throw ConstraintError("the holonomic constraints fix all " + std::to_string(n) +
                              " coordinates (rank " + std::to_string(dof.holonomic_rank) + "): no motion is left");
      for (const auto& r : dof.redundant)
        cr.warnings.push_back("constraint " + r + " is redundant at t0 (its Jacobian row depends on earlier rows)");
      auto cs = constraint_state(model_, x0.q, x0.qd, opt_.t0);
      const double qs = 1.0 + x0.q.template lpNorm<Eigen::Infinity>();
      const double vs = 1.0 + x0.qd.template lpNorm<Eigen::Infinity>();
      ActiveSet active = 0;
      if constexpr (unilateral_count_v<M> > 0) {
        restitution_ = restitution_coefficients(model_);
        approach_max_.fill(0.0);
        last_impact_.fill(-std::numeric_limits<double>::infinity());
        bool approaching = false;
        for (int j = 0; j < unilateral_count_v<M>; ++j) {
          const int row = holonomic_count_v<M> + j;
          const double g = cs.position[row], gd = cs.velocity[row];
          if (g < -1e-9 * qs) {
            std::ostringstream os;
            os.precision(17);
            os << "unilateral constraint " << cr.names[static_cast<std::size_t>(row)] << " is violated at t0: g = " << g
               << " (the bodies overlap); start on or outside the admissible side";
            throw ConstraintError(os.str());
          }
          if (std::abs(g) <= 1e-9 * qs) {
            if (gd < -opt_.contact_touch_speed) {
              approaching = true;  // an impact at t0
            } else if (gd <= opt_.contact_touch_speed) {
              active |= ActiveSet{1} << j;  // resting contact
            }
          }
        }
        if (ctx_) ctx_->active = active;
        if (approaching) {
          if constexpr (!has_restitution_v<M>) {
            throw ConstraintError("a unilateral constraint is approached at t0 (an impact) but the model declares no "
                                  "restitution(); start at rest relative to it, or declare restitution()");
          }
          StateBuffer<n> xb = make_buffer<n>(size_);
          for (int i = 0; i < size_; ++i) {
            xb[static_cast<std::size_t>(i)] = x0.q[i];
            xb[static_cast<std::size_t>(size_ + i)] = x0.qd[i];
          }
          for (int j = 0; j < unilateral_count_v<M>; ++j) {
            const int row = holonomic_count_v<M> + j;
            if (std::abs(cs.position[row]) <= 1e-9 * qs && cs.velocity[row] < -opt_.contact_touch_speed) {
              resolve_contacts(xb.data(), opt_.t0, j);
              break;
            }
          }
          split_state(xb.data(), x0.q, x0.qd);
          active = ctx_ ? ctx_->active : active;
          cs = constraint_state(model_, x0.q, x0.qd, opt_.t0);
        }
      }
      if (ctx_) ctx_->active = active;
      drop_inactive<M>(cs, active);
      for (int i = 0; i < constraint_count_v<M>; ++i) {
        const bool holo = i < position_rows_v<M>;
        if ((holo && !(std::abs(cs.position[i]) <= 1e-9 * qs)) || !(std::abs(cs.velocity[i]) <= 1e-9 * vs)) {
          std::ostringstream os;
          os.precision(17);
          os << "initial state violates constraint " << cr.names[static_cast<std::size_t>(i)] << ": "
             << (holo ? "g = " : "") << (holo ? cs.position[i] : 0.0) << (holo ? ", " : "")
             << "velocity residual = " << cs.velocity[i]
             << "; use consistent_initial_state() to find the nearest consistent state";
          throw ConstraintError(os.str());
        }
      }
    }
  }
  void sample_constraints(Sample<n>& s) {
    if constexpr (has_constraints_v<M>) {
      Vec<double, n> qdd;
      constrained_accelerations(model_, ws_, cw_, s.q, s.qd, s.t, qdd, 0.0, active());
      s.multipliers = cw_.multipliers;
      s.constraint_forces = cw_.constraint_forces;
      auto cs = constraint_state(model_, s.q, s.qd, s.t);
      if constexpr (holonomic_count_v<M> + pfaffian_count_v<M> > 0) monitor_conditioning(cs, s.t);
      drop_inactive<M>(cs, ActiveSet{0});  // rank of the bilateral constraints
      const int rank = detail::numeric_rank(cs.jacobian);
      ConstraintReport& cr = report_.constraints;
      if (rank < cr.min_rank) {
        std::ostringstream os;
        os.precision(10);
        os << "rank of the constraint Jacobian dropped from " << cr.initial_rank << " to " << rank << " at t = " << s.t
           << " (singular configuration)";
        cr.warnings.push_back(os.str());
        cr.min_rank = rank;
      }
    }
  }


  /// Gaps within this of zero count as touching: 1e-9 (1 + ‖q‖∞).
  double contact_touch_tolerance(const double* x) const {
    double qmax = 0;
    for (int i = 0; i < size_; ++i) qmax = std::max(qmax, std::abs(x[i]));
    return 1e-9 * (1.0 + qmax);
  }
  template <class G>
  void gaps_at(const double* x, double t, G& g, G& r) const {
    Vec<double, n> q, qd;
    split_state(x, q, qd);
    contact_gaps(model_, q, qd, t, g, r);
  }
  Vec<double, event_count_v<M>> watched_at(const double* x, double t) const {
    if constexpr (event_count_v<M> > 0) {
      Vec<double, n> q, qd;
      split_state(x, q, qd);
      return model_.events(q, qd, t);
    } else {
      (void)x, (void)t;
      return {};
    }
  }
  std::string contact_name(int j) const {
    return report_.constraints.names[static_cast<std::size_t>(holonomic_count_v<M> + j)];
  }
  /// d²φ_j/dt² = G_j q̈ + γ_j with q̈ from the current active set (contact j
  /// itself inactive): negative when the forces press the contact shut.
  double gap_acceleration(const Vec<double, n>& q, const Vec<double, n>& qd, double t, int j) {
    if constexpr (unilateral_count_v<M> > 0) {
      Vec<double, n> qdd;
      constrained_accelerations(model_, ws_, cw_, q, qd, t, qdd, 0.0, ctx_->active & ~(ActiveSet{1} << j));
      const auto cs = constraint_state(model_, q, qd, t);
      const int row = holonomic_count_v<M> + j;
      return cs.jacobian.row(row).dot(qdd) + cs.gamma[row];
    } else {
      (void)q, (void)qd, (void)t, (void)j;
      return 0.0;
    }
  }

  /// An event without an impulse: logs it with the kinetic energy at x.
  void log_simple(EventKind kind, const std::string& name, double t, const double* x) {
    EventRecord rec;
    rec.t = t;
    rec.kind = kind;
    rec.name = name;
    Vec<double, n> q, qd;
    split_state(x, q, qd);
    if constexpr (!has_kinetic_potential_v<M>) evaluate(model_, ws_, q, qd, t);  // M for ½ q̇ᵀMq̇
    rec.kinetic_energy_before = rec.kinetic_energy_after = detail::kinetic_for_log(model_, ws_, q, qd, t);
    report_.events.push_back(rec);
  }
  /// After an impact: the energy references move by the energy the impact
  /// took, so the drift monitors keep measuring integration error only.
  void shift_reference_energy(const Vec<double, n>& q, const Vec<double, n>& qd, double t, double h_before,
                              double kinetic_change) {
    // Applied by emit() from the event time on: samples interpolated
    // before the event still compare with the old references.
    pending_shifts_.push_back({t, energy_function(model_, q, qd, t) - h_before, kinetic_change});
  }
  void apply_pending_shifts(double t) {
    std::size_t k = 0;
    for (; k < pending_shifts_.size() && pending_shifts_[k][0] <= t; ++k) {
      h0_ += pending_shifts_[k][1];
      e0_ += pending_shifts_[k][2];  // an impulse leaves V unchanged: ΔE = ΔT
    }
    pending_shifts_.erase(pending_shifts_.begin(), pending_shifts_.begin() + static_cast<std::ptrdiff_t>(k));
  }

  const M& model_;
  const SimulationOptions& opt_;
  Observer& obs_;
  RunReport& report_;
  Workspace<n> ws_{model_size(model_)};
  std::array<double, unilateral_count_v<M>> restitution_{};
  std::array<double, unilateral_count_v<M>> approach_max_{};
  std::array<double, unilateral_count_v<M>> last_impact_{};
  std::vector<EventSpec> specs_;
  std::vector<double> event_buf_;
  bool stopped_ = false;
  std::vector<std::array<double, 3>> pending_shifts_;
  [[no_unique_address]] std::conditional_t<has_reference_v<M>, State<n>, None> reference_initial_{};  ///< (time, Δh, ΔE) of impacts not yet sampled past
  double last_event_time_ = std::numeric_limits<double>::quiet_NaN();
  int events_without_progress_ = 0;
  ConstraintContext<M>* ctx_ = nullptr;
  [[no_unique_address]] std::conditional_t<has_constraints_v<M>, ConstraintWorkspace<n, constraint_count_v<M>>, None>
      cw_{};
  std::vector<int> cyclic_;
  double h0_ = 0, e0_ = 0, h_last_ = 0, e_last_ = 0;
  std::uint64_t next_output_index_ = 1;
  double next_output_ = std::numeric_limits<double>::infinity();  ///< t0 + next_output_index_ · output_interval
  /// sample_due_: the time from which accepted() must look for due samples
  /// (−∞ when sampling every step, +∞ when sampling only the ends).
  double sample_due_ = std::numeric_limits<double>::infinity();
  double sample_slack_ = 0;  ///< 1e-12 Δt_out (s)
  void update_next_output() {
    constexpr double inf = std::numeric_limits<double>::infinity();
    const double dt_out = opt_.output_interval;
    next_output_ = dt_out > 0 ? opt_.t0 + static_cast<double>(next_output_index_) * dt_out : inf;
    sample_due_ = dt_out > 0 ? next_output_ : dt_out == 0 ? -inf : inf;
    sample_slack_ = dt_out > 0 ? 1e-12 * dt_out : 0.0;
  }
  template <class Interp>
  [[gnu::noinline]] void accepted_slow(double t_old, double t, const double* x, Interp& interpolate) {
    if (!all_finite(x)) throw_non_finite(t_old, t, x);
    if (report_.steps > opt_.max_steps) throw_max_steps(t);
    if (opt_.output_interval == 0) {
      emit(t, x, x + size_);
    } else if (opt_.output_interval > 0) {
      const double tol = 1e-12 * std::max(std::abs(t), opt_.output_interval);
      for (double to = next_output_time(); to <= t + tol && to <= opt_.t_end + tol; to = next_output_time()) {
        ++next_output_index_;
        update_next_output();
        if (std::abs(to - t) <= tol) {
          emit(t, x, x + size_);
        } else {
          interpolate(to, buf_.data());
          emit(to, buf_.data(), buf_.data() + size_);
        }
      }
    }
  }
  [[noreturn, gnu::cold, gnu::noinline]] void throw_non_finite(double t_old, double t, const double* x) const {
    std::ostringstream os;
    os.precision(17);
    os << "non-finite state after the step from t = " << t_old << " to t = " << t << ": x = [";
    for (int k = 0; k < 2 * size_; ++k) os << (k ? ", " : "") << x[k];
    os << "] (q then qd); the run was stopped";
    throw SimulationError(os.str(), t);
  }
  [[noreturn, gnu::cold, gnu::noinline]] void throw_max_steps(double t) const {
    std::ostringstream os;
    os << "max_steps = " << opt_.max_steps << " reached at t = " << t << " before t_end = " << opt_.t_end;
    throw SimulationError(os.str(), t);
  }
  /// All 2n state values finite (the loop's length is known at compile time
  /// for fixed-size models).
  bool all_finite(const double* x) const {
    const int count = n == Dynamic ? 2 * size_ : 2 * n;
    bool finite = true;
    for (int i = 0; i < count; ++i) finite = finite && std::isfinite(x[i]);
    return finite;
  }
  std::uint64_t consecutive_rejections_ = 0;
  std::array<double, 2> recent_steps_{};
  std::vector<double> singular_values_;
  bool warned_conditioning_ = false;
  double last_emitted_ = std::numeric_limits<double>::quiet_NaN();
  double last_t_ = 0;
  int size_;
  StateBuffer<n> buf_;
};

/// True when t has reached t_end up to rounding.
inline bool reached(double t, double t_end) {
  return t_end - t <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(t), std::abs(t_end));
}

/// The explicit Runge–Kutta loops (dopri5, rk4, cash_karp54, fehlberg78,
/// Bulirsch–Stoer) run in a function of their own, which works on its own
/// copies of the state, the stepper and (LoopModel) the model: the compiler
/// then knows that no store in the loop can change the model's parameters or
/// the stepper's coefficients, and keeps them out of the loop, as it does for
/// a hand-written Odeint program. For models that supply q̈ themselves and
/// have no constraints or events, every call in that function is inlined
/// (flatten), the model's `accelerations` in every stage included, whatever
/// the compiler's budget for inlining in the translation unit has left; the
/// rarely taken paths (samples, errors) are marked noinline and stay calls.
/// The instructions per run against raw Odeint with the same hand-coded q̈
/// are in docs/performance.md.
template <class M>
inline constexpr bool flat_loop_v =
    has_explicit_accelerations_v<M> && !has_constraints_v<M> && unilateral_count_v<M> == 0 && event_count_v<M> == 0;

template <class Loop>
[[gnu::noinline]] void run_loop(const Loop& loop) {
  loop();
}

template <class Loop>
[[gnu::noinline, gnu::flatten]] void run_loop_flat(const Loop& loop) {
  loop();
}

template <class M, class Loop>
void run_out_of_line(const Loop& loop) {
  if constexpr (flat_loop_v<M>) {
    run_loop_flat(loop);
  } else {
    run_loop(loop);
  }
}

/// Odeint's controlled stepper `Controlled` with the run's tolerances.
/// (Its constructor copies a default-constructed stepper whose scratch arrays
/// are not initialised yet; g++ warns of that copy once it is inlined.)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
template <class Controlled>
Controlled make_controlled(const SimulationOptions& opt) {
  if constexpr (requires { typename Controlled::error_checker_type; }) {
    return Controlled{typename Controlled::error_checker_type(opt.atol, opt.rtol)};
  } else {
    return Controlled(opt.atol, opt.rtol);  // Bulirsch–Stoer
  }
}
#pragma GCC diagnostic pop

/// Loop for an Odeint controlled stepper without dense output: steps are
/// shortened to land on output times and on t_end.
template <class Controlled, class M, class Observer, class X>
void run_controlled(FirstOrderSystem<M> sys, X& x_io, const SimulationOptions& opt, RunState<M, Observer>& rs) {
  namespace odeint = boost::numeric::odeint;
  constexpr bool events = RunState<M, Observer>::has_events_v;
  Controlled stepper = make_controlled<Controlled>(opt);
  X x = x_io;
  double t = opt.t0;
  double dt = opt.dt;
  const LoopModel<M> loop_model(sys);
  [[maybe_unused]] X x_prev = x;
  while (!reached(t, opt.t_end) && !rs.stopped()) {
    const double limit = std::min(opt.t_end, rs.next_output_time());
    const bool clamped = t + dt > limit;
    double dt_try = clamped ? limit - t : dt;
    const double t_old = t;
    if constexpr (events) x_prev = x;
    if (stepper.try_step(InlinedSystem<M>{sys}, x, t, dt_try) == odeint::success) {
      if (clamped) t = limit;  // land exactly on the output time or t_end
      if constexpr (events) {
        // No state is carried between steps except by Bulirsch–Stoer, which restarts.
        if (rs.handle_events(t_old, x_prev.data(), t, x.data(), SubStep<M, X>{sys, x_prev, t_old, opt.rtol, opt.atol})) {
          if constexpr (requires { stepper.reset(); }) stepper.reset();
        }
      }
      rs.stabilize(x.data(), t);
      rs.reset_rejections();
      rs.accepted(t_old, t, x.data(), [](double, double*) {});
      dt = clamped ? std::max(dt, dt_try) : dt_try;
    } else {
      rs.rejected(t, dt_try);
      dt = dt_try;
    }
  }
  x_io = x;
}

template <class M, class Observer, class X>
void run_dopri5(FirstOrderSystem<M> sys, X& x_io, const SimulationOptions& opt, RunState<M, Observer>& rs) {
  X x = x_io;
  namespace odeint = boost::numeric::odeint;
  using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<X>>;
  constexpr bool events = RunState<M, Observer>::has_events_v;
  Controlled stepper{typename Controlled::error_checker_type(opt.atol, opt.rtol)};
  const LoopModel<M> loop_model(sys);
  X dxdt = x;
  X x_old = x;
  X dxdt_old = x;
  X x_step = x;
  X dxdt_step = x;
  X buf = x;
  double t = opt.t0;
  double dt = opt.dt;
  // Samples between steps and event location need the step's start.
  const bool dense = opt.output_interval > 0 || events;
  sys(x, dxdt, t);
  while (!reached(t, opt.t_end) && !rs.stopped()) {
    const bool clamped = t + dt > opt.t_end;
    double dt_try = clamped ? opt.t_end - t : dt;
    if (dense) {
      x_old = x;
      dxdt_old = dxdt;
    }
    const double t_old = t;
    if (stepper.try_step(sys, x, dxdt, t, dt_try) == odeint::success) {
      if (clamped) t = opt.t_end;
      rs.reset_rejections();
      const double t_new = t;
      const X* x_new = &x;
      const X* deriv_new = &dxdt;
      auto interpolate = [&](double to, double* out) {
        stepper.stepper().calc_state(to, buf, x_old, dxdt_old, t_old, *x_new, *deriv_new, t_new);
        std::copy(buf.begin(), buf.end(), out);
      };
      if constexpr (has_constraints_v<M> || events) {
        if (dense) {
          // The step's own end point, for its dense output after x moves.
          x_step = x;
          dxdt_step = dxdt;
          x_new = &x_step;
          deriv_new = &dxdt_step;
        }
        bool changed = rs.handle_events(t_old, x_old.data(), t, x.data(), interpolate);
        changed = rs.stabilize(x.data(), t) || changed;
        if (changed) {
          sys(x, dxdt, t);  // FSAL: the moved state needs its own derivative
          rs.extra_rhs_evaluation();
        }
      }
      rs.accepted(t_old, t, x.data(), interpolate);
      dt = clamped ? std::max(dt, dt_try) : dt_try;
    } else {
      rs.rejected(t, dt_try);
      dt = dt_try;
    }
  }
  x_io = x;
}

template <class M, class Observer, class X>
void run_rk4(FirstOrderSystem<M> sys, X& x_io, const SimulationOptions& opt, RunState<M, Observer>& rs) {
  X x = x_io;
  namespace odeint = boost::numeric::odeint;
  constexpr bool events = RunState<M, Observer>::has_events_v;
  odeint::runge_kutta4<X> stepper;
  const LoopModel<M> loop_model(sys);
  // Fixed steps of opt.dt; the k-th step ends at t0 + k dt (no accumulated
  // rounding); a step is shortened only to land on an output time or t_end.
  std::uint64_t k = 0;
  double t = opt.t0;
  [[maybe_unused]] X x_prev = x;
  while (!reached(t, opt.t_end) && !rs.stopped()) {
    const double t_grid = opt.t0 + static_cast<double>(k + 1) * opt.dt;
    const double t_next = std::min({t_grid, opt.t_end, rs.next_output_time()});
    const double t_old = t;
    if constexpr (events) x_prev = x;
    stepper.do_step(InlinedSystem<M>{sys}, x, t, t_next - t);
    t = t_next;
    if constexpr (events) rs.handle_events(t_old, x_prev.data(), t, x.data(), SubStep<M, X>{sys, x_prev, t_old, opt.rtol, opt.atol});
    if (t >= t_grid) ++k;  // a step cut at an event leaves the grid point ahead
    rs.stabilize(x.data(), t);
    rs.accepted(t_old, t, x.data(), [](double, double*) {});
  }
  x_io = x;
}

/// The stiff path: odeint's rosenbrock4 (see detail/stiff.hpp). Its Jacobian
/// ∂f/∂x is formed by central differences of the AD-derived right-hand side,
///   J_ij ≈ (f_i(x + h e_j) − f_i(x − h e_j)) / 2h,  h = ∛ε · max(|x_j|, 1),
/// with truncation error O(h²) ≈ 1e-10 relative; ∂f/∂t likewise.
template <class M, class Observer, class X>
void run_rosenbrock4(FirstOrderSystem<M> sys, X& x, const SimulationOptions& opt, RunState<M, Observer>& rs) {
  struct Context {
    FirstOrderSystem<M> sys;
    X xa, fa, fb;
    int m;
  } ctx{sys, x, x, x, static_cast<int>(x.size())};
  StiffSystem stiff{
      &ctx,
      [](void* c, const double* xin, double* dxdt, double t) {
        auto& k = *static_cast<Context*>(c);
        std::copy(xin, xin + k.m, k.xa.begin());
        k.sys(k.xa, k.fa, t);
        std::copy(k.fa.begin(), k.fa.end(), dxdt);
      },
      [](void* c, const double* xin, double* J, double* dfdt, double t) {
        auto& k = *static_cast<Context*>(c);
        const int m = k.m;
        const double cbrt_eps = std::cbrt(std::numeric_limits<double>::epsilon());
        std::copy(xin, xin + m, k.xa.begin());
        for (int j = 0; j < m; ++j) {
          const double h = cbrt_eps * std::max(std::abs(k.xa[j]), 1.0);
          const double xj = k.xa[j];
          k.xa[j] = xj + h;
          k.sys(k.xa, k.fa, t);
          k.xa[j] = xj - h;
          k.sys(k.xa, k.fb, t);
          k.xa[j] = xj;
          for (int i = 0; i < m; ++i) J[i * m + j] = (k.fa[i] - k.fb[i]) / (2 * h);
        }
        const double ht = cbrt_eps * std::max(std::abs(t), 1.0);
        k.sys(k.xa, k.fa, t + ht);
        k.sys(k.xa, k.fb, t - ht);
        for (int i = 0; i < m; ++i) dfdt[i] = (k.fa[i] - k.fb[i]) / (2 * ht);
      }};
  Rosenbrock4Stepper stepper(ctx.m, opt.atol, opt.rtol);
  double t = opt.t0;
  double dt = opt.dt;
  while (!reached(t, opt.t_end) && !rs.stopped()) {
    const double limit = std::min(opt.t_end, rs.next_output_time());
    const bool clamped = t + dt > limit;
    double dt_try = clamped ? limit - t : dt;
    const double t_old = t;
    [[maybe_unused]] const X x_prev = RunState<M, Observer>::has_events_v ? x : X{};
    if (stepper.try_step(stiff, x.data(), t, dt_try)) {
      if (clamped) t = limit;
      if constexpr (RunState<M, Observer>::has_events_v)
        rs.handle_events(t_old, x_prev.data(), t, x.data(), SubStep<M, X>{sys, x_prev, t_old, opt.rtol, opt.atol});
      rs.stabilize(x.data(), t);
      rs.reset_rejections();
      rs.accepted(t_old, t, x.data(), [](double, double*) {});
      dt = clamped ? std::max(dt, dt_try) : dt_try;
    } else {
      rs.rejected(t, dt_try);
      dt = dt_try;
    }
  }
}


/// Cubic Hermite interpolation of [q; q̇] inside a fixed step from (t0, x0)
/// to (t1, x1) (2n values each): q from its end values and slopes q̇, q̇ as
/// the derivative of that cubic. Used only for samples between steps.
inline void hermite_state(double t0, const double* x0, double t1, const double* x1, int size, double t, double* out) {
  const double h = t1 - t0;
  const double s = (t - t0) / h;
  const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s;
  const double h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
  const double d00 = (6 * s * s - 6 * s) / h, d10 = 3 * s * s - 4 * s + 1;
  const double d01 = (-6 * s * s + 6 * s) / h, d11 = 3 * s * s - 2 * s;
  for (int i = 0; i < size; ++i) {
    const double q0 = x0[i], v0 = x0[size + i], q1 = x1[i], v1 = x1[size + i];
    out[i] = h00 * q0 + h10 * h * v0 + h01 * q1 + h11 * h * v1;
    out[size + i] = d00 * q0 + d10 * v0 + d01 * q1 + d11 * v1;
  }
}

/// Fixed-step loop shared by the variational and symplectic steppers: the
/// k-th step ends at t0 + k dt (no accumulated rounding); the last step is
/// shortened to end on t_end. `advance(t, h, x)` takes one step of h from t
/// and writes the new [q; q̇] into x. Samples between steps are interpolated
/// (hermite_state); projection is never applied (these methods keep the
/// constraints themselves), residuals are still monitored.
template <class M, class Observer, class X, class Advance>
void run_fixed_grid(X& x, const SimulationOptions& opt, RunState<M, Observer>& rs, Advance&& advance) {
  std::uint64_t k = 0;
  double t = opt.t0;
  X x_old = x;
  const int size = static_cast<int>(x.size() / 2);
  while (!reached(t, opt.t_end) && !rs.stopped()) {
    const double t_grid = opt.t0 + static_cast<double>(k + 1) * opt.dt;
    const double t_next = reached(t_grid, opt.t_end) || t_grid > opt.t_end ? opt.t_end : t_grid;
    const double t_old = t;
    x_old = x;
    advance(t, t_next - t, x);
    t = t_next;
    ++k;
    rs.stabilize(x.data(), t, false);
    rs.accepted(t_old, t, x.data(),
                [&](double to, double* out) { hermite_state(t_old, x_old.data(), t, x.data(), size, to, out); });
  }
}

/// The variational integrator (variational.hpp) at fixed step opt.dt.
template <class M, class Observer, class X>
void run_variational(const M& model, X& x, const SimulationOptions& opt, RunState<M, Observer>& rs,
                     RunReport& report) {
  if constexpr (!variational_supported_v<M>) {
    (void)model, (void)x, (void)opt, (void)rs, (void)report;
    throw OptionError("unreachable: variational refused earlier");
  } else {
    constexpr int n = M::dof;
    State<n> s;
    split_state(x.data(), s.q, s.qd);
    VariationalIntegrator<M> vi(model, s, opt.t0, discrete_rule_from_string(opt.discrete_rule),
                                NewtonSettings{opt.newton_tolerance, opt.newton_max_iterations});
    auto count = [&] {
      report.newton_iterations = vi.newton_iterations();
      report.rhs_evaluations = vi.lagrangian_evaluations();
    };
    try {
      run_fixed_grid(x, opt, rs, [&](double, double h, X& xs) {
        vi.step(h);
        for (int i = 0; i < n; ++i) {
          xs[static_cast<std::size_t>(i)] = vi.q()[i];
          xs[static_cast<std::size_t>(n + i)] = vi.qd()[i];
        }
      });
    } catch (const DynamicsError& e) {
      count();
      throw SimulationError(std::string("run stopped: ") + e.what(), vi.t());
    }
    count();
  }
}

/// Odeint's symplectic_rkn_sb3a_mclachlan or velocity_verlet on q̈ = a(q)
/// for a separable model (checked before the run), at fixed step opt.dt.
/// The pair (q, q̇) is integrated; with a constant M, (q, M q̇) is canonical,
/// so the map is symplectic.
template <class M, class Observer, class X>
void run_symplectic(const M& model, Workspace<M::dof>& ws, X& x, const SimulationOptions& opt,
                    RunState<M, Observer>& rs, RunReport& report) {
  namespace odeint = boost::numeric::odeint;
  using V = std::vector<double>;
  const int size = static_cast<int>(x.size() / 2);
  V q(static_cast<std::size_t>(size)), v(static_cast<std::size_t>(size));
  Vec<double, M::dof> qv(size), zero = Vec<double, M::dof>::Zero(size), acc(size);
  auto acceleration = [&](const V& qin, V& a, double t) {
    for (int i = 0; i < size; ++i) qv[i] = qin[static_cast<std::size_t>(i)];
    accelerations(model, ws, qv, zero, t, acc);  // separable: q̈ does not depend on q̇
    for (int i = 0; i < size; ++i) a[static_cast<std::size_t>(i)] = acc[i];
    ++report.rhs_evaluations;
  };
  auto unpack = [&](const X& xs) {
    for (int i = 0; i < size; ++i) {
      q[static_cast<std::size_t>(i)] = xs[static_cast<std::size_t>(i)];
      v[static_cast<std::size_t>(i)] = xs[static_cast<std::size_t>(size + i)];
    }
  };
  auto pack = [&](X& xs) {
    for (int i = 0; i < size; ++i) {
      xs[static_cast<std::size_t>(i)] = q[static_cast<std::size_t>(i)];
      xs[static_cast<std::size_t>(size + i)] = v[static_cast<std::size_t>(i)];
    }
  };
  unpack(x);
  if (opt.method == "velocity_verlet") {
    odeint::velocity_verlet<V> stepper;
    auto sys = [&](const V& qin, const V&, V& a, double t) { acceleration(qin, a, t); };
    run_fixed_grid(x, opt, rs, [&](double t, double h, X& xs) {
      stepper.do_step(sys, std::make_pair(std::ref(q), std::ref(v)), t, h);
      pack(xs);
    });
  } else {
    odeint::symplectic_rkn_sb3a_mclachlan<V> stepper;
    double t_now = opt.t0;  // the momentum function of odeint's RKN steppers gets no time
    auto coordinate_rate = [](const V& vin, V& dqdt) { dqdt = vin; };
    auto momentum_rate = [&](const V& qin, V& dvdt) { acceleration(qin, dvdt, t_now); };
    run_fixed_grid(x, opt, rs, [&](double t, double h, X& xs) {
      t_now = t;
      stepper.do_step(std::make_pair(coordinate_rate, momentum_rate), std::make_pair(std::ref(q), std::ref(v)), t, h);
      pack(xs);
    });
  }
}

}  // namespace detail

namespace detail {

/// Estimates ρ, the largest |eigenvalue| of J = ∂f/∂x at x (1/s), as
/// √(‖J²v‖/‖v‖) after 20 power iterations on J² (J² turns a pair of
/// oscillatory eigenvalues ±iω into the real −ω², so the iteration settles);
/// J v by central differences of f. Sets report.stiffness_rho and warns when
/// the step size h at the end satisfies h ρ > 1 (steps limited by stability:
/// an explicit Runge–Kutta method is stable only for h ρ below a few units).
template <class M, class X>
void check_stiffness(FirstOrderSystem<M> sys, const X& x, double t, double step, RunReport& report) {
  std::uint64_t scratch = 0;
  sys.evaluations = &scratch;  // not counted as the run's work
  const std::size_t size = x.size();
  X v = x, w = x, xp = x, xm = x, fp = x, fm = x;
  for (std::size_t i = 0; i < size; ++i) v[i] = 1.0 + 0.1 * static_cast<double>(i % 7);
  double xnorm = 0;
  for (double c : x) xnorm = std::max(xnorm, std::abs(c));
  auto norm = [](const X& a) {
    double s = 0;
    for (double c : a) s += c * c;
    return std::sqrt(s);
  };
  auto apply = [&](const X& in, X& out) {
    const double eps = 1e-6 * (1.0 + xnorm) / std::max(norm(in), 1e-300);
    for (std::size_t i = 0; i < size; ++i) {
      xp[i] = x[i] + eps * in[i];
      xm[i] = x[i] - eps * in[i];
    }
    sys(xp, fp, t);
    sys(xm, fm, t);
    for (std::size_t i = 0; i < size; ++i) out[i] = (fp[i] - fm[i]) / (2 * eps);
  };
  double rho2 = 0;
  try {
    for (int it = 0; it < 20; ++it) {
      const double nv = norm(v);
      if (!(nv > 0) || !std::isfinite(nv)) return;
      for (auto& c : v) c /= nv;
      apply(v, w);
      apply(w, v);
      rho2 = norm(v);
    }
  } catch (const std::exception&) {
    return;  // a diagnostic only: a state where f cannot be evaluated gives none
  }
  if (!std::isfinite(rho2)) return;
  report.stiffness_rho = std::sqrt(rho2);
  if (step * report.stiffness_rho > 1.0) {
    std::ostringstream os;
    os.precision(3);
    os << "stiff problem: the " << report.steps << " steps (" << step << " s at the end) were limited by stability, "
       << "not accuracy (largest |eigenvalue| of df/dx about " << report.stiffness_rho << " 1/s, step x rho = "
       << step * report.stiffness_rho << "); method rosenbrock4 needs far fewer steps";
    report.warnings.push_back(os.str());
  }
}

/// Throws OptionError when the chosen method cannot run this model: the
/// variational integrator without a compile-time dof or with Pfaffian or
/// unilateral constraints; the symplectic steppers on a model that is not
/// separable (separability_problem()).
template <class M>
void refuse_unsuited_method(const M& model, const State<M::dof>& initial, const SimulationOptions& options) {
  const std::string& m = options.method;
  if (m == "variational" && !variational_supported_v<M>) {
    throw OptionError(
        "method 'variational' cannot run model " + model_name(model) +
        ": it needs a compile-time number of coordinates and supports holonomic constraints only (no Pfaffian or "
        "unilateral constraints, no contacts); use dopri5 or fehlberg78");
  }
  if (m == "symplectic_rkn_sb3a_mclachlan" || m == "velocity_verlet") {
    const std::string why = separability_problem(model, initial, options.t0);
    if (!why.empty())
      throw OptionError("method '" + m + "' needs a separable model (L = 1/2 qd^T M qd - V(q), constant M); model " +
                        model_name(model) + " is not: " + why + "; use variational, dopri5 or fehlberg78");
  }
}

/// The body of simulate(), compiled once per model (the observer is erased).
template <class M>
RunReport simulate_impl(const M& model, const State<M::dof>& initial, const SimulationOptions& options,
                        ObserverRef<M::dof> observer) {
  check_model<M>();
  constexpr int n = M::dof;
  namespace odeint = boost::numeric::odeint;
#if defined(LAGRANGIAN_TRAP_FE_INVALID) && LAGRANGIAN_TRAP_FE_INVALID
  const FloatingPointTrap trap;  // debug builds: the first NaN raises SIGFPE where it is made
#endif
  const auto wall_start = std::chrono::steady_clock::now();
  options.validate();
  const int size = model_size(model);
  const auto names = coordinate_names(model);
  if (initial.q.size() != size || initial.qd.size() != size)
    throw OptionError("initial state has " + std::to_string(initial.q.size()) + " coordinates and " +
                      std::to_string(initial.qd.size()) + " velocities; the model has " + std::to_string(size));
  for (int i = 0; i < size; ++i) {
    if (!std::isfinite(initial.q[i]) || !std::isfinite(initial.qd[i])) {
      std::ostringstream os;
      os << "initial state: " << (std::isfinite(initial.q[i]) ? "qd" : "q") << "[" << i << "] ('"
         << names[static_cast<std::size_t>(i)] << "') is "
         << (std::isfinite(initial.q[i]) ? initial.qd[i] : initial.q[i]) << "; it must be finite";
      throw OptionError(os.str());
    }
  }

  refuse_unsuited_method(model, initial, options);

  RunReport report;
  report.model = model_name(model);
  report.coordinates = names;
  report.method = options.method;
  report.adaptive = !fixed_step_method(options.method);
  report.rtol = options.rtol;
  report.atol = options.atol;
  report.dt = options.dt;
  report.t0 = options.t0;
  report.t_end = options.t_end;
  report.conservative = !has_generalized_forces_v<M> && !has_dissipation_v<M> &&
                        is_autonomous(model, initial, options.t0) &&
                        constraints_workless(model, initial, options.t0);

  Workspace<n> ws(size);
  if constexpr (!has_constraints_v<M>)
    accelerations(model, ws, initial.q, initial.qd, options.t0);  // a singular M at t0 is an input error

  RunState<M> rs(model, options, observer, report);
  FirstOrderSystem<M> sys{&model, &ws, &report.rhs_evaluations};
  [[maybe_unused]] std::conditional_t<has_constraints_v<M>, ConstraintContext<M>, None> constraint_context{};
  if constexpr (has_constraints_v<M>) {
    constraint_context.omega = options.stabilization == Stabilization::baumgarte ? options.baumgarte_omega : 0.0;
    sys.constraints = &constraint_context;
    rs.attach(&constraint_context);
  }
  using X = StateBuffer<n>;
  X x = make_buffer<n>(size);
  for (int i = 0; i < size; ++i) {
    x[i] = initial.q[i];
    x[size + i] = initial.qd[i];
  }
  {
    const State<n> start = rs.start(initial);  // impacts at t0 may change the velocities
    for (int i = 0; i < size; ++i) {
      x[static_cast<std::size_t>(i)] = start.q[i];
      x[static_cast<std::size_t>(size + i)] = start.qd[i];
    }
  }
  try {
    const std::string& m = options.method;
    if (m == "dopri5") {
      run_out_of_line<M>([&] { run_dopri5(sys, x, options, rs); });
    } else if (m == "rk4") {
      run_out_of_line<M>([&] { run_rk4(sys, x, options, rs); });
    } else if (m == "cash_karp54") {
      using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_cash_karp54<X>>;
      run_out_of_line<M>([&] { run_controlled<Controlled>(sys, x, options, rs); });
    } else if (m == "fehlberg78") {
      using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<X>>;
      run_out_of_line<M>([&] { run_controlled<Controlled>(sys, x, options, rs); });
    } else if (m == "bulirsch_stoer") {
      run_out_of_line<M>([&] { run_controlled<odeint::bulirsch_stoer<X>>(sys, x, options, rs); });
    } else if (m == "rosenbrock4") {
      run_rosenbrock4(sys, x, options, rs);
    } else if (m == "variational") {
      run_variational(model, x, options, rs, report);
    } else if (m == "symplectic_rkn_sb3a_mclachlan" || m == "velocity_verlet") {
      run_symplectic(model, ws, x, options, rs, report);
    } else {
      throw OptionError("unreachable: unknown method '" + m + "'");
    }
  } catch (const DynamicsError& e) {
    throw SimulationError(std::string("run stopped: ") + e.what(), std::numeric_limits<double>::quiet_NaN());
  }
  rs.finish(x.data());
  if (report.adaptive && options.method != "rosenbrock4") check_stiffness(sys, x, report.t_final, rs.recent_step(), report);
  report.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return report;
}

}  // namespace detail

/// Integrates a model from `initial` over [options.t0, options.t_end] and
/// returns what the run cost and how accurate it was. Samples go to
/// `observer` (see observers.hpp); its finish() is called only on success.
///
/// Throws OptionError for invalid options or a non-finite initial state,
/// DynamicsError when M is singular at t0, ConstraintError for an unusable
/// constraint set or an inconsistent initial state, and SimulationError (with
/// the time) when the run fails part-way: a non-finite state, step-size
/// underflow, max_steps, or a singular mass matrix met during the run.
template <class M, class Observer = NullObserver>
RunReport simulate(const M& model, const State<M::dof>& initial, const SimulationOptions& options,
                   Observer&& observer = {}) {
  check_model<M>();
  using Obs = std::remove_reference_t<Observer>;
  RunReport report = detail::simulate_impl(model, initial, options, detail::ObserverRef<M::dof>::of(observer));
  if constexpr (detail::observer_with_finish<Obs>) {
    const auto start = std::chrono::steady_clock::now();
    observer.finish();
    report.wall_time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  return report;
}

template <class M>
std::vector<int> cyclic_coordinates(const M& model, const State<M::dof>& s, double t) {
  check_model<M>();
  constexpr int n = M::dof;
  const int size = static_cast<int>(s.q.size());
  std::vector<bool> cyclic(static_cast<std::size_t>(size), true);
  Workspace<n> ws(size);
  for (const State<n>& p : detail::probe_states(s)) {
    detail::eom_pass(model, ws, p.q, p.qd, t);
    detail::force_pass(model, ws, p.q, p.qd, t);
    for (int i = 0; i < size; ++i)
      cyclic[static_cast<std::size_t>(i)] = cyclic[static_cast<std::size_t>(i)] && ws.dL_dq[i] == 0.0 && ws.forces[i] == 0.0;
    if constexpr (has_constraints_v<M>) {
      // A constraint force along q_i changes p_i: conserved only if no constraint involves q_i.
      const auto cs = constraint_state(model, p.q, p.qd, t);
      for (int i = 0; i < size; ++i)
        cyclic[static_cast<std::size_t>(i)] = cyclic[static_cast<std::size_t>(i)] && cs.jacobian.col(i).isZero(0.0);
    }
  }
  std::vector<int> out;
  for (int i = 0; i < size; ++i)
    if (cyclic[static_cast<std::size_t>(i)]) out.push_back(i);
  return out;
}

template <class M>
std::string separability_problem(const M& model, const State<M::dof>& s, double t) {
  check_model<M>();
  if constexpr (declares_separable<M>) {
    (void)s, (void)t;
    return M::separable ? std::string() : model_name(model) + " declares separable = false";
  } else if constexpr (has_constraints_v<M>) {
    (void)model, (void)s, (void)t;
    return "it has constraints";
  } else if constexpr (has_generalized_forces_v<M> || has_dissipation_v<M>) {
    (void)model, (void)s, (void)t;
    return "it has generalized forces or dissipation";
  } else {
    if (!is_autonomous(model, s, t)) return "L depends explicitly on time";
    const auto m0 = mass_matrix(model, s.q, s.qd, t);
    const double scale = m0.template lpNorm<Eigen::Infinity>();
    for (const State<M::dof>& p : detail::probe_states(s)) {
      const auto mp = mass_matrix(model, p.q, p.qd, t);
      if ((mp - m0).template lpNorm<Eigen::Infinity>() > 1e-12 * scale) {
        std::ostringstream os;
        os.precision(6);
        os << "the mass matrix d2L/dqd2 depends on the state (entry max change "
           << (mp - m0).template lpNorm<Eigen::Infinity>() << " of " << scale << ")";
        return os.str();
      }
      const auto mom = momenta(model, p.q, p.qd, t);
      const auto expected = (m0 * p.qd).eval();
      if ((mom - expected).template lpNorm<Eigen::Infinity>() > 1e-12 * (1.0 + expected.template lpNorm<Eigen::Infinity>()))
        return "the momenta dL/dqd are not M qd (terms linear in the velocities)";
    }
    return {};
  }
}

template <class M>
bool is_autonomous(const M& model, const State<M::dof>& s, double t) {
  const auto probes = detail::probe_states(s);
  for (std::size_t k = 0; k < probes.size(); ++k) {
    const double tk = t + 0.37 * static_cast<double>(k) * (1.0 + std::abs(t));
    if (lagrangian_time_derivative(model, probes[k].q, probes[k].qd, tk) != 0.0) return false;
  }
  return true;
}

}  // namespace lagrangian
