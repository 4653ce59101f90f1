// The stiff path of the driver: Odeint's rosenbrock4 behind StiffSystem.

#include <algorithm>
#include <cmath>
#include <limits>

#include "lagrangian/detail/stiff.hpp"
#include "loops.hpp"

namespace lagrangian::detail {

/// Odeint's rosenbrock4 (see detail/stiff.hpp). Its Jacobian ∂f/∂x is formed
/// by central differences of the right-hand side,
///   J_ij ≈ (f_i(x + h e_j) − f_i(x − h e_j)) / 2h,  h = ∛ε · max(|x_j|, 1),
/// with truncation error O(h²) ≈ 1e-10 relative; ∂f/∂t likewise.
void run_rosenbrock4(Run& run, StateVector& x) {
  const SimulationOptions& opt = run.options();
  struct Context {
    CountedRhs<> rhs;
    StateVector xa, fa, fb;
    int m;
  } ctx{run.rhs(), x, x, x, static_cast<int>(x.size())};
  const StiffSystem stiff{
      &ctx,
      [](void* c, const double* xin, double* dxdt, double t) {
        auto& k = *static_cast<Context*>(c);
        std::copy(xin, xin + k.m, k.xa.begin());
        k.rhs(k.xa, k.fa, t);
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
          k.rhs(k.xa, k.fa, t);
          k.xa[j] = xj - h;
          k.rhs(k.xa, k.fb, t);
          k.xa[j] = xj;
          for (int i = 0; i < m; ++i) J[i * m + j] = (k.fa[i] - k.fb[i]) / (2 * h);
        }
        const double ht = cbrt_eps * std::max(std::abs(t), 1.0);
        k.rhs(k.xa, k.fa, t + ht);
        k.rhs(k.xa, k.fb, t - ht);
        for (int i = 0; i < m; ++i) dfdt[i] = (k.fa[i] - k.fb[i]) / (2 * ht);
      }};
  Rosenbrock4Stepper stepper(ctx.m, opt.atol, opt.rtol);
  run_controlled_loop(
      run, x, [&](StateVector& xs, double& t, double& dt) { return stepper.try_step(stiff, xs.data(), t, dt); },
      [] {});
}

}  // namespace lagrangian::detail
