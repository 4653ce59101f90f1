#pragma once
// Internal: what the plots read of a run's CSV files: the impacts of the
// events file, and the rows, ranges and values at the impacts of the trajectory.

#include <cstddef>
#include <string>
#include <vector>

#include "lagrangian/scene/detail/contact_names.hpp"

namespace lagrangian::plots_detail {

constexpr std::size_t kPointsPerLine = 5000;  // rows are thinned to about this many per line
constexpr std::size_t kMaxImpactMarks = 2000;  // more impacts are thinned evenly

struct Impact {
  double t = 0;
  std::string bodies;  // impacts: the bodies or contact ("ball-floor"); watched events: the event's name
  bool watched = false;  // a watched event (kind "event"), marked by name on the trajectory
  double ke_before = 0, ke_after = 0;  // kinetic energy just before and after (J), 0 when not given
  std::vector<double> row;  // the columns Trajectory::slot names, at time t (interpolated)
};

struct Trajectory {
  std::vector<std::string> header;  // the columns' names, without their units
  std::size_t rows = 0;
  std::size_t every = 1;            // rows are drawn every `every` (about kPointsPerLine per line)
  std::vector<double> first, last;  // first and last rows
  std::vector<double> lo, hi;       // finite minimum and maximum of every column
  std::vector<std::size_t> slot;    // per column: its index in Impact::row, or npos
  bool kept(std::size_t col) const { return slot.at(col) != std::string::npos; }
  // Column `col` of the trajectory at an impact.
  double at(const Impact& imp, std::size_t col) const { return imp.row.at(slot.at(col)); }
};

// All impacts of the events file, in time order (none if it does not exist);
// with `watched`, its watched events (kind "event": an apex, a landing) instead.
std::vector<Impact> read_impacts(const std::string& path, bool watched = false);

// At most kMaxImpactMarks of `impacts`, evenly chosen (the first and the last kept).
std::vector<Impact> thinned(const std::vector<Impact>& impacts);

// Reads the trajectory: header, row count, and — over the rows gnuplot will
// draw (every `every`-th, and the last) — the column ranges; the first and
// last rows; at the impact times (from the rows around each), t and the
// columns named in at_impacts (all columns when it is empty). Other rows are only checked for their field count and
// time, so that files of millions of rows read quickly.
Trajectory read_trajectory(const std::string& path, std::vector<Impact>& impacts,
                           const std::vector<std::string>& at_impacts);

// Does an event's `bodies` field ("ball-floor", "s1-s2") name this body?
using lagrangian::detail::names_body;

}  // namespace lagrangian::plots_detail
