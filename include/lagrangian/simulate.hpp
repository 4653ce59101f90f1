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

#include "lagrangian/detail/stiff.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/observers.hpp"
#include "lagrangian/report.hpp"

namespace lagrangian {

/// Indices of cyclic coordinates: ∂L/∂q_i = 0 and Q_i = 0 at the given state
/// and at three nearby states (a fixed, deterministic perturbation). This is
/// a sampled check: a coordinate that drops out of L only on those states
/// would be misreported, which is why the run reports the momentum drift so
/// the claim can be seen to hold.
template <class M>
std::vector<int> cyclic_coordinates(const M& model, const State<M::dof>& s, double t = 0.0);

/// True when ∂L/∂t = 0 at the given (state, t) and at three nearby states and
/// later times (sampled check, same caveat as cyclic_coordinates()).
template <class M>
bool is_autonomous(const M& model, const State<M::dof>& s, double t = 0.0);

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

/// h = p·q̇ − L and p in one first-order pass.
template <class M>
double energy_and_momenta(const M& model, const Vec<double, M::dof>& q, const Vec<double, M::dof>& qd, double t,
                          Vec<double, M::dof>& p) {
  constexpr int n = M::dof;
  if constexpr (n == Dynamic) {
    p = momenta(model, q, qd, t);
    return p.dot(qd) - lagrangian_value(model, q, qd, t);
  } else {
    using J = ad::Jet<double, n, 1>;
    const Vec<J, n> qj = q.template cast<J>();
    Vec<J, n> qdj;
    for (int k = 0; k < n; ++k) qdj[k] = J::variable(qd[k], k);
    const J l = lagrangian_of(model, qj, qdj, J(t));
    double h = -l.v;
    for (int i = 0; i < n; ++i) {
      p[i] = l.g[i];
      h += p[i] * qd[i];
    }
    return h;
  }
}

/// The first-order system ẋ = f(x, t) handed to Odeint, counting evaluations.
template <class M>
struct FirstOrderSystem {
  static constexpr int n = M::dof;
  const M* model;
  Workspace<n>* ws;
  std::uint64_t* evaluations;

