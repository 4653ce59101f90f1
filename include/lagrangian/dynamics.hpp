#pragma once
// This header moved to lagrangian/mechanics/dynamics.hpp (docs/architecture.md, "Layers").
// The old path keeps compiling until the next release; include the new one.
#include "lagrangian/mechanics/dynamics.hpp"
