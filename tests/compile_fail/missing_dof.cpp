// Must NOT compile: the model does not declare its number of coordinates.
#include "lagrangian/lagrangian.hpp"

struct NoDof {
  template <class S>
  S lagrangian(const lagrangian::Vec<S, 1>&, const lagrangian::Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
};

int main() {
  lagrangian::check_model<NoDof>();
  return 0;
}
