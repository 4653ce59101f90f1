#include "lagrangian/integrate/report.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>

#include "lagrangian/detail/csv_header.hpp"
#include "lagrangian/detail/text_output.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/params.hpp"
#include "report_parts.hpp"

namespace lagrangian {

const char* to_string(Stabilization s) {
  switch (s) {
    case Stabilization::none: return "none";
    case Stabilization::baumgarte: return "baumgarte";
    case Stabilization::projection: return "projection";
  }
  return "unknown";
}

const char* to_string(EventKind k) {
  switch (k) {
    case EventKind::impact: return "impact";
    case EventKind::rest: return "rest";
    case EventKind::release: return "release";
    case EventKind::watched: return "event";
    case EventKind::stop: return "stop";
  }
  return "unknown";
}

namespace detail {

void json_string(std::ostringstream& os, const std::string& s) {
  os << '"';
  for (const char c : s) {
    switch (c) {
      case '"': os << "\\\""; break;
      case '\\': os << "\\\\"; break;
      case '\n': os << "\\n"; break;
      case '\t': os << "\\t"; break;
      case '\r': os << "\\r"; break;
      // also safe inside an HTML <script> element (the animation page's data)
      case '<': os << "\\u003c"; break;
      case '>': os << "\\u003e"; break;
      case '&': os << "\\u0026"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
          os << buf;
        } else {
          os << c;
        }
    }
  }
  os << '"';
}

void write_text_file(const std::string& path, const std::string& text, const std::string& what) {
  const std::string partial = path + ".partial";
  std::FILE* f = std::fopen(partial.c_str(), "w");
  if (!f) throw OptionError("cannot write " + what + " '" + partial + "': " + std::strerror(errno));
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (std::fclose(f) != 0 || !ok) {
    std::remove(partial.c_str());
    throw OptionError("writing " + what + " '" + partial + "' failed");
  }
  if (std::rename(partial.c_str(), path.c_str()) != 0)
    throw OptionError("cannot rename '" + partial + "' to '" + path + "': " + std::strerror(errno));
}

std::array<std::uint64_t, 5> event_counts(const std::vector<EventRecord>& events) {
  std::array<std::uint64_t, 5> counts{};
  for (const auto& e : events) ++counts[static_cast<std::size_t>(e.kind)];
  return counts;
}

void json_number(std::ostringstream& os, double v) {
  if (std::isfinite(v)) {
    os << format_number(v);
  } else {
    os << "null";
  }
}

}  // namespace detail

