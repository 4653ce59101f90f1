// The stiff path of the driver: Odeint's rosenbrock4 behind StiffSystem.

#include <algorithm>
#include <cmath>
#include <limits>

#include "lagrangian/detail/stiff.hpp"
#include "loops.hpp"

namespace lagrangian::detail {

/// Odeint's rosenbrock4 (see detail/stiff.hpp) on the autonomous system
/// y = [x; τ], ẏ = [f(x, τ); 1]: Odeint's treatment of an explicit time
/// dependence through ∂f/∂t is wrong (a driven oscillator lost four orders
/// of accuracy and took 85 times the steps, with ∂f/∂t exact or not), while
/// the autonomous form is the one its Rosenbrock coefficients are derived
/// for. τ is integrated exactly (it is linear) and equals t. The Jacobian
///   ∂ẏ/∂y = [[∂f/∂x, ∂f/∂τ], [0, 0]]
/// is formed by central differences of the right-hand side,
///   J_ij ≈ (f_i(y + h e_j) − f_i(y − h e_j)) / 2h,  h = ∛ε · max(|y_j|, 1),
/// with truncation error O(h²) ≈ 1e-10 relative.
void run_rosenbrock4(Run& run, StateVector& x) {
  const SimulationOptions& opt = run.options();
  struct Context {
    CountedRhs<> rhs;
    StateVector xa, fa, fb;
    int m;  ///< 2n, the driver's state; the stepper's has one more value, τ
  } ctx{run.rhs(), x, x, x, static_cast<int>(x.size())};
  const StiffSystem stiff{
      &ctx,
      [](void* c, const double* yin, double* dydt, double) {
        auto& k = *static_cast<Context*>(c);
        std::copy(yin, yin + k.m, k.xa.begin());
        k.rhs(k.xa, k.fa, yin[k.m]);
        std::copy(k.fa.begin(), k.fa.end(), dydt);
        dydt[k.m] = 1.0;
      },
      [](void* c, const double* yin, double* J, double* dfdt, double) {
        auto& k = *static_cast<Context*>(c);
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
  // Odeint's controller measures the error as an RMS over the state's
  // values; τ's error is zero, so the tolerances scaled by √(m / (m + 1))
  // accept exactly the steps they would accept on x alone.
  const double scale = std::sqrt(static_cast<double>(ctx.m) / (ctx.m + 1));
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

}  // namespace lagrangian::detail
