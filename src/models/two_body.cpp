// simulate() and eom_sample() compiled for the built-in models listed in lagrangian/models/two_body.hpp
// (see lagrangian/integrate/detail/compiled_models.hpp).
#include "lagrangian/models/two_body.hpp"
#include "lagrangian/integrate/detail/eom_sample.hpp"
#include "lagrangian/integrate/simulate.hpp"

LAGRANGIAN_TWO_BODY_MODELS(LAGRANGIAN_INSTANTIATE_SIMULATE)
LAGRANGIAN_TWO_BODY_MODELS(LAGRANGIAN_INSTANTIATE_EOM_SAMPLE)
