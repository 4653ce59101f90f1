// The explicit Runge–Kutta loops on a run-time sized state (n > 12).
#include "explicit_loops.hpp"

namespace lagrangian::detail {

template void run_explicit_on<StateVector>(Run&, StateVector&);
template struct SubStep<StateVector>;  // also used by rosenbrock_loop.cpp

}  // namespace lagrangian::detail