  template <class X, class DX>
  LAGRANGIAN_INLINE void operator()(const X& x, DX& dxdt, double t) const {
    if constexpr (n == Dynamic) {
      const int size = static_cast<int>(ws->scratch_q.size());
      for (int i = 0; i < size; ++i) {
        ws->scratch_q[i] = x[i];
        ws->scratch_qd[i] = x[size + i];
      }
      evaluate_into(ws->scratch_q, ws->scratch_qd, t, ws->scratch_qdd);
      for (int i = 0; i < size; ++i) {
        dxdt[i] = x[size + i];
        dxdt[size + i] = ws->scratch_qdd[i];
      }
    } else {
      Vec<double, n> q;
      Vec<double, n> qd;
      for (int i = 0; i < n; ++i) {
        q[i] = x[i];
        qd[i] = x[n + i];
      }
      Vec<double, n> qdd;  // a local: a store to the workspace and reload costs ~35% here
      evaluate_into(q, qd, t, qdd);
      for (int i = 0; i < n; ++i) {
        dxdt[i] = qd[i];
        dxdt[n + i] = qdd[i];
      }
    }
    ++*evaluations;
  }
  LAGRANGIAN_INLINE void evaluate_into(const Vec<double, n>& q, const Vec<double, n>& qd, double t,
                                       Vec<double, n>& qdd) const {
    if constexpr (has_explicit_accelerations_v<M>) {
      model->accelerations(q, qd, t, qdd);
    } else {
      accelerations(*model, *ws, q, qd, t, qdd);
    }
  }
};

template <class O, int N>
concept observer_with_begin = requires(O& o, const std::vector<std::string>& names) { o.begin(names, true); };
template <class O>
concept observer_with_finish = requires(O& o) { o.finish(); };

/// Bookkeeping shared by all stepper loops: samples, drift monitors, limits.
template <class M, class Observer>
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
    if constexpr (observer_with_begin<Observer, n>) obs_.begin(names, has_kinetic_potential_v<M>);
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
    for (std::size_t k = 0; k < cyclic_.size(); ++k) {
      MomentumDrift& d = report_.conserved_momenta[k];
      d.final_abs_drift = std::abs(p[cyclic_[k]] - d.initial);
      d.max_abs_drift = std::max(d.max_abs_drift, d.final_abs_drift);
    }
    obs_(s);
    ++report_.samples;
    last_emitted_ = t;
  }

  const M& model_;
  const SimulationOptions& opt_;
  Observer& obs_;
  RunReport& report_;
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
  while (!reached(t, opt.t_end)) {
    const double limit = std::min(opt.t_end, rs.next_output_time());
    const bool clamped = t + dt > limit;
    double dt_try = clamped ? limit - t : dt;
    const double t_old = t;
    if (stepper.try_step(sys, x, t, dt_try) == odeint::success) {
      if (clamped) t = limit;  // land exactly on the output time or t_end
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
  X buf = x;
  double t = opt.t0;
  double dt = opt.dt;
  const bool dense = opt.output_interval > 0;  // samples between steps need the step's start
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
      rs.accepted(t_old, t_new, x.data(), [&](double to, double* out) {
        stepper.stepper().calc_state(to, buf, x_old, dxdt_old, t_old, x, dxdt, t_new);
        std::copy(buf.begin(), buf.end(), out);
      });
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
    if (t_next >= t_grid) ++k;
    const double t_old = t;
    stepper.do_step(sys, x, t, t_next - t);
    t = t_next;
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
    if (stepper.try_step(stiff, x.data(), t, dt_try)) {
      if (clamped) t = limit;
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

/// Integrates a model from `initial` over [options.t0, options.t_end] and
/// returns what the run cost and how accurate it was. Samples go to
/// `observer` (see observers.hpp); its finish() is called only on success.
///
/// Throws OptionError for invalid options or a non-finite initial state,
/// DynamicsError when M is singular at t0, and SimulationError (with the
/// time) when the run fails part-way: a non-finite state, step-size
/// underflow, max_steps, or a singular mass matrix met during the run.
template <class M, class Observer = NullObserver>
RunReport simulate(const M& model, const State<M::dof>& initial, const SimulationOptions& options,
                   Observer&& observer = {}) {
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
  report.conservative =
      !has_generalized_forces_v<M> && !has_dissipation_v<M> && is_autonomous(model, initial, options.t0);

  Workspace<n> ws(size);
  accelerations(model, ws, initial.q, initial.qd, options.t0);  // a singular M at t0 is an input error

  using Obs = std::remove_reference_t<Observer>;
  detail::RunState<M, Obs> rs(model, options, observer, report);
  detail::FirstOrderSystem<M> sys{&model, &ws, &report.rhs_evaluations};
  using X = detail::StateBuffer<n>;
  X x = detail::make_buffer<n>(size);
  for (int i = 0; i < size; ++i) {
    x[i] = initial.q[i];
    x[size + i] = initial.qd[i];
  }
  rs.start(initial);
  try {
    const std::string& m = options.method;
    if (m == "dopri5") {
      detail::run_dopri5(sys, x, options, rs);
    } else if (m == "rk4") {
      detail::run_rk4(sys, x, options, rs);
    } else if (m == "cash_karp54") {
      using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_cash_karp54<X>>;
      Controlled stepper{typename Controlled::error_checker_type(options.atol, options.rtol)};
      detail::run_controlled(stepper, sys, x, options, rs);
    } else if (m == "fehlberg78") {
      using Controlled = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<X>>;
      Controlled stepper{typename Controlled::error_checker_type(options.atol, options.rtol)};
      detail::run_controlled(stepper, sys, x, options, rs);
    } else if (m == "bulirsch_stoer") {
      odeint::bulirsch_stoer<X> stepper(options.atol, options.rtol);
      detail::run_controlled(stepper, sys, x, options, rs);
    } else if (m == "rosenbrock4") {
      detail::run_rosenbrock4(sys, x, options, rs);
    } else {
      throw OptionError("unreachable: unknown method '" + m + "'");
    }
  } catch (const DynamicsError& e) {
    throw SimulationError(std::string("run stopped: ") + e.what(), std::numeric_limits<double>::quiet_NaN());
  }
  rs.finish();
  if constexpr (detail::observer_with_finish<Obs>) observer.finish();
  report.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
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
