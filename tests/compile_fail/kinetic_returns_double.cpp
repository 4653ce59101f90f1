// Must NOT compile: kinetic() is a template on S but returns double, so the
// derivatives that automatic differentiation carries in S would be dropped.
// The test checks that the compiler says so in the library's one sentence.
#include "lagrangian/lagrangian.hpp"

struct DoubleKinetic {
  static constexpr int coordinate_count = 1;
  template <class S>
  double kinetic(const lagrangian::Vec<S, 1>&, const lagrangian::Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const lagrangian::Vec<S, 1>& q, const S&) const {
    return 9.81 * q[0];
  }
};

int main() {
  lagrangian::State<1> s;
  return static_cast<int>(lagrangian::simulate(DoubleKinetic{}, s, {}).steps);
}
