// simulate() and eom_sample() compiled for the built-in models listed in lagrangian/models/constrained.hpp
// (see lagrangian/integrate/detail/compiled_models.hpp).
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/integrate/detail/eom_sample.hpp"
#include "lagrangian/integrate/simulate.hpp"

LAGRANGIAN_CONSTRAINED_MODELS_B(LAGRANGIAN_INSTANTIATE_SIMULATE)
LAGRANGIAN_CONSTRAINED_MODELS_B(LAGRANGIAN_INSTANTIATE_EOM_SAMPLE)
