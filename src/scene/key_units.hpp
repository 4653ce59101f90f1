#pragma once
// Internal: the SI unit of a scene key and of a sweep table's column, for
// axis labels ("" for a pure number or a count).

#include <string>

#include "lagrangian/scene/scene.hpp"

namespace lagrangian::scene::detail {

/// The unit of a velocity for a coordinate of unit `u` ("m" → "m/s", "" → "1/s"),
/// and of the momentum conjugate to it ("rad" → "kg*m^2/s", "m" → "kg*m/s").
std::string velocity_unit(const std::string& u);
std::string momentum_unit(const std::string& u);

/// The unit of a numeric scene key as written in a file or given to --vary,
/// --set: "model.parameters.l1" → the catalog's "m", "model.q[0]" → the
/// coordinate's, "bodies[0].velocity[2]" → "m/s", "run.t_end" → "s",
/// "springs[1].stiffness" → "N/m"; "" for unitless keys (tolerances,
/// restitution, counts) and keys it does not know.
std::string key_unit(const Scene& scene, const std::string& key);

/// The unit of a column of sweep.csv: t_final, first_/last_<event>,
/// t_<crossing>, wall_time_s → "s"; q_<c> and qd_<c> → the coordinate's
/// unit and its rate's; impact_energy_loss → "J"; a varied or set key →
/// key_unit(); relative drifts, counts and unknown columns → "".
std::string column_unit(const Scene& scene, const std::string& column);

}  // namespace lagrangian::scene::detail
