#pragma once
// This header moved to lagrangian/integrate/report.hpp (docs/architecture.md, "Layers").
// The old path keeps compiling until the next release; include the new one.
#include "lagrangian/integrate/report.hpp"
