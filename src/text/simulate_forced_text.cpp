// simulate() compiled once, in the library, for the text model with forces
// and dissipation (see lagrangian/detail/compiled_models.hpp).
#include "lagrangian/simulate.hpp"
#include "lagrangian/text/text_model.hpp"

LAGRANGIAN_INSTANTIATE_SIMULATE(lagrangian::text::ForcedTextModel)
