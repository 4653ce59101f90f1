#pragma once
// This header moved to lagrangian/scene/progress.hpp (docs/architecture.md, "Layers").
// The old path keeps compiling until the next release; include the new one.
#include "lagrangian/scene/progress.hpp"
