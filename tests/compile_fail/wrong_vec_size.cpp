// Must NOT compile: the model declares two coordinates but its kinetic() and
// potential() take Vec<S, 1>. The test checks that the compiler says so in
// the library's one sentence.
#include "lagrangian/lagrangian.hpp"

struct WrongSize {
  static constexpr int coordinate_count = 2;
  template <class S>
  S kinetic(const lagrangian::Vec<S, 1>&, const lagrangian::Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const lagrangian::Vec<S, 1>& q, const S&) const {
    return 9.81 * q[0];
  }
};

int main() {
  lagrangian::State<2> s;
  return static_cast<int>(lagrangian::simulate(WrongSize{}, s, {}).steps);
}
