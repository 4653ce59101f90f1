// Must NOT compile: the model has no potential. The test checks that the
// compiler's message is the library's sentence.
#include "lagrangian/lagrangian.hpp"

struct NoPotential {
  static constexpr int dof = 1;
  template <class S>
  S kinetic(const lagrangian::Vec<S, 1>&, const lagrangian::Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
};

int main() {
  lagrangian::State<1> s;
  return static_cast<int>(lagrangian::simulate(NoPotential{}, s, {}).steps);
}