namespace {

using detail::format_shortest;

[[noreturn]] void option_failure(const std::string& field, const std::string& condition, double value) {
  throw InvalidOption(field, "must be " + condition + ", got " + format_shortest(value));
}

/// Finite and > 0.
void require_positive(const std::string& field, double value) {
  if (!std::isfinite(value)) option_failure(field, "finite", value);
  if (!(value > 0)) option_failure(field, "> 0", value);
}



/// |Δ| / |initial| from a drift relative to the energy scale; NaN when the
/// initial energy is 0.
double relative_to_initial(double drift_of_scale, double scale, double initial) {
  return initial != 0 ? drift_of_scale * scale / std::abs(initial) : std::numeric_limits<double>::quiet_NaN();
}

/// "energy function h: 3.2 J, drift |E - E0|/|E0| max 1.2e-13, final 1.1e-13 (of the energy scale 5 J: max 7e-14)":
/// the conserved energy's drift relative to its initial value, and to the scale where that is 0.
std::string energy_drift_line(const char* what, double initial, double drift_max, double drift_final,
                              double scale) {
  char buf[320];
  if (initial != 0) {
    std::snprintf(buf, sizeof buf,
                  "%s: %.12g J, drift |E - E0|/|E0| max %.2e, final %.2e (of the energy scale %.4g J: max %.2e)\n", what,
                  initial, relative_to_initial(drift_max, scale, initial),
                  relative_to_initial(drift_final, scale, initial), scale, drift_max);
  } else {
    std::snprintf(buf, sizeof buf, "%s: 0 J, drift of the energy scale %.4g J (E0 = 0): max %.2e, final %.2e\n", what,
                  scale, drift_max, drift_final);
  }
  return buf;
}

/// "energy function h: 0.5 J at t0, 0.42 J at t = 10 s: change -0.08 J (-16 % of |E0|); not conserved: why":
/// an energy that the system's own terms change, given as the change it is, not as drift.
std::string energy_change_line(const char* what, double initial, double final_value, double t_final,
                               const char* why) {
  char buf[512];
  const double change = final_value - initial;
  char share[64] = "";
  if (initial != 0) std::snprintf(share, sizeof share, " (%+.3g %% of |E0|)", 100 * change / std::abs(initial));
  std::snprintf(buf, sizeof buf, "%s: %.12g J at t0, %.12g J at t = %.6g s: change %+.6g J%s; not conserved: %s\n",
                what, initial, final_value, t_final, change, share, why);
  return buf;
}

/// "events: 12 (10 impacts, 1 rests, …); impacts dissipated 0.3 J", then
/// one line for each rest (with the Zeno rule's cut-off), stop and release.
std::string events_summary(const RunReport& r) {
  std::ostringstream os;
  char buf[256];
  if (!r.events.empty()) {
    const auto counts = detail::event_counts(r.events);
    // A truncated log (unlogged_events > 0) counts by kind only what it holds.
    const unsigned long long total = r.events.size() + r.unlogged_events;
    if (r.unlogged_events > 0) {
      std::snprintf(buf, sizeof buf, "events: %llu (the first %zu logged: ", total, r.events.size());
    } else {
      std::snprintf(buf, sizeof buf, "events: %llu (", total);
    }
    os << buf;
    // A watched event with action stop is logged twice, as the event and as the stop it made.
    std::snprintf(buf, sizeof buf,
                  "%llu impacts, %llu rests, %llu releases, %llu watched, %llu stops); impacts dissipated %.6g J\n",
                  static_cast<unsigned long long>(counts[0]), static_cast<unsigned long long>(counts[1]),
                  static_cast<unsigned long long>(counts[2]), static_cast<unsigned long long>(counts[3]),
                  static_cast<unsigned long long>(counts[4]), r.impact_energy_loss);
    os << buf;
    for (const auto& e : r.events) {
      if (e.kind == EventKind::rest && std::isfinite(e.zeno_cutoff) && e.zeno_cutoff > 0) {
        // Only the digits the cut-off leaves known, and the cut-off said.
        const double known = std::max(1.0, std::ceil(std::log10(std::max(std::abs(e.t), e.zeno_cutoff) / e.zeno_cutoff)));
        std::snprintf(buf, sizeof buf,
                      "event: rest %s at t = %.*g s (the Zeno rule ended the bounces there; those it cut off "
                      "would take about %.2g s more)\n",
                      e.name.c_str(), static_cast<int>(std::min(known, 15.0)), e.t, e.zeno_cutoff);
        os << buf;
      } else if (e.kind == EventKind::rest || e.kind == EventKind::stop || e.kind == EventKind::release) {
        std::snprintf(buf, sizeof buf, "event: %s %s at t = %.15g s\n", to_string(e.kind), e.name.c_str(), e.t);
        os << buf;
      }
    }
  }
  return os.str();
}

/// P and L of the point masses (what is conserved, or why not) and the
/// momenta of the cyclic coordinates.
std::string momenta_summary(const RunReport& r) {
  std::ostringstream os;
  char buf[256];
  if (r.has_particles) {
    // "linear momentum P0 = (…) kg*m/s, conserved along x y: drift max …",
    // then one line for each component left out, with the reason.
    auto momentum = [&](const char* name, const char* symbol, const char* unit, const char* along,
                        const std::array<double, 3>& v0, const std::array<bool, 3>& conserved,
                        const std::array<std::string, 3>& reason, double drift) {
      std::snprintf(buf, sizeof buf, "%s %s0 = (%.6g, %.6g, %.6g) %s", name, symbol, v0[0], v0[1], v0[2], unit);
      os << buf;
      std::string axes;
      for (std::size_t k = 0; k < 3; ++k)
        if (conserved[k]) axes += std::string(axes.empty() ? "" : " ") + "xyz"[k];
      if (axes.empty()) {
        os << ", not conserved\n";
      } else {
        std::snprintf(buf, sizeof buf, ", conserved %s %s: drift max %.2e\n", along, axes.c_str(), drift);
        os << buf;
      }
      for (std::size_t k = 0; k < 3; ++k)
        if (!conserved[k]) os << "  " << symbol << "_" << "xyz"[k] << " not conserved: " << reason[k] << "\n";
    };
    momentum("linear momentum", "P", "kg*m/s", "along", r.linear_momentum_initial, r.linear_momentum_conserved,
             r.linear_momentum_reason, r.linear_momentum_drift_max);
    momentum("angular momentum", "L", "kg*m^2/s", "about", r.angular_momentum_initial, r.angular_momentum_conserved,
             r.angular_momentum_reason, r.angular_momentum_drift_max);
  }
  for (const auto& m : r.conserved_momenta) {
    std::snprintf(buf, sizeof buf, "momentum of cyclic %s: %.12g, drift max %.2e\n", m.coordinate.c_str(), m.initial,
                  m.max_abs_drift);
    os << buf;
  }
  return os.str();
}

}  // namespace

