// The explicit Runge–Kutta loops on std::array<double, 2n> for n = 5 … 8.
#include "lagrangian/integrate/detail/explicit_loops.hpp"
#include "loops.hpp"

namespace lagrangian::detail {

template void run_explicit_fixed<5>(Run&, StateVector&);
template void run_explicit_fixed<6>(Run&, StateVector&);
template void run_explicit_fixed<7>(Run&, StateVector&);
template void run_explicit_fixed<8>(Run&, StateVector&);

}  // namespace lagrangian::detail
