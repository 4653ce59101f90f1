#pragma once
// This header moved to lagrangian/analysis/equilibria.hpp (docs/architecture.md, "Layers").
// The old path keeps compiling until the next release; include the new one.
#include "lagrangian/analysis/equilibria.hpp"
