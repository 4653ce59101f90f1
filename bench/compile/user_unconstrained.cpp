// A user's own translation unit, timed by scripts/time-user-tu: one
// unconstrained model written from the docs (a spring pendulum: a bob of
// mass m on a spring of stiffness k and rest length L0, polar coordinates
// r, θ) and one simulate() call.
#include <cmath>
#include <cstdio>

#include <lagrangian/lagrangian.hpp>

struct SpringPendulum {
  static constexpr int dof = 2;
  double m = 1.0, k = 40.0, L0 = 1.0, g = 9.81;
  /// T = ½ m (ṙ² + r² θ̇²) (J)
  template <class S>
  S kinetic(const lagrangian::Vec<S, 2>& q, const lagrangian::Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + q[0] * q[0] * qd[1] * qd[1]);
  }
  /// V = ½ k (r − L0)² − m g r cos θ (J)
  template <class S>
  S potential(const lagrangian::Vec<S, 2>& q, const S&) const {
    using std::cos;
    return 0.5 * k * (q[0] - L0) * (q[0] - L0) - m * g * q[0] * cos(q[1]);
  }
};

int main() {
  lagrangian::State<2> s;
  s.q << 1.2, 0.5;
  lagrangian::SimulationOptions o;
  o.t_end = 10.0;
  const auto report = lagrangian::simulate(SpringPendulum{}, s, o);
  std::printf("%s", report.summary().c_str());
  return report.energy_drift_max < 1e-6 ? 0 : 1;
}