double RunReport::energy_drift_relative_to_initial() const {
  return relative_to_initial(energy_drift_final, energy_scale, energy_initial);
}
double RunReport::energy_drift_relative_to_initial_max() const {
  return relative_to_initial(energy_drift_max, energy_scale, energy_initial);
}
double RunReport::total_energy_drift_relative_to_initial() const {
  return relative_to_initial(total_energy_drift_final, energy_scale, total_energy_initial);
}
double RunReport::total_energy_drift_relative_to_initial_max() const {
  return relative_to_initial(total_energy_drift_max, energy_scale, total_energy_initial);
}

void check_drift(RunReport& report, double rtol) {
  report.drift_bound = std::max(1e-2, 100 * rtol);
  report.drift_exceeded = false;
  report.monitors.clear();
  auto judge = [&](std::string name, double figure, const std::string& what, const char* relative_to) {
    MonitorVerdict v{std::move(name), figure, figure > report.drift_bound};
    if (v.exceeded) {
      report.drift_exceeded = true;
      char buf[640];
      std::snprintf(buf, sizeof buf,
                    "%s %.3g (%s) exceeds %.3g, more than a run at rtol = %.3g can excuse (the bound is max(1e-2, "
                    "100 rtol)): the trajectory is not to be trusted; tighten rtol, or dt for a fixed-step method",
                    what.c_str(), figure, relative_to, report.drift_bound, rtol);
      report.warnings.emplace_back(buf);
    }
    report.monitors.push_back(std::move(v));
  };
  const double energy = report.energy_scale > 0 ? report.energy_scale : 1.0;
  if (report.conservative) judge("energy", report.energy_drift_max, "energy drift", "of the energy scale");
  for (const MomentumDrift& m : report.conserved_momenta)
    judge("momentum p_" + m.coordinate, m.max_abs_drift * m.rate_max / energy,
          "drift of the conserved momentum p_" + m.coordinate, "times max |rate|, of the energy scale");
  auto any = [](const std::array<bool, 3>& a) { return a[0] || a[1] || a[2]; };
  if (report.has_particles && any(report.linear_momentum_conserved) && report.momentum_scale > 0)
    judge("linear momentum", report.linear_momentum_drift_max / report.momentum_scale,
          "drift of the total linear momentum", "of the sum of m |v|");
  if (report.has_particles && any(report.angular_momentum_conserved) && report.angular_momentum_scale > 0)
    judge("angular momentum", report.angular_momentum_drift_max / report.angular_momentum_scale,
          "drift of the total angular momentum", "of the sum of m |r| |v|");
  const double length = 1.0 + report.coordinate_scale;
  if (report.constrained && !report.constraints.names.empty())
    judge("constraint residual", report.constraints.max_position_residual / length, "constraint residual max |g|",
          "of 1 + max |q|");
  if (report.has_reference)
    judge("closed-form error", report.reference_error_max / length, "error against the closed form max |q - q_ref|",
          "of 1 + max |q|");
}

