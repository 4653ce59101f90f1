// Must NOT compile: accelerations() on a model with a constraint would give
// the free motion, ignoring the rod (a particle on a sphere falling through
// it). The test checks that the compiler says so in the library's one
// sentence, naming constrained_accelerations(), and nothing else.
#include "lagrangian/lagrangian.hpp"

struct ParticleOnRod {
  static constexpr int coordinate_count = 2;
  template <class S>
  S kinetic(const lagrangian::Vec<S, 2>&, const lagrangian::Vec<S, 2>& qd, const S&) const {
    return 0.5 * qd.squaredNorm();
  }
  template <class S>
  S potential(const lagrangian::Vec<S, 2>& q, const S&) const {
    return 9.81 * q[1];
  }
  template <class S>
  lagrangian::Vec<S, 1> holonomic(const lagrangian::Vec<S, 2>& q, const S&) const {
    return lagrangian::Vec<S, 1>(q.squaredNorm() - 1.0);
  }
};

int main() {
  const lagrangian::Vec<double, 2> q(0.6, -0.8), qd(0.8, 0.6);
  return static_cast<int>(lagrangian::accelerations(ParticleOnRod{}, q, qd, 0.0)[0]);
}
