// lyapunov_spectrum(), floquet_multipliers() and sensitivities() compiled for
// the built-in models listed in lagrangian/models/projectile.hpp and
// lagrangian/models/two_body.hpp (see
// lagrangian/analysis/detail/compiled_tangent_flow.hpp).
#include "lagrangian/analysis/floquet.hpp"
#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/models/projectile.hpp"
#include "lagrangian/models/two_body.hpp"

LAGRANGIAN_PROJECTILE_MODELS(LAGRANGIAN_INSTANTIATE_TANGENT_FLOW)
LAGRANGIAN_TWO_BODY_MODELS(LAGRANGIAN_INSTANTIATE_TANGENT_FLOW)