void SimulationOptions::validate() const {
  if (static_cast<std::size_t>(method) >= method_table().size())
    option_failure("method", "one of the Method enumerators", static_cast<double>(method));
  if (!std::isfinite(t0)) option_failure("t0", "finite", t0);
  if (!std::isfinite(t_end)) option_failure("t_end", "finite", t_end);
  if (!(t_end > t0))
    throw InvalidOption("t_end", "must be greater than t0 = " + format_shortest(t0) + ", got " + format_shortest(t_end));
  require_positive("dt", dt);
  require_positive("rtol", rtol);
  require_positive("atol", atol);
  if (rtol >= 1) option_failure("rtol", "< 1", rtol);
  if (rtol < min_rtol)
    option_failure("rtol", "at least 1e-15 (no double-precision step can meet a smaller relative tolerance)", rtol);
  if (max_steps == 0) throw InvalidOption("max_steps", "must be at least 1, got 0");
  if (!std::isfinite(output_interval)) option_failure("output_interval", "finite", output_interval);
  if (stabilization != Stabilization::none && stabilization != Stabilization::baumgarte &&
      stabilization != Stabilization::projection)
    throw InvalidOption("stabilization", "is " + std::to_string(static_cast<int>(stabilization)) +
                                             ", not one of: none, baumgarte, projection");
  require_positive("baumgarte_omega", baumgarte_omega);
  require_positive("projection_tolerance", projection_tolerance);
  if (discrete_rule != "midpoint" && discrete_rule != "trapezoidal")
    throw InvalidOption("discrete_rule", "is '" + discrete_rule + "'; choose one of: midpoint, trapezoidal");
  if (!std::isfinite(newton_tolerance) || !(newton_tolerance > 0) || !(newton_tolerance < 1))
    option_failure("newton_tolerance", "in (0, 1)", newton_tolerance);
  if (newton_max_iterations < 1)
    option_failure("newton_max_iterations", "at least 1", static_cast<double>(newton_max_iterations));
  if (!(zeno_speed_ratio >= 0 && zeno_speed_ratio < 1)) option_failure("zeno_speed_ratio", "in [0, 1)", zeno_speed_ratio);
  if (!std::isfinite(zeno_min_interval) || !(zeno_min_interval >= 0))
    option_failure("zeno_min_interval", "non-negative and finite", zeno_min_interval);
  if (!std::isfinite(contact_touch_speed) || !(contact_touch_speed >= 0))
    option_failure("contact_touch_speed", "non-negative and finite", contact_touch_speed);
}

void RunReport::write_json(const std::string& path) const {
  detail::write_text_file(path, to_json(), "report file");
}

void RunReport::write_events_csv(const std::string& path, const std::string& gap_unit) const {
  const std::string partial = path + ".partial";
  std::FILE* f = std::fopen(partial.c_str(), "w");
  if (!f) throw OptionError("cannot write events file '" + partial + "': " + std::strerror(errno));
  {
    using detail::csv_field;
    // Λ is along +∇φ: a generalized momentum per unit of φ, N*s for φ in m.
    const std::string impulse_unit = gap_unit.empty() ? "" : gap_unit == "m" ? "N*s" : "J*s/" + gap_unit;
    const std::string speed_unit = detail::csv_rate_unit(gap_unit);
    const std::string header = csv_field("t", "s") + ",kind,bodies," + csv_field("impulse", impulse_unit) + "," +
                               csv_field("approach_speed", speed_unit) + "," +
                               csv_field("separation_speed", speed_unit) + "," + csv_field("ke_before", "J") + "," +
                               csv_field("ke_after", "J") + "\n";
    std::fputs(header.c_str(), f);
  }
  for (const EventRecord& e : events) {
    std::string name = e.name;
    if (name.find_first_of(",\"\n") != std::string::npos) {
      std::string quoted = "\"";
      for (char c : name) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
      name = quoted + "\"";
    }
    std::fprintf(f, "%.17g,%s,%s,%.17g,%.17g,%.17g,%.17g,%.17g\n", e.t, to_string(e.kind), name.c_str(), e.impulse,
                 e.approach_speed, e.separation_speed, e.kinetic_energy_before, e.kinetic_energy_after);
  }
  if (unlogged_events > 0)  // said in the file itself (pandas: read_csv(..., comment="#"))
    std::fprintf(f, "# truncated: these are the first %zu of %llu events; raise output.max_events to log them all\n",
                 events.size(), static_cast<unsigned long long>(events.size() + unlogged_events));
  const bool ok = std::ferror(f) == 0;
  if (std::fclose(f) != 0 || !ok) {
    std::remove(partial.c_str());
    throw OptionError("writing events file '" + partial + "' failed");
  }
  if (std::rename(partial.c_str(), path.c_str()) != 0)
    throw OptionError("cannot rename '" + partial + "' to '" + path + "': " + std::strerror(errno));
}

