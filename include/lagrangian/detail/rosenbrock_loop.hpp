#pragma once
// The stiff path of simulate(): Odeint's rosenbrock4 behind StiffSystem.

#include <algorithm>
#include <cmath>
#include <limits>

#include "lagrangian/detail/first_order_system.hpp"
#include "lagrangian/detail/rk_loops.hpp"
#include "lagrangian/detail/run_state.hpp"
#include "lagrangian/detail/stiff.hpp"
#include "lagrangian/report.hpp"

namespace lagrangian::detail {

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

}  // namespace lagrangian::detail
