// RunReport::to_json(): report.json, section by section.
#include <algorithm>
#include <array>
#include <cstddef>
#include <sstream>
#include <string>
#include <utility>

#include "lagrangian/detail/text_output.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/params.hpp"
#include "report_parts.hpp"

namespace lagrangian {

namespace {

/// The model, the method and its cost, the warnings and the monitors' verdicts.
void json_run(std::ostringstream& os, const RunReport& r) {
  os << "{\n  \"model\": ";
  detail::json_string(os, r.model);
  os << ",\n  \"coordinates\": [";
  for (std::size_t i = 0; i < r.coordinates.size(); ++i) {
    if (i) os << ", ";
    detail::json_string(os, r.coordinates[i]);
  }
  os << "],\n  \"method\": ";
  detail::json_string(os, r.method);
  os << ",\n  \"adaptive\": " << (r.adaptive ? "true" : "false");
  const std::pair<const char*, double> numbers[] = {
      {"rtol", r.rtol}, {"atol", r.atol}, {"dt", r.dt}, {"t0", r.t0}, {"t_end", r.t_end}, {"wall_time_s", r.wall_time_s}};
  for (const auto& [k, v] : numbers) {
    os << ",\n  \"" << k << "\": ";
    detail::json_number(os, v);
  }
  os << ",\n  \"steps\": " << r.steps << ",\n  \"rejected_steps\": " << r.rejected_steps
     << ",\n  \"rhs_evaluations\": " << r.rhs_evaluations << ",\n  \"newton_iterations\": " << r.newton_iterations
     << ",\n  \"samples\": " << r.samples << ",\n  \"stiffness_rho\": ";
  detail::json_number(os, r.stiffness_rho);
  os << ",\n  \"warnings\": [";
  for (std::size_t i = 0; i < r.warnings.size(); ++i) {
    os << (i ? ", " : "");
    detail::json_string(os, r.warnings[i]);
  }
  os << "]";
  os << ",\n  \"conservative\": " << (r.conservative ? "true" : "false");
  os << ",\n  \"drift_bound\": ";
  detail::json_number(os, r.drift_bound);
  os << ",\n  \"drift_exceeded\": " << (r.drift_exceeded ? "true" : "false");
  os << ",\n  \"monitors\": [";
  for (std::size_t i = 0; i < r.monitors.size(); ++i) {
    os << (i ? ", " : "") << "{\"name\": ";
    detail::json_string(os, r.monitors[i].name);
    os << ", \"figure\": ";
    detail::json_number(os, r.monitors[i].figure);
    os << ", \"exceeded\": " << (r.monitors[i].exceeded ? "true" : "false") << "}";
  }
  os << "],\n  \"coordinate_scale\": ";
  detail::json_number(os, r.coordinate_scale);
}

/// The energies, their drifts, the conserved momenta and the closed-form error.
void json_energy(std::ostringstream& os, const RunReport& r) {
  const std::pair<const char*, double> energy[] = {{"energy_scale", r.energy_scale},
                                                   {"energy_initial", r.energy_initial},
                                                   {"energy_final", r.energy_final},
                                                   {"energy_drift_max", r.energy_drift_max},
                                                   {"energy_drift_final", r.energy_drift_final},
                                                   {"energy_drift_relative_to_initial",
                                                    r.energy_drift_relative_to_initial()},
                                                   {"energy_drift_relative_to_initial_max",
                                                    r.energy_drift_relative_to_initial_max()}};
  for (const auto& [k, v] : energy) {
    os << ",\n  \"" << k << "\": ";
    detail::json_number(os, v);
  }
  os << ",\n  \"has_total_energy\": " << (r.has_total_energy ? "true" : "false");
  if (r.has_total_energy) {
    os << ",\n  \"total_energy_initial\": ";
    detail::json_number(os, r.total_energy_initial);
    os << ",\n  \"total_energy_drift_max\": ";
    detail::json_number(os, r.total_energy_drift_max);
    os << ",\n  \"total_energy_drift_final\": ";
    detail::json_number(os, r.total_energy_drift_final);
    os << ",\n  \"total_energy_final\": ";
    detail::json_number(os, r.total_energy_final);
    os << ",\n  \"total_energy_is_h\": " << (r.total_energy_is_h ? "true" : "false");
    os << ",\n  \"total_energy_drift_relative_to_initial\": ";
    detail::json_number(os, r.total_energy_drift_relative_to_initial());
    os << ",\n  \"total_energy_drift_relative_to_initial_max\": ";
    detail::json_number(os, r.total_energy_drift_relative_to_initial_max());
  }
  os << ",\n  \"conserved_momenta\": [";
  for (std::size_t i = 0; i < r.conserved_momenta.size(); ++i) {
    const auto& m = r.conserved_momenta[i];
    os << (i ? ", " : "") << "{\"coordinate\": ";
    detail::json_string(os, m.coordinate);
    os << ", \"initial\": ";
    detail::json_number(os, m.initial);
    os << ", \"max_abs_drift\": ";
    detail::json_number(os, m.max_abs_drift);
    os << ", \"final_abs_drift\": ";
    detail::json_number(os, m.final_abs_drift);
    os << ", \"rate_max\": ";
    detail::json_number(os, m.rate_max);
    os << "}";
  }
  os << "]";
  os << ",\n  \"has_reference\": " << (r.has_reference ? "true" : "false");
  if (r.has_reference) {
    os << ",\n  \"reference_error_max\": ";
    detail::json_number(os, r.reference_error_max);
    os << ",\n  \"reference_error_final\": ";
    detail::json_number(os, r.reference_error_final);
  }
}

/// P and L of the point masses: initial, conserved or why not, drift and scale.
void json_particles(std::ostringstream& os, const RunReport& r) {
  os << ",\n  \"has_particles\": " << (r.has_particles ? "true" : "false");
  if (r.has_particles) {
    auto vec = [&](const char* k, const std::array<double, 3>& v) {
      os << ",\n  \"" << k << "\": [";
      for (int i = 0; i < 3; ++i) {
        if (i) os << ", ";
        detail::json_number(os, v[static_cast<std::size_t>(i)]);
      }
      os << "]";
    };
    vec("linear_momentum_initial", r.linear_momentum_initial);
    vec("angular_momentum_initial", r.angular_momentum_initial);
    auto flags = [&](const char* k, const std::array<bool, 3>& v) {
      os << ",\n  \"" << k << "\": [" << (v[0] ? "true" : "false") << ", " << (v[1] ? "true" : "false") << ", "
         << (v[2] ? "true" : "false") << "]";
    };
    auto reasons = [&](const char* k, const std::array<std::string, 3>& v) {
      os << ",\n  \"" << k << "\": [";
      for (std::size_t i = 0; i < 3; ++i) {
        os << (i ? ", " : "");
        detail::json_string(os, v[i]);
      }
      os << "]";
    };
    flags("linear_momentum_conserved", r.linear_momentum_conserved);
    reasons("linear_momentum_not_conserved_because", r.linear_momentum_reason);
    flags("angular_momentum_conserved", r.angular_momentum_conserved);
    reasons("angular_momentum_not_conserved_because", r.angular_momentum_reason);
    const std::pair<const char*, double> pm[] = {{"linear_momentum_drift_max", r.linear_momentum_drift_max},
                                                 {"linear_momentum_drift_final", r.linear_momentum_drift_final},
                                                 {"angular_momentum_drift_max", r.angular_momentum_drift_max},
                                                 {"angular_momentum_drift_final", r.angular_momentum_drift_final},
                                                 {"momentum_scale", r.momentum_scale},
                                                 {"angular_momentum_scale", r.angular_momentum_scale}};
    for (const auto& [k, v] : pm) {
      os << ",\n  \"" << k << "\": ";
      detail::json_number(os, v);
    }
  }
}

/// The constraint residuals, ranks and stabilisation.
void json_constraints(std::ostringstream& os, const RunReport& r) {
  os << ",\n  \"constrained\": " << (r.constrained ? "true" : "false");
  if (r.constrained) {
    const ConstraintReport& c = r.constraints;
    os << ",\n  \"constraints\": {\"names\": [";
    for (std::size_t i = 0; i < c.names.size(); ++i) {
      if (i) os << ", ";
      detail::json_string(os, c.names[i]);
    }
    os << "], \"stabilization\": ";
    detail::json_string(os, c.stabilization);
    const std::pair<const char*, double> nums[] = {{"baumgarte_omega", c.baumgarte_omega},
                                                   {"max_position_residual", c.max_position_residual},
                                                   {"max_velocity_residual", c.max_velocity_residual},
                                                   {"final_position_residual", c.final_position_residual},
                                                   {"final_velocity_residual", c.final_velocity_residual},
                                                   {"stabilization_time_s", c.stabilization_time_s}};
    for (const auto& [k, v] : nums) {
      os << ", \"" << k << "\": ";
      detail::json_number(os, v);
    }
    os << ", \"projections\": " << c.projections << ", \"projection_iterations\": " << c.projection_iterations
       << ", \"extra_rhs_evaluations\": " << c.extra_rhs_evaluations << ", \"initial_rank\": " << c.initial_rank
       << ", \"min_rank\": " << c.min_rank << ", \"min_conditioning\": " << detail::format_number(c.min_conditioning)
       << ", \"min_conditioning_time\": " << detail::format_number(c.min_conditioning_time) << ", \"warnings\": [";
    for (std::size_t i = 0; i < c.warnings.size(); ++i) {
      if (i) os << ", ";
      detail::json_string(os, c.warnings[i]);
    }
    os << "]}";
  }
}

/// Event counts by kind, the first 20 in full and every rest.
void json_events(std::ostringstream& os, const RunReport& r) {
  // Events: counts by kind, the times of stops, and the first few in full
  // (the whole log goes to write_events_csv).
  const auto counts = detail::event_counts(r.events);
  os << ",\n  \"events\": {\"count\": " << r.events.size() << ", \"not_logged\": " << r.unlogged_events
     << ", \"truncated\": " << (r.unlogged_events > 0 ? "true" : "false");
  for (int k = 0; k < 5; ++k) os << ", \"" << to_string(static_cast<EventKind>(k)) << "\": " << counts[static_cast<std::size_t>(k)];
  os << ", \"impact_energy_loss\": ";
  detail::json_number(os, r.impact_energy_loss);
  if (!r.wall_impulses.empty()) {
    os << ", \"wall_impulses\": {";
    std::size_t k = 0;
    for (const auto& [name, impulse] : r.wall_impulses) {
      os << (k++ ? ", " : "");
      detail::json_string(os, name);
      os << ": ";
      detail::json_number(os, impulse);
    }
    os << "}";
  }
  os << ", \"first\": [";
  const std::size_t shown = std::min<std::size_t>(r.events.size(), 20);
  for (std::size_t i = 0; i < shown; ++i) {
    const EventRecord& e = r.events[i];
    os << (i ? ", " : "") << "{\"t\": ";
    detail::json_number(os, e.t);
    os << ", \"kind\": ";
    detail::json_string(os, to_string(e.kind));
    os << ", \"name\": ";
    detail::json_string(os, e.name);
    const std::pair<const char*, double> f[] = {{"impulse", e.impulse},
                                                {"approach_speed", e.approach_speed},
                                                {"separation_speed", e.separation_speed},
                                                {"ke_before", e.kinetic_energy_before},
                                                {"ke_after", e.kinetic_energy_after},
                                                {"zeno_cutoff", e.zeno_cutoff}};
    for (const auto& [k, v] : f) {
      os << ", \"" << k << "\": ";
      detail::json_number(os, v);
    }
    os << "}";
  }
  os << "], \"rests\": [";  // every rest, logged beyond the first 20 or not, with the Zeno rule's cut-off
  bool first_rest = true;
  for (const EventRecord& e : r.events) {
    if (e.kind != EventKind::rest) continue;
    os << (first_rest ? "" : ", ") << "{\"t\": ";
    detail::json_number(os, e.t);
    os << ", \"name\": ";
    detail::json_string(os, e.name);
    os << ", \"zeno_cutoff\": ";
    detail::json_number(os, e.zeno_cutoff);
    os << "}";
    first_rest = false;
  }
  os << "]}";
}

}  // namespace

std::string RunReport::to_json() const {
  std::ostringstream os;
  json_run(os, *this);
  json_energy(os, *this);
  json_particles(os, *this);
  json_constraints(os, *this);
  json_events(os, *this);
  os << ",\n  \"t_final\": ";
  detail::json_number(os, t_final);
  os << ",\n  \"stopped_by\": ";
  if (stopped_by.empty()) {
    os << "null";
  } else {
    detail::json_string(os, stopped_by);
  }
  os << "\n}\n";
  return os.str();
}

}  // namespace lagrangian
