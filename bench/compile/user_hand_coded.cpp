// A user's own translation unit, timed by scripts/time-user-tu: a model
// that supplies its own q̈ (the spring pendulum of user_unconstrained.cpp
// with its equations of motion written out), wrapped by lagrangian::inlined()
// so that the explicit methods are compiled here with that q̈ inlined, and
// one simulate() call.
#include <cmath>
#include <cstdio>

#include <lagrangian/integrate/inlined.hpp>
#include <lagrangian/lagrangian.hpp>

struct SpringPendulum {
  static constexpr int coordinate_count = 2;
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
  /// r̈ = r θ̇² − (k/m)(r − L0) + g cos θ (m/s²), θ̈ = −(2 ṙ θ̇ + g sin θ)/r (rad/s²)
  void accelerations(const lagrangian::Vec<double, 2>& q, const lagrangian::Vec<double, 2>& qd, double,
                     lagrangian::Vec<double, 2>& qdd) const {
    qdd[0] = q[0] * qd[1] * qd[1] - (k / m) * (q[0] - L0) + g * std::cos(q[1]);
    qdd[1] = -(2.0 * qd[0] * qd[1] + g * std::sin(q[1])) / q[0];
  }
};

int main() {
  lagrangian::State<2> s;
  s.q << 1.2, 0.5;
  lagrangian::SimulationOptions o;
  o.t_end = 10.0;
  const auto report = lagrangian::simulate(lagrangian::inlined(SpringPendulum{}), s, o);
  std::printf("%s", report.summary().c_str());
  return report.energy_drift_max < 1e-6 ? 0 : 1;
}
