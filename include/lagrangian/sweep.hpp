#pragma once
// This header moved to lagrangian/scene/sweep.hpp (docs/architecture.md, "Layers").
// The old path keeps compiling until the next release; include the new one.
#include "lagrangian/scene/sweep.hpp"
