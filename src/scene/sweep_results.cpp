// The sweep's results: the table (header and one row of text cells per
// point, as written to sweep.csv) and its plots against the grid keys.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "key_units.hpp"
#include "lagrangian/detail/csv_header.hpp"
#include "sweep_detail.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/scene/plots.hpp"

namespace lagrangian::scene::detail {
namespace {

// -- the table ------------------------------------------------------------------------

std::string cell(double v) {
  if (std::isnan(v)) return "";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string csv_text(std::string s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

/// Event groups in a fixed order: impact, rest, release, stop (a watched
/// event that ended the run), then the watched events' names in
/// alphabetical order.
std::vector<std::string> event_groups(const std::vector<SweepRecord>& records) {
  std::vector<std::string> names;
  for (const SweepRecord& r : records)
    for (const auto& [name, g] : r.events)
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  auto rank = [](const std::string& n) {
    return n == "impact" ? 0 : n == "rest" ? 1 : n == "release" ? 2 : n == "stop" ? 3 : 4;
  };
  std::sort(names.begin(), names.end(), [&](const std::string& a, const std::string& b) {
    return rank(a) != rank(b) ? rank(a) < rank(b) : a < b;
  });
  return names;
}

}  // namespace

Table make_table(const SweepOptions& o, const std::vector<SweepRecord>& records) {
  Table t;
  t.header.emplace_back("point");
  for (const VarySpec& v : o.vary) t.header.push_back(v.key);
  for (const SetSpec& s : o.set) t.header.push_back(s.key);
  t.header.emplace_back("status");
  std::vector<std::string> coords;
  for (const SweepRecord& r : records)
    if (r.ok()) {
      coords = r.coordinates;
      break;
    }
  const std::vector<std::string> groups = event_groups(records);
  if (o.wants("final")) {
    t.header.emplace_back("t_final");
    for (const auto& c : coords) t.header.push_back("q_" + c);
    for (const auto& c : coords) t.header.push_back("qd_" + c);
  }
  if (o.wants("events"))
    for (const auto& g : groups)
      for (const char* p : {"n_", "first_", "last_"}) t.header.push_back(p + g);
  for (const FirstTimeSpec& f : o.first_times) t.header.push_back("t_" + f.name);
  if (o.wants("energy"))
    for (const char* c : {"energy_drift_max", "energy_drift_final", "energy_drift_relative_to_initial",
                          "impact_energy_loss"})
      t.header.emplace_back(c);
  if (o.wants("error")) t.header.emplace_back("reference_error_final");
  if (o.wants("cost"))
    for (const char* c : {"steps", "rejected_steps", "rhs_evaluations"}) t.header.emplace_back(c);
  if (o.wants("wall")) t.header.emplace_back("wall_time_s");
  if (o.wants("chaos"))
    for (const char* c : {"lyapunov_max", "megno"}) t.header.emplace_back(c);

  for (std::size_t i = 0; i < records.size(); ++i) {
    const SweepRecord& r = records[i];
    const bool ok = r.ok();
    std::vector<std::string> row;
    row.push_back(std::to_string(i));
    for (std::size_t k = 0; k < o.vary.size() + o.set.size(); ++k)
      row.push_back(k < r.values.size() ? cell(r.values[k]) : "");
    row.push_back(csv_text(r.status));
    auto num = [&](double v) { row.push_back(ok ? cell(v) : ""); };
    auto count = [&](std::uint64_t v) { row.push_back(ok ? std::to_string(v) : ""); };
    if (o.wants("final")) {
      num(r.t_final);
      for (std::size_t k = 0; k < coords.size(); ++k) num(k < r.q.size() ? r.q[k] : kNaN);
      for (std::size_t k = 0; k < coords.size(); ++k) num(k < r.qd.size() ? r.qd[k] : kNaN);
    }
    if (o.wants("events"))
      for (const auto& g : groups) {
        const auto it = r.events.find(g);
        count(it == r.events.end() ? 0 : it->second.count);
        num(it == r.events.end() ? kNaN : it->second.first);
        num(it == r.events.end() ? kNaN : it->second.last);
      }
    for (std::size_t k = 0; k < o.first_times.size(); ++k) num(k < r.first_times.size() ? r.first_times[k] : kNaN);
    if (o.wants("energy")) {
      num(r.energy_drift_max);
      num(r.energy_drift_final);
      num(r.energy_drift_relative_to_initial);
      num(r.impact_energy_loss);
    }
    if (o.wants("error")) num(r.has_reference ? r.reference_error_final : kNaN);
    if (o.wants("cost")) {
      count(r.steps);
      count(r.rejected_steps);
      count(r.rhs_evaluations);
    }
    if (o.wants("wall")) num(r.wall_time_s);
    if (o.wants("chaos")) {
      num(r.lyapunov_max);
      num(r.megno);
    }
    t.rows.push_back(std::move(row));
  }
  return t;
}

std::string to_csv(const Table& t, const Scene& scene) {
  std::string out;
  for (std::size_t k = 0; k < t.header.size(); ++k)
    out += (k ? "," : "") + lagrangian::detail::csv_field(t.header[k], column_unit(scene, t.header[k]));
  out += "\n";
  for (const auto& row : t.rows) {
    for (std::size_t k = 0; k < row.size(); ++k) out += (k ? "," : "") + row[k];
    out += "\n";
  }
  return out;
}

}  // namespace lagrangian::scene::detail

namespace lagrangian::scene::detail {
namespace {

/// The columns drawn by default: t_final, the final coordinates, the impact
/// energy loss, the first time of each event group and each --first-time,
/// the largest Lyapunov exponent and MEGNO.
std::vector<std::string> default_plot_columns(const Table& t) {
  std::vector<std::string> cols;
  for (std::size_t k = 0; k < t.header.size(); ++k) {
    const std::string& h = t.header[k];
    // Columns that are the same in every row say nothing as a curve.
    bool varies = false;
    for (const auto& row : t.rows) varies = varies || row[k] != t.rows.front()[k];
    if (!varies) continue;
    if (h == "t_final" || h.rfind("q_", 0) == 0 || h == "impact_energy_loss" || h.rfind("first_", 0) == 0 ||
        (h.rfind("t_", 0) == 0 && h != "t_final") || h == "lyapunov_max" || h == "megno")
      cols.push_back(h);
  }
  if (cols.size() > 12) cols.resize(12);
  return cols;
}

}  // namespace

void plot(const SweepOptions& o, const Table& t, const Scene& scene, SweepResult& result) {
  std::vector<std::size_t> axes;
  for (std::size_t k = 0; k < o.vary.size(); ++k)
    if (o.vary[k].count > 1) axes.push_back(k);
  if (o.monte_carlo > 0) {
    result.plot_note = "Monte Carlo sweeps are not plotted (the points are in sweep.csv)";
    return;
  }
  if (axes.empty() || axes.size() > 2) {
    result.plot_note = "plots are drawn for sweeps along one or two keys; this one varies " +
                       std::to_string(axes.size());
    return;
  }
  std::vector<std::string> columns = o.plot_columns.empty() ? default_plot_columns(t) : o.plot_columns;
  if (columns.empty()) {
    result.plot_note =
        "nothing plotted: no default column (t_final, q_*, impact_energy_loss, first_*, t_*, lyapunov_max, megno) "
        "varies across the points; name columns with --plot";
    return;
  }
  SweepPlotSpec spec;
  spec.title = scene.name;
  spec.out_dir = o.out_dir;
  spec.png = o.png;
  spec.svg = o.svg;
  for (std::size_t a : axes) {
    spec.axes.push_back(o.vary[a].key);
    spec.axis_units.push_back(key_unit(scene, o.vary[a].key));
    spec.axis_counts.push_back(o.vary[a].count);
    spec.log_axes.push_back(o.vary[a].kind == VarySpec::Kind::log);
  }
  auto index_of = [&](const std::string& name) {
    const auto it = std::find(t.header.begin(), t.header.end(), name);
    if (it == t.header.end()) {
      const std::string near = nearest(name, t.header);
      throw OptionError("--plot: no column " + q(name) +
                        (near.empty() ? " in sweep.csv" : "; did you mean '" + near + "'?"));
    }
    return static_cast<std::size_t>(it - t.header.begin());
  };
  std::vector<std::size_t> x_cols;
  for (std::size_t a : axes) x_cols.push_back(1 + a);
  for (const std::string& c : columns) {
    const std::size_t ci = index_of(c);
    SweepPlotSpec::Series s;
    s.name = c;
    s.unit = column_unit(scene, c);
    for (const auto& row : t.rows) {
      std::vector<double> x;
      for (std::size_t xc : x_cols) x.push_back(row[xc].empty() ? kNaN : std::strtod(row[xc].c_str(), nullptr));
      s.x.push_back(std::move(x));
      s.y.push_back(row[ci].empty() ? kNaN : std::strtod(row[ci].c_str(), nullptr));
    }
    spec.series.push_back(std::move(s));
  }
  // Axis values come from the grid (a failed run has no values in its row).
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const std::vector<double> values = point_values(o, i);
    for (auto& s : spec.series)
      for (std::size_t a = 0; a < axes.size(); ++a) s.x[i][a] = values[axes[a]];
  }
  collect_plots([&] { return make_sweep_plots(spec); }, result.files, result.plot_note);
}

}  // namespace lagrangian::scene::detail
