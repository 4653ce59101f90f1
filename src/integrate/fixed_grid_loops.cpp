// The fixed-step loops of the driver for the structure-preserving methods:
// Odeint's symplectic steppers and the system's own variational stepper.

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include <boost/numeric/odeint/stepper/symplectic_rkn_sb3a_mclachlan.hpp>
#include <boost/numeric/odeint/stepper/velocity_verlet.hpp>

#include "loops.hpp"

namespace lagrangian::detail {

namespace {

/// Cubic Hermite interpolation of [q; q̇] inside a fixed step from (t0, x0)
/// to (t1, x1) (2n values each): q from its end values and slopes q̇, q̇ as
/// the derivative of that cubic. Used only for samples between steps.
void hermite_state(double t0, const double* x0, double t1, const double* x1, int size, double t, double* out) {
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
template <class Advance>
void run_fixed_grid(Run& run, StateVector& x, Advance&& advance) {
  const SimulationOptions& opt = run.options();
  std::uint64_t k = 0;
  double t = opt.t0;
  StateVector x_old = x;
  const int size = run.size();
  while (!reached(t, opt.t_end) && !run.stopped()) {
    const double t_grid = opt.t0 + static_cast<double>(k + 1) * opt.dt;
    const double t_next = reached(t_grid, opt.t_end) || t_grid > opt.t_end ? opt.t_end : t_grid;
    const double t_old = t;
    x_old = x;
    advance(t, t_next - t, x);
    t = t_next;
    ++k;
    run.stabilize(x.data(), t, false);
    run.accepted(t_old, t, x.data(),
                 [&](double to, double* out) { hermite_state(t_old, x_old.data(), t, x.data(), size, to, out); });
  }
}

}  // namespace

void run_variational(Run& run, StateVector& x) {
  System& system = run.system();
  run_fixed_grid(run, x, [&](double t, double h, StateVector& xs) { system.variational_step(t, h, xs.data()); });
}

/// Odeint's symplectic_rkn_sb3a_mclachlan or velocity_verlet on q̈ = a(q, t),
/// a = the second half of f([q; 0], t), for a separable system (checked by
/// the caller), at fixed step dt. The pair (q, q̇) is integrated; with a
/// constant M, (q, M q̇) is canonical, so the map is symplectic.
void run_symplectic(Run& run, StateVector& x) {
  namespace odeint = boost::numeric::odeint;
  using V = std::vector<double>;
  const SimulationOptions& opt = run.options();
  const CountedRhs<> rhs = run.rhs();
  const auto size = static_cast<std::size_t>(run.size());
  V q(size), v(size);
  StateVector xa(2 * size, 0.0), fa(2 * size, 0.0);
  auto acceleration = [&](const V& qin, V& a, double t) {
    std::copy(qin.begin(), qin.end(), xa.begin());  // q̇ = 0: separable, q̈ does not depend on q̇
    rhs(xa, fa, t);
    std::copy(fa.begin() + static_cast<std::ptrdiff_t>(size), fa.end(), a.begin());
  };
  auto unpack = [&](const StateVector& xs) {
    std::copy(xs.begin(), xs.begin() + static_cast<std::ptrdiff_t>(size), q.begin());
    std::copy(xs.begin() + static_cast<std::ptrdiff_t>(size), xs.end(), v.begin());
  };
  auto pack = [&](StateVector& xs) {
    std::copy(q.begin(), q.end(), xs.begin());
    std::copy(v.begin(), v.end(), xs.begin() + static_cast<std::ptrdiff_t>(size));
  };
  unpack(x);
  if (opt.method == Method::velocity_verlet) {
    odeint::velocity_verlet<V> stepper;
    auto sys = [&](const V& qin, const V&, V& a, double t) { acceleration(qin, a, t); };
    run_fixed_grid(run, x, [&](double t, double h, StateVector& xs) {
      stepper.do_step(sys, std::make_pair(std::ref(q), std::ref(v)), t, h);
      pack(xs);
    });
  } else {
    odeint::symplectic_rkn_sb3a_mclachlan<V> stepper;
    double t_now = opt.t0;  // the momentum function of odeint's RKN steppers gets no time
    auto coordinate_rate = [](const V& vin, V& dqdt) { dqdt = vin; };
    auto momentum_rate = [&](const V& qin, V& dvdt) { acceleration(qin, dvdt, t_now); };
    run_fixed_grid(run, x, [&](double t, double h, StateVector& xs) {
      t_now = t;
      stepper.do_step(std::make_pair(coordinate_rate, momentum_rate), std::make_pair(std::ref(q), std::ref(v)), t, h);
      pack(xs);
    });
  }
}

}  // namespace lagrangian::detail
