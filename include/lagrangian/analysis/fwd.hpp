#pragma once
// The tangent-flow analyses' options and results, declared for headers that
// name them without needing their members (lyapunov.hpp, floquet.hpp and
// sensitivity.hpp define them).

namespace lagrangian {

struct LyapunovOptions;
struct LyapunovResult;
struct FloquetOptions;
struct FloquetResult;
struct SensitivityOptions;
struct SensitivityResult;

}  // namespace lagrangian
