// Must NOT compile: T and V take double, not a template scalar, so automatic
// differentiation cannot instantiate them.
#include <cmath>

#include "lagrangian/lagrangian.hpp"

struct DoubleOnly {
  static constexpr int dof = 1;
  double kinetic(const lagrangian::Vec<double, 1>&, const lagrangian::Vec<double, 1>& qd, const double&) const {
    return 0.5 * qd[0] * qd[0];
  }
  double potential(const lagrangian::Vec<double, 1>& q, const double&) const { return -std::cos(q[0]); }
};

int main() {
  return static_cast<int>(lagrangian::accelerations(DoubleOnly{}, lagrangian::Vec<double, 1>(0.1),
                                                    lagrangian::Vec<double, 1>(0.0))[0]);
}
