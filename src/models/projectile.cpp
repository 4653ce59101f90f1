// simulate() compiled for the built-in models listed in lagrangian/models/projectile.hpp
// (see lagrangian/detail/compiled_models.hpp).
#include "lagrangian/models/projectile.hpp"
#include "lagrangian/simulate.hpp"

LAGRANGIAN_PROJECTILE_MODELS(LAGRANGIAN_INSTANTIATE_SIMULATE)
