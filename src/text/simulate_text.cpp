// simulate(), eom_sample() and the Euler–Lagrange pass compiled once, in the library, for
// text models (see lagrangian/integrate/detail/compiled_models.hpp and
// lagrangian/text/text_model.hpp).
#include "lagrangian/integrate/detail/eom_sample.hpp"
#include "lagrangian/integrate/simulate.hpp"
#include "lagrangian/text/text_model.hpp"

LAGRANGIAN_INSTANTIATE_SIMULATE(lagrangian::text::TextModel)
LAGRANGIAN_INSTANTIATE_EOM_SAMPLE(lagrangian::text::TextModel)
template LAGRANGIAN_TEXT_EOM_PASS(lagrangian::text::TextModel)
