// The stiff path of the driver: Odeint's rosenbrock4 behind StiffSystem.

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>

#include "lagrangian/integrate/detail/stiff.hpp"
#include "loops.hpp"

namespace lagrangian::detail {

/// Odeint's rosenbrock4 (see integrate/detail/stiff.hpp) on the autonomous system
/// y = [x; τ], ẏ = [f(x, τ); 1]: Odeint's treatment of an explicit time
/// dependence through ∂f/∂t is wrong (a driven oscillator lost four orders
/// of accuracy and took 85 times the steps, with ∂f/∂t exact or not), while
/// the autonomous form is the one its Rosenbrock coefficients are derived
/// for. τ is integrated exactly (it is linear) and equals t. The Jacobian
///   ∂ẏ/∂y = [[∂f/∂x, ∂f/∂τ], [0, 0]]
/// is formed by central differences of the right-hand side,
///   J_ij ≈ (f_i(y + h e_j) − f_i(y − h e_j)) / 2h,  h = ∛ε · max(|y_j|, 1),
/// with truncation error O(h²) ≈ 1e-10 relative.
namespace {

/// f and its Jacobian for the stepper, on y = [x; τ] (see run_rosenbrock4);
/// `Rhs` evaluates f(x, t) into a StateVector.
template <class Rhs>
struct Autonomous {
  Rhs rhs;
  StateVector xa, fa, fb;
  int m;  ///< 2n, the driver's state; the stepper's has one more value, τ

  StiffSystem system() {
    return StiffSystem{
        this,
        [](void* c, const double* yin, double* dydt, double) {
          auto& k = *static_cast<Autonomous*>(c);
          std::copy(yin, yin + k.m, k.xa.begin());
          k.rhs(k.xa, k.fa, yin[k.m]);
          std::copy(k.fa.begin(), k.fa.end(), dydt);
          dydt[k.m] = 1.0;
        },
        [](void* c, const double* yin, double* J, double* dfdt, double) {
          auto& k = *static_cast<Autonomous*>(c);
          const int m = k.m, my = m + 1;
          const double cbrt_eps = std::cbrt(std::numeric_limits<double>::epsilon());
          const double tau = yin[m];
          std::copy(yin, yin + m, k.xa.begin());
          for (int j = 0; j < m; ++j) {
            const double h = cbrt_eps * std::max(std::abs(k.xa[j]), 1.0);
            const double xj = k.xa[j];
            k.xa[j] = xj + h;
            k.rhs(k.xa, k.fa, tau);
            k.xa[j] = xj - h;
            k.rhs(k.xa, k.fb, tau);
            k.xa[j] = xj;
            for (int i = 0; i < m; ++i) J[i * my + j] = (k.fa[i] - k.fb[i]) / (2 * h);
          }
          const double ht = cbrt_eps * std::max(std::abs(tau), 1.0);
          k.rhs(k.xa, k.fa, tau + ht);
          k.rhs(k.xa, k.fb, tau - ht);
          for (int i = 0; i < m; ++i) J[i * my + m] = (k.fa[i] - k.fb[i]) / (2 * ht);
          for (int j = 0; j < my; ++j) J[m * my + j] = 0.0;  // τ̇ = 1
          for (int i = 0; i < my; ++i) dfdt[i] = 0.0;       // autonomous
        }};
  }
};

/// Odeint's controller measures the error as an RMS over the state's
/// values; τ's error is zero, so the tolerances scaled by √(m / (m + 1))
/// accept exactly the steps they would accept on x alone.
double tolerance_scale(int m) { return std::sqrt(static_cast<double>(m) / (m + 1)); }

}  // namespace

void run_rosenbrock4(Run& run, StateVector& x) {
  const SimulationOptions& opt = run.options();
  Autonomous<CountedRhs<>> ctx{run.rhs(), x, x, x, static_cast<int>(x.size())};
  const StiffSystem stiff = ctx.system();
  const double scale = tolerance_scale(ctx.m);
  Rosenbrock4Stepper stepper(ctx.m + 1, opt.atol * scale, opt.rtol * scale);
  StateVector y(x.size() + 1);
  run_controlled_loop(
      run, x, run.rhs(),
      [&](StateVector& xs, double& t, double& dt) {
        std::copy(xs.begin(), xs.end(), y.begin());
        y.back() = t;
        if (!stepper.try_step(stiff, y.data(), t, dt)) return false;
        std::copy(y.begin(), y.end() - 1, xs.begin());
        return true;
      },
      [] {});
}

ProbeCost rosenbrock4_probe(const System& system, StateVector x, double t, double t_end, double dt, double rtol,
                            double atol, double grid_t0, double grid, std::uint64_t max_evaluations) {
  ProbeCost cost;
  auto f = [&system, &cost](const StateVector& y, StateVector& dydt, double tt) {
    ++cost.evaluations;
    system.rhs(y.data(), dydt.data(), tt);
  };
  Autonomous<decltype(f)> ctx{f, x, x, x, static_cast<int>(x.size())};
  const StiffSystem stiff = ctx.system();
  const double scale = tolerance_scale(ctx.m);
  Rosenbrock4Stepper stepper(ctx.m + 1, atol * scale, rtol * scale);
  StateVector y(x.size() + 1);
  std::copy(x.begin(), x.end(), y.begin());
  try {
    while (t < t_end) {
      if (cost.evaluations > max_evaluations) {
        cost.outcome = ProbeCost::Outcome::capped;
        return cost;
      }
      // Steps land on the run's sample times, as run_controlled_loop's do.
      double limit = t_end;
      if (grid > 0) limit = std::min(limit, grid_t0 + (std::floor((t - grid_t0) / grid + 1e-9) + 1) * grid);
      const bool clamped = t + dt > limit;
      double dt_try = clamped ? limit - t : dt;
      y.back() = t;
      const double t_before = t;
      if (stepper.try_step(stiff, y.data(), t, dt_try)) {
        ++cost.steps;
        if (clamped) t = limit;
        dt = clamped ? std::max(dt, dt_try) : dt_try;
      } else {
        dt = dt_try;
      }
      if (!(dt > 0) || (t == t_before && t + dt == t)) return cost;  // underflow: outcome failed
      for (std::size_t i = 0; i < x.size(); ++i)
        if (!std::isfinite(y[i])) return cost;
    }
  } catch (const std::exception&) {
    return cost;
  }
  cost.outcome = ProbeCost::Outcome::reached;
  return cost;
}

}  // namespace lagrangian::detail
