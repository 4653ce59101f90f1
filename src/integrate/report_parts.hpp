#pragma once
// What report.cpp and report_json.cpp share.
#include <array>
#include <cstdint>
#include <sstream>
#include <vector>

#include "lagrangian/integrate/report.hpp"

namespace lagrangian::detail {

/// Number of events of each kind, indexed by EventKind.
std::array<std::uint64_t, 5> event_counts(const std::vector<EventRecord>& events);

/// v in the shortest form that reads back the same, or null when not finite.
void json_number(std::ostringstream& os, double v);

}  // namespace lagrangian::detail
