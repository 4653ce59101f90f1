// A user's own translation unit, timed by scripts/time-user-tu: two
// formulations of one Atwood machine (masses m1, m2 on a string of length L
// over a fixed pulley), each with a holonomic constraint, their degrees of
// freedom (dof_report), q̈ by constrained_accelerations() and one simulate()
// call each. Both must give the closed form ÿ1 = −(m1 − m2) g / (m1 + m2).
#include <cmath>
#include <cstdio>

#include <lagrangian/lagrangian.hpp>

namespace {
constexpr double m1 = 2.0, m2 = 1.0, g = 9.81, L = 3.0, d = 0.5;

/// Heights y1, y2 (m) of the two masses; the string: y1 + y2 = −L (m).
struct AtwoodHeights {
  static constexpr int dof = 2;
  /// T = ½ m1 ẏ1² + ½ m2 ẏ2² (J)
  template <class S>
  S kinetic(const lagrangian::Vec<S, 2>&, const lagrangian::Vec<S, 2>& qd, const S&) const {
    return 0.5 * m1 * qd[0] * qd[0] + 0.5 * m2 * qd[1] * qd[1];
  }
  /// V = m1 g y1 + m2 g y2 (J)
  template <class S>
  S potential(const lagrangian::Vec<S, 2>& q, const S&) const {
    return m1 * g * q[0] + m2 * g * q[1];
  }
  template <class S>
  lagrangian::Vec<S, 1> holonomic(const lagrangian::Vec<S, 2>& q, const S&) const {
    lagrangian::Vec<S, 1> c;
    c[0] = q[0] + q[1] + L;
    return c;
  }
};

/// Cartesian positions (x1, y1, x2, y2) (m); the masses hang at x = ∓d and
/// the string keeps y1 + y2 = −L: three constraints (m).
struct AtwoodCartesian {
  static constexpr int dof = 4;
  /// T = ½ m1 (ẋ1² + ẏ1²) + ½ m2 (ẋ2² + ẏ2²) (J)
  template <class S>
  S kinetic(const lagrangian::Vec<S, 4>&, const lagrangian::Vec<S, 4>& qd, const S&) const {
    return 0.5 * m1 * (qd[0] * qd[0] + qd[1] * qd[1]) + 0.5 * m2 * (qd[2] * qd[2] + qd[3] * qd[3]);
  }
  /// V = m1 g y1 + m2 g y2 (J)
  template <class S>
  S potential(const lagrangian::Vec<S, 4>& q, const S&) const {
    return m1 * g * q[1] + m2 * g * q[3];
  }
  template <class S>
  lagrangian::Vec<S, 3> holonomic(const lagrangian::Vec<S, 4>& q, const S&) const {
    lagrangian::Vec<S, 3> c;
    c << q[0] + d, q[2] - d, q[1] + q[3] + L;
    return c;
  }
};
}  // namespace

int main() {
  const double exact = -(m1 - m2) * g / (m1 + m2);
  int failures = 0;
  lagrangian::State<2> a;
  a.q << -1.0, -2.0;
  lagrangian::State<4> b;
  b.q << -d, -1.0, d, -2.0;
  const auto da = lagrangian::dof_report(AtwoodHeights{}, a), db = lagrangian::dof_report(AtwoodCartesian{}, b);
  std::printf("%s%s", da.summary().c_str(), db.summary().c_str());
  failures += da.degrees_of_freedom != 1 || db.degrees_of_freedom != 1;
  lagrangian::Workspace<2> wa;
  lagrangian::ConstraintWorkspaceFor<AtwoodHeights> ca;
  lagrangian::Vec<double, 2> qdda;
  lagrangian::constrained_accelerations(AtwoodHeights{}, wa, ca, a.q, a.qd, 0.0, qdda);
  lagrangian::Workspace<4> wb;
  lagrangian::ConstraintWorkspaceFor<AtwoodCartesian> cb;
  lagrangian::Vec<double, 4> qddb;
  lagrangian::constrained_accelerations(AtwoodCartesian{}, wb, cb, b.q, b.qd, 0.0, qddb);
  failures += std::abs(qdda[0] - exact) > 1e-12 || std::abs(qddb[1] - exact) > 1e-12;
  lagrangian::SimulationOptions o;
  o.t_end = 0.5;
  const auto ra = lagrangian::simulate(AtwoodHeights{}, a, o);
  const auto rb = lagrangian::simulate(AtwoodCartesian{}, b, o);
  std::printf("%s%s", ra.summary().c_str(), rb.summary().c_str());
  failures += ra.constraints.max_position_residual > 1e-9 || rb.constraints.max_position_residual > 1e-9;
  return failures;
}
