// A user's own translation unit, timed by scripts/time-user-tu: one
// constrained model written from the docs (a bead on a parabola z = a x²
// spinning at ω about the vertical axis, in Cartesian coordinates of the
// rotating frame with the parabola as a holonomic constraint) and one
// simulate() call.
#include <cmath>
#include <cstdio>

#include <lagrangian/lagrangian.hpp>

struct BeadOnSpinningParabola {
  static constexpr int dof = 2;  // x (m), z (m) in the rotating frame
  double m = 1.0, a = 0.5, omega = 3.0, g = 9.81;
  /// T = ½ m (ẋ² + ż² + ω² x²) (J): the rotation adds the centrifugal term.
  template <class S>
  S kinetic(const lagrangian::Vec<S, 2>& q, const lagrangian::Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1] + omega * omega * q[0] * q[0]);
  }
  /// V = m g z (J)
  template <class S>
  S potential(const lagrangian::Vec<S, 2>& q, const S&) const {
    return m * g * q[1];
  }
  /// g(q) = z − a x² = 0 (m)
  template <class S>
  lagrangian::Vec<S, 1> holonomic(const lagrangian::Vec<S, 2>& q, const S&) const {
    lagrangian::Vec<S, 1> c;
    c[0] = q[1] - a * q[0] * q[0];
    return c;
  }
};

int main() {
  lagrangian::State<2> s;
  s.q << 0.4, 0.5 * 0.4 * 0.4;
  lagrangian::SimulationOptions o;
  o.t_end = 10.0;
  const auto report = lagrangian::simulate(BeadOnSpinningParabola{}, s, o);
  std::printf("%s", report.summary().c_str());
  return report.constraints.max_position_residual < 1e-9 ? 0 : 1;
}
