#pragma once
// This header moved to lagrangian/view/view.hpp (docs/architecture.md, "Layers").
// The old path keeps compiling until the next release; include the new one.
#include "lagrangian/view/view.hpp"
