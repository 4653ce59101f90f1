// The explicit Runge–Kutta loops on std::array<double, 2n> for n = 9 … 12.
#include "lagrangian/integrate/detail/explicit_loops.hpp"
#include "loops.hpp"

namespace lagrangian::detail {

template void run_explicit_fixed<9>(Run&, StateVector&);
template void run_explicit_fixed<10>(Run&, StateVector&);
template void run_explicit_fixed<11>(Run&, StateVector&);
template void run_explicit_fixed<12>(Run&, StateVector&);

}  // namespace lagrangian::detail
