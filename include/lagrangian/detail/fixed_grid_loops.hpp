#pragma once
// The fixed-step loops of simulate() for the structure-preserving methods:
// the variational integrator and Odeint's symplectic steppers.

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <boost/numeric/odeint/stepper/symplectic_rkn_sb3a_mclachlan.hpp>
#include <boost/numeric/odeint/stepper/velocity_verlet.hpp>

#include "lagrangian/detail/first_order_system.hpp"
#include "lagrangian/detail/rk_loops.hpp"
#include "lagrangian/detail/run_state.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/report.hpp"
#include "lagrangian/variational.hpp"

namespace lagrangian::detail {

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

}  // namespace lagrangian::detail
