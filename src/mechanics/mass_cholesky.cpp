// The Cholesky factors of a mass matrix (mechanics/detail/mass_cholesky.hpp),
// compiled once for run-time sizes and the fixed sizes of the library's
// models and tangent flow.

#include "lagrangian/mechanics/detail/mass_cholesky.hpp"

namespace lagrangian::detail {

template class MassCholesky<Dynamic>;
template class MassCholesky<1>;
template class MassCholesky<2>;
template class MassCholesky<3>;
template class MassCholesky<4>;
template class MassCholesky<5>;
template class MassCholesky<6>;
template class MassCholesky<7>;
template class MassCholesky<8>;
template class MassCholesky<9>;
template class MassCholesky<10>;

}  // namespace lagrangian::detail
