// The explicit Runge–Kutta loops on a run-time sized state (n > 12).
#include "lagrangian/integrate/detail/explicit_loops.hpp"
#include "loops.hpp"

namespace lagrangian::detail {

void run_explicit_dynamic(Run& run, StateVector& x) { run_explicit_on(run, x, run.rhs()); }
template struct SubStep<StateVector>;  // also used by rosenbrock_loop.cpp

}  // namespace lagrangian::detail
