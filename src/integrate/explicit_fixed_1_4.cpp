// The explicit Runge–Kutta loops on std::array<double, 2n> for n = 1 … 4.
#include "lagrangian/integrate/detail/explicit_loops.hpp"
#include "loops.hpp"

namespace lagrangian::detail {

template void run_explicit_fixed<1>(Run&, StateVector&);
template void run_explicit_fixed<2>(Run&, StateVector&);
template void run_explicit_fixed<3>(Run&, StateVector&);
template void run_explicit_fixed<4>(Run&, StateVector&);

}  // namespace lagrangian::detail
