#pragma once
// This header moved to lagrangian/scene/text_model.hpp (docs/architecture.md, "Layers").
// The old path keeps compiling until the next release; include the new one.
#include "lagrangian/scene/text_model.hpp"
