// lyapunov_spectrum(), floquet_multipliers() and sensitivities() compiled for
// the built-in models listed in lagrangian/models/impacts.hpp (see
// lagrangian/analysis/detail/compiled_tangent_flow.hpp).
#include "lagrangian/analysis/floquet.hpp"
#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/models/impacts.hpp"

LAGRANGIAN_IMPACT_MODELS(LAGRANGIAN_INSTANTIATE_TANGENT_FLOW)
