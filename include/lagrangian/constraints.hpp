#pragma once
// This header moved to lagrangian/mechanics/constraints.hpp (docs/architecture.md, "Layers").
// The old path keeps compiling until the next release; include the new one.
#include "lagrangian/mechanics/constraints.hpp"
