#pragma once
// Internal: kinetic theory against a finished run of a gas (GasCheck).

#include <optional>

#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/run.hpp"

namespace lagrangian::scene::detail {

/// The check for a run of `scene` (gas expanded) when it is a gas (see
/// GasCheck: equal spheres, elastic box and collisions, nothing else, wall
/// impulses reported), else nothing.
std::optional<GasCheck> gas_check(const Scene& scene, const RunResult& result);

}  // namespace lagrangian::scene::detail
