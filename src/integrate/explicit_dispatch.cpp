// The choice of the Odeint state for the explicit Runge–Kutta loops: a fixed
// array for n ≤ 12 coordinates (explicit_fixed_*.cpp), a vector above
// (explicit_dynamic.cpp). Only declarations here: each loop is compiled once.
#include "loops.hpp"

namespace lagrangian::detail {

void run_explicit(Run& run, StateVector& x) {
  switch (run.size()) {
#define LAGRANGIAN_FIXED_CASE(N) \
  case N:                        \
    return run_explicit_fixed<N>(run, x);
    LAGRANGIAN_FIXED_CASE(1)
    LAGRANGIAN_FIXED_CASE(2)
    LAGRANGIAN_FIXED_CASE(3)
    LAGRANGIAN_FIXED_CASE(4)
    LAGRANGIAN_FIXED_CASE(5)
    LAGRANGIAN_FIXED_CASE(6)
    LAGRANGIAN_FIXED_CASE(7)
    LAGRANGIAN_FIXED_CASE(8)
    LAGRANGIAN_FIXED_CASE(9)
    LAGRANGIAN_FIXED_CASE(10)
    LAGRANGIAN_FIXED_CASE(11)
    LAGRANGIAN_FIXED_CASE(12)
#undef LAGRANGIAN_FIXED_CASE
    default:
      return run_explicit_dynamic(run, x);
  }
}
static_assert(kMaxFixedStateSize == 12, "run_explicit lists the fixed sizes");

}  // namespace lagrangian::detail
