// Must NOT compile: the holonomic constraint returns a scalar instead of a
// Vec<S, 1>. The test checks that the compiler says so in the library's one
// sentence, and nothing else.
#include "lagrangian/lagrangian.hpp"

struct ScalarRod {
  static constexpr int dof = 2;
  template <class S>
  S kinetic(const lagrangian::Vec<S, 2>&, const lagrangian::Vec<S, 2>& qd, const S&) const {
    return 0.5 * qd.squaredNorm();
  }
  template <class S>
  S potential(const lagrangian::Vec<S, 2>& q, const S&) const {
    return 9.81 * q[1];
  }
  template <class S>
  S holonomic(const lagrangian::Vec<S, 2>& q, const S&) const {
    return q.squaredNorm() - 1.0;
  }
};

int main() {
  lagrangian::State<2> s;
  s.q << 0.0, -1.0;
  return static_cast<int>(lagrangian::simulate(ScalarRod{}, s, {}).steps);
}
