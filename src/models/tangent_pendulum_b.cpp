// lyapunov_spectrum(), floquet_multipliers() and sensitivities() compiled for
// the built-in models listed in lagrangian/models/pendulums.hpp (see
// lagrangian/analysis/detail/compiled_tangent_flow.hpp).
#include "lagrangian/analysis/floquet.hpp"
#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/models/pendulums.hpp"

LAGRANGIAN_PENDULUM_MODELS_B(LAGRANGIAN_INSTANTIATE_TANGENT_FLOW)
