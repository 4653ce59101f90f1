// simulate() compiled for the built-in models listed in lagrangian/models/pendulums.hpp
// (see lagrangian/detail/compiled_models.hpp).
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/simulate.hpp"

LAGRANGIAN_PENDULUM_MODELS_B(LAGRANGIAN_INSTANTIATE_SIMULATE)
