#pragma once
// Internal: what the pieces of the sweep (src/scene/sweep*.cpp) share — text
// helpers, the plan of a point's document, the run of one point, the
// serialization between ranks, the table and its plots.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <variant>
#include <vector>

#include <toml++/toml.h>

#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/sweep.hpp"
#include "scene_edit.hpp"

namespace lagrangian::scene::detail {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// -- text helpers (sweep_spec.cpp) ----------------------------------------------

std::vector<std::string> split(const std::string& s, char sep);
std::string q(const std::string& s);

// -- changing the document (scene_edit.hpp) ------------------------------------

// parse_path and assign: scene_edit.hpp

/// Everything a worker needs to build the scene of a point.
struct Plan {
  std::string file;
  /// The scene file's text, parsed again for every point: a parsed document
  /// keeps the source lines that error messages cite, a copy of one does not.
  std::string text;
  std::vector<std::vector<PathPart>> vary_paths;  // empty for variables
  std::vector<std::vector<PathPart>> set_paths;
  std::vector<Expression> set_expressions;
  std::vector<std::string> variables;             // names of the variables, in --vary order
  std::vector<std::size_t> variable_slots;        // their index in SweepOptions::vary
};

Scene point_scene(const Plan& plan, const SweepOptions& o, toml::table& doc, std::vector<double>& values);

// -- running one point (sweep_point.cpp) ---------------------------------------

std::vector<std::string> trajectory_names(const Scene& scene);
SweepRecord run_point(const Plan& plan, const SweepOptions& o, std::uint64_t index);

// -- serialization between ranks (sweep_point.cpp) -----------------------------

std::string serialize(std::uint64_t index, const SweepRecord& r);
void deserialize(const std::string& text, std::vector<SweepRecord>& slots, std::vector<bool>& filled);

// -- the table (sweep_results.cpp) and its plots (sweep_results.cpp) --------------------

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

Table make_table(const SweepOptions& o, const std::vector<SweepRecord>& records);
/// The table as CSV, each column's unit in its header field ("t_final [s]").
std::string to_csv(const Table& t, const Scene& scene);
void plot(const SweepOptions& o, const Table& t, const Scene& scene, SweepResult& result);

}  // namespace lagrangian::scene::detail
