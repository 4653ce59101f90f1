// simulate() and eom_sample() compiled for the built-in models listed in lagrangian/models/pendulums.hpp
// (see lagrangian/integrate/detail/compiled_models.hpp).
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/integrate/detail/eom_sample.hpp"
#include "lagrangian/integrate/simulate.hpp"

LAGRANGIAN_PENDULUM_MODELS_A(LAGRANGIAN_INSTANTIATE_SIMULATE)
LAGRANGIAN_PENDULUM_MODELS_A(LAGRANGIAN_INSTANTIATE_EOM_SAMPLE)
