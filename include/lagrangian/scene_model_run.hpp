#pragma once
// This header moved to lagrangian/scene/model_run.hpp (docs/architecture.md, "Layers").
// The old path keeps compiling until the next release; include the new one.
#include "lagrangian/scene/model_run.hpp"
