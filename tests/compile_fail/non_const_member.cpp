// Must NOT compile: kinetic() is not a const member function, and the
// library calls it on a const model. The test checks that the compiler says
// so in the library's one sentence.
#include "lagrangian/lagrangian.hpp"

struct NonConst {
  static constexpr int coordinate_count = 1;
  template <class S>
  S kinetic(const lagrangian::Vec<S, 1>&, const lagrangian::Vec<S, 1>& qd, const S&) {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const lagrangian::Vec<S, 1>& q, const S&) const {
    return 9.81 * q[0];
  }
};

int main() {
  lagrangian::State<1> s;
  return static_cast<int>(lagrangian::simulate(NonConst{}, s, {}).steps);
}