std::string RunReport::summary() const {
  std::ostringstream os;
  char buf[256];
  os << "model " << model << " (" << coordinates.size() << " coordinates), method " << method;
  if (adaptive) {
    std::snprintf(buf, sizeof buf, ", rtol %.1e, atol %.1e", rtol, atol);
  } else {
    std::snprintf(buf, sizeof buf, ", dt %.3g s", dt);
  }
  os << buf << "\n";
  std::snprintf(buf, sizeof buf, "t = %.6g .. %.6g s: %llu steps (%llu rejected), %llu RHS evaluations, %.3f ms wall\n",
                t0, t_final, static_cast<unsigned long long>(steps), static_cast<unsigned long long>(rejected_steps),
                static_cast<unsigned long long>(rhs_evaluations), wall_time_s * 1e3);
  os << buf;
  if (newton_iterations > 0) {
    std::snprintf(buf, sizeof buf, "implicit steps: %llu Newton iterations (%.2f per step)\n",
                  static_cast<unsigned long long>(newton_iterations),
                  steps ? static_cast<double>(newton_iterations) / static_cast<double>(steps) : 0.0);
    os << buf;
  }
  if (conservative) {
    os << energy_drift_line("energy function h", energy_initial, energy_drift_max, energy_drift_final, energy_scale);
  } else {
    os << energy_change_line("energy function h", energy_initial, energy_final, t_final,
                             "forces, dissipation or explicit time dependence");
  }
  if (has_total_energy) {
    if (conservative && total_energy_is_h) {
      os << energy_drift_line("total energy T+V", total_energy_initial, total_energy_drift_max,
                              total_energy_drift_final, energy_scale);
    } else {
      os << energy_change_line("total energy T+V", total_energy_initial, total_energy_final, t_final,
                               conservative ? "T is not homogeneous quadratic in the velocities (a moving "
                                              "constraint or a drive), so h is the conserved energy and T + V changes"
                                            : "forces, dissipation or explicit time dependence");
    }
  }
  if (constrained) {
    const ConstraintReport& c = constraints;
    std::snprintf(buf, sizeof buf,
                  "constraints (%zu, %s): max residual position %.2e, velocity %.2e; %llu projections, %llu extra RHS, "
                  "%.3f ms\n",
                  c.names.size(), c.stabilization.c_str(), c.max_position_residual, c.max_velocity_residual,
                  static_cast<unsigned long long>(c.projections),
                  static_cast<unsigned long long>(c.extra_rhs_evaluations), c.stabilization_time_s * 1e3);
    os << buf;
    for (const auto& w : c.warnings) os << "warning: " << w << "\n";
  }
  os << events_summary(*this);
  for (const auto& w : warnings) os << "warning: " << w << "\n";
  if (!stopped_by.empty()) {
    std::snprintf(buf, sizeof buf, "stopped by event %s at t = %.15g s\n", stopped_by.c_str(), stopped_at);
    os << buf;
  }
  if (has_reference) {
    std::snprintf(buf, sizeof buf, "error against the closed form: max %.2e, final %.2e (units of q)\n",
                  reference_error_max, reference_error_final);
    os << buf;
  }
  os << momenta_summary(*this);
  return os.str();
}

}  // namespace lagrangian
