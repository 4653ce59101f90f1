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

#include <boost/math/tools/toms748_solve.hpp>
#include <boost/numeric/odeint/stepper/bulirsch_stoer.hpp>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_cash_karp54.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

#include "lagrangian/constraints.hpp"
#include "lagrangian/detail/stiff.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/observers.hpp"
#include "lagrangian/report.hpp"

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

/// Time tolerance of located events (lift-off of unilateral constraints):
/// the bracket is narrowed to 1e-12 · max(1 s, |t|).
inline constexpr double release_time_tolerance = 1e-12;

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
  void evaluate_into(const Vec<double, n>& q, const Vec<double, n>& qd, double t,
                                       Vec<double, n>& qdd) const {
    if constexpr (has_constraints_v<M>) {
      constrained_accelerations(*model, *ws, constraints->cw, q, qd, t, qdd, constraints->omega, constraints->active);
    } else if constexpr (has_explicit_accelerations_v<M>) {
      model->accelerations(q, qd, t, qdd);
    } else {
      accelerations(*model, *ws, q, qd, t, qdd);
    }
  }
};

/// The state inside an accepted step for steppers without dense output: one
/// Runge–Kutta–Fehlberg 7(8) step from the step's start (t0, x0) to t, an
/// 8th-order continuous extension (13 right-hand sides per evaluation, used
/// only while locating an event).
template <class M, class X>
struct SubStep {
  const FirstOrderSystem<M>& sys;
  X x0;
  double t0;
  void operator()(double t, double* out) const {
    if (t == t0) {
      std::copy(x0.begin(), x0.end(), out);
      return;
    }
    boost::numeric::odeint::runge_kutta_fehlberg78<X> stepper;
    X x = x0;
    stepper.do_step(sys, x0, t0, x, t - t0);
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

  RunState(const M& model, const SimulationOptions& opt, Observer& obs, RunReport& report)
      : model_(model),
        opt_(opt),
        obs_(obs),
        report_(report),
        size_(model_size(model)),
        buf_(make_buffer<n>(size_)),
        last_x_(make_buffer<n>(size_)) {}

  void start(const State<n>& x0) {
    const std::vector<int> cyclic = cyclic_coordinates(model_, x0, opt_.t0);
    cyclic_.assign(cyclic.begin(), cyclic.end());
    Vec<double, n> p(size_);
    h0_ = energy_and_momenta(model_, x0.q, x0.qd, opt_.t0, p);
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
    const auto names = coordinate_names(model_);
    for (int i : cyclic_) report_.conserved_momenta.push_back({names[static_cast<std::size_t>(i)], p[i], 0, 0});
    Columns columns{names, {}, has_kinetic_potential_v<M>};
    if constexpr (has_constraints_v<M>) start_constraints(x0, columns);
    if (obs_.begin) obs_.begin(obs_.object, columns);
    next_output_index_ = 1;
    emit(opt_.t0, x0.q.data(), x0.qd.data());
  }

  /// Next time a sample is due (infinity when sampling every step or never).
  double next_output_time() const {
    if (opt_.output_interval <= 0) return std::numeric_limits<double>::infinity();
    return opt_.t0 + static_cast<double>(next_output_index_) * opt_.output_interval;
  }

  /// Called after every accepted step ending at t with state x (2n values).
  /// `interpolate(t_out, buffer)` fills the state at an earlier time when the
  /// stepper has dense output; otherwise steps end on output times.
  template <class Interp>
  void accepted(double t_old, double t, const double* x, Interp&& interpolate) {
    ++report_.steps;
    for (int i = 0; i < 2 * size_; ++i) {
      if (!std::isfinite(x[i])) {
        std::ostringstream os;
        os.precision(17);
        os << "non-finite state after the step from t = " << t_old << " to t = " << t << ": x = [";
        for (int k = 0; k < 2 * size_; ++k) os << (k ? ", " : "") << x[k];
        os << "] (q then qd); the run was stopped";
        throw SimulationError(os.str(), t);
      }
    }
    if (report_.steps > opt_.max_steps) {
      std::ostringstream os;
      os << "max_steps = " << opt_.max_steps << " reached at t = " << t << " before t_end = " << opt_.t_end;
      throw SimulationError(os.str(), t);
    }
    if (opt_.output_interval == 0) {
      emit(t, x, x + size_);
    } else if (opt_.output_interval > 0) {
      const double tol = 1e-12 * std::max(std::abs(t), opt_.output_interval);
      for (double to = next_output_time(); to <= t + tol && to <= opt_.t_end + tol; to = next_output_time()) {
        ++next_output_index_;
        if (std::abs(to - t) <= tol) {
          emit(t, x, x + size_);
          last_emitted_ = t;
        } else {
          interpolate(to, buf_.data());
          emit(to, buf_.data(), buf_.data() + size_);
        }
      }
    }
    last_t_ = t;
    if (opt_.output_interval != 0) std::copy(x, x + 2 * size_, last_x_.begin());
  }

  /// Constrained models: projection (when chosen) and residual monitoring
  /// after an accepted step ending at t with state x; true when x changed.
  bool stabilize(double* x, double t) {
    if constexpr (!has_constraints_v<M>) {
      (void)x;
      (void)t;
      return false;
    } else {
      ConstraintReport& cr = report_.constraints;
      Vec<double, n> q, qd;
      split_state(x, q, qd);
      bool changed = false;
      if (opt_.stabilization == Stabilization::projection) {
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
             << "): the body came back into contact; impacts are not handled by this version";
          throw SimulationError(os.str(), t);
        }
      }
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
  void extra_rhs_evaluation() {
    if constexpr (has_constraints_v<M>) ++report_.constraints.extra_rhs_evaluations;
  }
  void attach(ConstraintContext<M>* ctx) { ctx_ = ctx; }
  ActiveSet active() const { return ctx_ ? ctx_->active : all_active; }

  /// Unilateral constraints: when an active one's multiplier is negative at
  /// the end of the step (it would pull), finds the time t* in the step where
  /// it crosses zero (Boost.Math TOMS 748 on the step's continuous extension:
  /// dopri5's dense output, or a Fehlberg 7(8) sub-step from the step's
  /// start; bracket narrowed to release_time_tolerance), moves the step end to
  /// t*, releases the constraint and returns true. The caller restarts its
  /// stepper from there.
  template <class Interp>
  bool release(double t_old, double& t, double* x, Interp&& interp) {
    if constexpr (unilateral_count_v<M> == 0) {
      (void)t_old;
      (void)t;
      (void)x;
      (void)interp;
      return false;
    } else {
      const ActiveSet act = ctx_->active;
      if ((act & ((ActiveSet{1} << unilateral_count_v<M>) - 1)) == 0) return false;
      auto multipliers_at = [&](const double* xs, double ts) {
        Vec<double, n> q, qd, qdd;
        split_state(xs, q, qd);
        constrained_accelerations(model_, ws_, cw_, q, qd, ts, qdd, 0.0, act);
        return cw_.multipliers;
      };
      const auto lam_end = multipliers_at(x, t);
      int which = -1;
      double t_star = std::numeric_limits<double>::infinity();  // a root at the step end counts too
      std::vector<double> buf(static_cast<std::size_t>(2 * n));
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
        if (fa > 0) {
          std::uintmax_t iterations = 100;
          const auto r = boost::math::tools::toms748_solve(
              f, t_old, t, fa, lam_end[row],
              [](double a, double b) { return std::abs(b - a) <= release_time_tolerance * std::max(1.0, std::abs(a)); },
              iterations);
          tj = r.second;  // upper end of the final bracket: λ ≥ 0 up to r.first, < 0 from here
        }
        if (tj < t_star) {
          t_star = tj;
          which = j;
        }
      }
      if (which < 0) return false;
      if (t_star < t) {
        interp(t_star, buf.data());
        std::copy(buf.begin(), buf.end(), x);
        t = t_star;
      }
      ctx_->active &= ~(ActiveSet{1} << which);
      const std::string name = report_.constraints.names[static_cast<std::size_t>(holonomic_count_v<M> + which)];
      std::ostringstream os;
      os.precision(15);
      os << "released " << name << " at t = " << t;
      report_.constraints.events.push_back(os.str());
      report_.constraints.event_times.push_back(t);
      return true;
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

  /// Final bookkeeping: sample the end state if not done yet.
  void finish() {
    if (opt_.output_interval != 0 && last_emitted_ != last_t_)
      emit(last_t_, last_x_.data(), last_x_.data() + size_);
    report_.energy_drift_final = std::abs(h_last_ - h0_) / report_.energy_scale;
    if (report_.has_total_energy) report_.total_energy_drift_final = std::abs(e_last_ - e0_) / report_.energy_scale;
    report_.energy_final = h_last_;
  }

 private:
  void emit(double t, const double* q, const double* qd) {
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
    for (std::size_t k = 0; k < cyclic_.size(); ++k) {
      MomentumDrift& d = report_.conserved_momenta[k];
      d.final_abs_drift = std::abs(p[cyclic_[k]] - d.initial);
      d.max_abs_drift = std::max(d.max_abs_drift, d.final_abs_drift);
    }
    obs_(s);
    ++report_.samples;
    last_emitted_ = t;
  }

  void start_constraints(const State<n>& x0, Columns& columns) {
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
      for (int j = 0; j < unilateral_count_v<M>; ++j) {
        const int row = holonomic_count_v<M> + j;
        const double g = cs.position[row], gd = cs.velocity[row];
        if (g < -1e-9 * qs || (std::abs(g) <= 1e-9 * qs && gd < -1e-9 * vs)) {
          std::ostringstream os;
          os.precision(17);
          os << "unilateral constraint " << cr.names[static_cast<std::size_t>(row)]
             << (g < -1e-9 * qs ? " is violated at t0: g = " : " is approached at t0 (an impact): dg/dt = ")
             << (g < -1e-9 * qs ? g : gd) << "; start on or outside the admissible side at rest relative to it";
          throw ConstraintError(os.str());
        }
        if (std::abs(g) <= 1e-9 * qs) active |= ActiveSet{1} << j;  // in contact
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

  const M& model_;
  const SimulationOptions& opt_;
  Observer& obs_;
  RunReport& report_;
  Workspace<n> ws_{model_size(model_)};
  ConstraintContext<M>* ctx_ = nullptr;
  [[no_unique_address]] std::conditional_t<has_constraints_v<M>, ConstraintWorkspace<n, constraint_count_v<M>>, None>
      cw_{};
  std::vector<int> cyclic_;
  double h0_ = 0, e0_ = 0, h_last_ = 0, e_last_ = 0;
  std::uint64_t next_output_index_ = 1;
  std::uint64_t consecutive_rejections_ = 0;
  double last_emitted_ = std::numeric_limits<double>::quiet_NaN();
  double last_t_ = 0;
  int size_;
  StateBuffer<n> buf_;
  StateBuffer<n> last_x_;
};

/// True when t has reached t_end up to rounding.
inline bool reached(double t, double t_end) {
  return t_end - t <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(t), std::abs(t_end));
}

/// Loop for an Odeint controlled stepper without dense output: steps are
/// shortened to land on output times and on t_end.
template <class M, class Observer, class Controlled, class X>
void run_controlled(Controlled& stepper, FirstOrderSystem<M> sys, X& x, const SimulationOptions& opt,
                    RunState<M, Observer>& rs) {
  namespace odeint = boost::numeric::odeint;
  double t = opt.t0;
  double dt = opt.dt;
  [[maybe_unused]] X x_prev = x;
  while (!reached(t, opt.t_end)) {
    const double limit = std::min(opt.t_end, rs.next_output_time());
    const bool clamped = t + dt > limit;
    double dt_try = clamped ? limit - t : dt;
    const double t_old = t;
    if constexpr (unilateral_count_v<M> > 0) x_prev = x;
    if (stepper.try_step(sys, x, t, dt_try) == odeint::success) {
      if (clamped) t = limit;  // land exactly on the output time or t_end
      if constexpr (unilateral_count_v<M> > 0) {
        rs.release(t_old, t, x.data(), SubStep<M, X>{sys, x_prev, t_old});  // no state carried between steps
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
}

template <class M, class Observer, class X>
void run_dopri5(FirstOrderSystem<M> sys, X& x, const SimulationOptions& opt, RunState<M, Observer>& rs) {
  namespace odeint = boost::numeric::odeint;
  using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<X>>;
  Controlled stepper{typename Controlled::error_checker_type(opt.atol, opt.rtol)};
  X dxdt = x;
  X x_old = x;
  X dxdt_old = x;
  X dxdt_step = x;
  X buf = x;
  double t = opt.t0;
  double dt = opt.dt;
  // Samples between steps and event location need the step's start.
  const bool dense = opt.output_interval > 0 || unilateral_count_v<M> > 0;
  sys(x, dxdt, t);
  while (!reached(t, opt.t_end)) {
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
      const X* deriv_new = &dxdt;
      auto interpolate = [&](double to, double* out) {
        stepper.stepper().calc_state(to, buf, x_old, dxdt_old, t_old, x, *deriv_new, t_new);
        std::copy(buf.begin(), buf.end(), out);
      };
      if constexpr (has_constraints_v<M>) {
        if (dense) {
          dxdt_step = dxdt;  // the step's own end derivative, for its dense output
          deriv_new = &dxdt_step;
        }
        bool changed = rs.release(t_old, t, x.data(), interpolate);
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
}

template <class M, class Observer, class X>
void run_rk4(FirstOrderSystem<M> sys, X& x, const SimulationOptions& opt, RunState<M, Observer>& rs) {
  namespace odeint = boost::numeric::odeint;
  odeint::runge_kutta4<X> stepper;
  // Fixed steps of opt.dt; the k-th step ends at t0 + k dt (no accumulated
  // rounding); a step is shortened only to land on an output time or t_end.
  std::uint64_t k = 0;
  double t = opt.t0;
  while (!reached(t, opt.t_end)) {
    const double t_grid = opt.t0 + static_cast<double>(k + 1) * opt.dt;
    const double t_next = std::min({t_grid, opt.t_end, rs.next_output_time()});
    const double t_old = t;
    [[maybe_unused]] const X x_prev = unilateral_count_v<M> > 0 ? x : X{};
    stepper.do_step(sys, x, t, t_next - t);
    t = t_next;
    if constexpr (unilateral_count_v<M> > 0) rs.release(t_old, t, x.data(), SubStep<M, X>{sys, x_prev, t_old});
    if (t >= t_grid) ++k;  // a step cut at an event leaves the grid point ahead
    rs.stabilize(x.data(), t);
    rs.accepted(t_old, t, x.data(), [](double, double*) {});
  }
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
  while (!reached(t, opt.t_end)) {
    const double limit = std::min(opt.t_end, rs.next_output_time());
    const bool clamped = t + dt > limit;
    double dt_try = clamped ? limit - t : dt;
    const double t_old = t;
    [[maybe_unused]] const X x_prev = unilateral_count_v<M> > 0 ? x : X{};
    if (stepper.try_step(stiff, x.data(), t, dt_try)) {
      if (clamped) t = limit;
      if constexpr (unilateral_count_v<M> > 0) rs.release(t_old, t, x.data(), SubStep<M, X>{sys, x_prev, t_old});
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

}  // namespace detail

namespace detail {

/// The body of simulate(), compiled once per model (the observer is erased).
template <class M>
RunReport simulate_impl(const M& model, const State<M::dof>& initial, const SimulationOptions& options,
                        ObserverRef<M::dof> observer) {
  check_model<M>();
  constexpr int n = M::dof;
  namespace odeint = boost::numeric::odeint;
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

  RunReport report;
  report.model = model_name(model);
  report.coordinates = names;
  report.method = options.method;
  report.adaptive = options.method != "rk4";
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
  rs.start(initial);
  try {
    const std::string& m = options.method;
    if (m == "dopri5") {
      run_dopri5(sys, x, options, rs);
    } else if (m == "rk4") {
      run_rk4(sys, x, options, rs);
    } else if (m == "cash_karp54") {
      using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_cash_karp54<X>>;
      Controlled stepper{typename Controlled::error_checker_type(options.atol, options.rtol)};
      run_controlled(stepper, sys, x, options, rs);
    } else if (m == "fehlberg78") {
      using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<X>>;
      Controlled stepper{typename Controlled::error_checker_type(options.atol, options.rtol)};
      run_controlled(stepper, sys, x, options, rs);
    } else if (m == "bulirsch_stoer") {
      odeint::bulirsch_stoer<X> stepper(options.atol, options.rtol);
      run_controlled(stepper, sys, x, options, rs);
    } else if (m == "rosenbrock4") {
      run_rosenbrock4(sys, x, options, rs);
    } else {
      throw OptionError("unreachable: unknown method '" + m + "'");
    }
  } catch (const DynamicsError& e) {
    throw SimulationError(std::string("run stopped: ") + e.what(), std::numeric_limits<double>::quiet_NaN());
  }
  rs.finish();
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
bool is_autonomous(const M& model, const State<M::dof>& s, double t) {
  const auto probes = detail::probe_states(s);
  for (std::size_t k = 0; k < probes.size(); ++k) {
    const double tk = t + 0.37 * static_cast<double>(k) * (1.0 + std::abs(t));
    if (lagrangian_time_derivative(model, probes[k].q, probes[k].qd, tk) != 0.0) return false;
  }
  return true;
}

}  // namespace lagrangian
