#pragma once
// Internal: how the tangent runs name numbers and contacts in their
// messages (tangent_system.hpp, resting_contacts.hpp, manifold.hpp).

#include <cstdio>
#include <string>

#include "lagrangian/analysis/lyapunov.hpp"

namespace lagrangian::detail {

/// x with 6 significant digits.
inline std::string short_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

/// Contact j's name (its number when the model names none).
inline std::string contact_name(const TangentModel& model, int j) {
  return j < static_cast<int>(model.contact_names.size()) ? model.contact_names[static_cast<std::size_t>(j)]
                                                           : std::to_string(j);
}

}  // namespace lagrangian::detail
