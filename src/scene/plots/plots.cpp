// The public entry points of plots.hpp: make_plots(), the work-precision and
// sweep plots, collect_plots() and gnuplot_available(), with their file helpers.
#include "lagrangian/scene/plots.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <iterator>
#include <sstream>
#include <string>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include "csv_inputs.hpp"
#include "gnuplot_process.hpp"
#include "gnuplot_text.hpp"
#include "lagrangian/errors.hpp"
#include "script_writer.hpp"

namespace lagrangian {

namespace plots_detail {
namespace {

constexpr const char* kPlotNames[] = {"trajectory", "coordinates", "energy", "phase"};

// The path of `file` as the script (run in `dir`) should name it: relative
// when it lies under dir or under its parent (a run directory holding its
// plot directory), so that the run can be moved; absolute otherwise.
std::string script_path(const std::string& file, const fs::path& dir) {
  const fs::path abs = fs::absolute(file).lexically_normal();
  const fs::path rel = abs.lexically_relative(dir);
  int up = 0;
  for (const fs::path& part : rel) up += part == "..";
  if (!rel.empty() && up <= 1) return rel.generic_string();
  return abs.string();
}

void write_file(const fs::path& path, const std::string& text) {
  const std::string partial = path.string() + ".partial";
  std::FILE* f = std::fopen(partial.c_str(), "w");
  if (!f) throw OptionError("cannot write plot script '" + partial + "': " + std::strerror(errno));
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (std::fclose(f) != 0 || !ok) {
    std::remove(partial.c_str());
    throw OptionError("writing plot script '" + partial + "' failed");
  }
  if (std::rename(partial.c_str(), path.c_str()) != 0)
    throw OptionError("cannot rename '" + partial + "' to '" + path.string() + "': " + std::strerror(errno));
}

/// Creates `out_dir` and returns it absolute.
fs::path plot_directory(const std::string& out_dir) {
  if (out_dir.empty()) throw OptionError("plots: out_dir is empty");
  if (out_dir.find_first_of("\n\r") != std::string::npos)
    throw OptionError("plots: a path contains a line break: '" + out_dir + "'");
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec || !fs::is_directory(out_dir))
    throw OptionError("cannot create plot directory '" + out_dir + "'" + (ec ? ": " + ec.message() : ""));
  return fs::absolute(out_dir).lexically_normal();
}

}  // namespace
}  // namespace plots_detail

using namespace plots_detail;  // the helpers above and those of the internal headers

bool gnuplot_available() { return !working_gnuplot().empty(); }

PlotResult make_plots(const PlotSpec& spec) {
  PlotResult result;
  const std::string exe = gnuplot_for(spec.png, spec.svg, result);
  if (exe.empty()) return result;

  // Check the spec.
  if (!(spec.energy_scale > 0) || !std::isfinite(spec.energy_scale))
    throw OptionError("plots: energy_scale must be a positive number of J, not " + num(spec.energy_scale));
  for (const std::string* p : {&spec.trajectory_csv, &spec.events_csv, &spec.out_dir})
    if (p->find_first_of("\n\r") != std::string::npos)
      throw OptionError("plots: a path contains a line break: '" + *p + "'");
  if (spec.out_dir.empty()) throw OptionError("plots: out_dir is empty");

  // Inputs.
  const std::vector<Impact> impacts = read_impacts(spec.events_csv);
  const std::vector<Impact> times = thinned(impacts);
  std::vector<Impact> positions;  // those the trajectory plot marks: of the bodies it draws
  if (spec.bodies.size() > kMaxBodiesUnlabelled) {
    for (const Impact& imp : impacts)
      for (std::size_t b = 0; b < kLegendBodies; ++b)
        if (names_body(imp.bodies, spec.bodies[b].name)) {
          positions.push_back(imp);
          break;
        }
    positions = thinned(positions);
  } else {
    positions = times;
  }
  // The coordinates the trajectory plot may need at the impacts.
  std::vector<std::string> at_impacts;
  if (!spec.coordinates.empty()) {
    const auto add = [&](int idx) {
      if (idx >= 0 && idx < static_cast<int>(spec.coordinates.size()))
        at_impacts.push_back(spec.coordinates[static_cast<std::size_t>(idx)]);
    };
    if (spec.bodies.empty()) {
      add(0);
      add(1);
    }
    const std::size_t drawn =
        spec.bodies.size() > kMaxBodiesUnlabelled ? kLegendBodies : spec.bodies.size();
    for (std::size_t b = 0; b < drawn; ++b) {
      add(spec.bodies[b].x);
      add(spec.bodies[b].y);
      add(spec.bodies[b].z);
    }
  }
  // Watched events (an apex, a landing) are marked by name where the one body
  // drawn, or the configuration, is at their time: their rows are read with
  // the impacts' and split off again.
  std::vector<Impact> marks;
  if (spec.bodies.size() <= 1) {
    marks = thinned(read_impacts(spec.events_csv, true));
    positions.insert(positions.end(), marks.begin(), marks.end());
    std::stable_sort(positions.begin(), positions.end(), [](const Impact& a, const Impact& b) { return a.t < b.t; });
  }
  Trajectory tr = read_trajectory(spec.trajectory_csv, positions, at_impacts);
  if (!marks.empty()) {
    marks.clear();
    std::vector<Impact> impacts_only;
    for (Impact& p : positions) (p.watched ? marks : impacts_only).push_back(std::move(p));
    positions = std::move(impacts_only);
  }

  std::unordered_map<std::string, std::size_t> index;
  for (std::size_t k = 0; k < tr.header.size(); ++k) index.emplace(tr.header[k], k);
  auto column = [&](const std::string& name) {
    const auto it = index.find(name);
    if (it == index.end())
      throw OptionError("trajectory file '" + spec.trajectory_csv + "' has no column '" + name + "'");
    return it->second;
  };
  std::vector<std::string> coords = spec.coordinates;
  if (coords.empty()) {  // the names between t and the first rate
    const auto rate = index.find(tr.header.size() > 1 ? tr.header[1] + "_dot" : std::string());
    if (rate == index.end())
      throw OptionError("trajectory file '" + spec.trajectory_csv + "': cannot tell the coordinates from the header");
    coords.assign(tr.header.begin() + 1, tr.header.begin() + static_cast<std::ptrdiff_t>(rate->second));
  }
  std::vector<std::string> units = spec.units;
  if (units.empty()) units.assign(coords.size(), "");
  if (units.size() != coords.size())
    throw OptionError("plots: " + std::to_string(units.size()) + " units for " + std::to_string(coords.size()) +
                      " coordinates");
  Columns cols;
  for (const std::string& name : coords) {
    cols.q.push_back(column(name));
    cols.qd.push_back(column(name + "_dot"));
  }
  cols.energy = column("energy");
  if (const auto it = index.find("total_energy"); it != index.end()) cols.total_energy = it->second;
  for (const auto& b : spec.bodies)
    for (int idx : {b.x, b.y, b.z})
      if (idx >= static_cast<int>(coords.size()))
        throw OptionError("plots: body '" + b.name + "' names coordinate " + std::to_string(idx) + " of only " +
                          std::to_string(coords.size()));

  // Output directory and script.
  const fs::path dir = plot_directory(spec.out_dir);
  ScriptWriter writer(spec, tr, cols, impacts, times, positions, marks, coords, units,
                      script_path(spec.trajectory_csv, dir));
  const fs::path script = dir / "plots.gp";
  write_file(script, writer.write());

  std::vector<std::string> names(std::begin(kPlotNames), std::end(kPlotNames));
  run_script(exe, dir, script, names, spec.png, spec.svg, result);
  return result;
}

PlotResult make_work_precision_plots(const WorkPrecisionPlotSpec& spec) {
  PlotResult result;
  const std::string exe = gnuplot_for(spec.png, spec.svg, result);
  if (exe.empty()) return result;
  const fs::path dir = plot_directory(spec.out_dir);

  // One data block per series: wall time, RHS evaluations, error, energy
  // drift; rows whose value is not positive and finite hold NaN there, which
  // gnuplot leaves out (log axes).
  auto positive = [](double v) { return std::isfinite(v) && v > 0 ? num(v) : std::string("NaN"); };
  std::ostringstream os;
  os << "# Work-precision diagrams, written by lagrangian::make_work_precision_plots.\n"
     << "# Run with: gnuplot bench.gp   (images <name>.png / .svg; `suffix` goes between\n"
     << "# the image name and the extension; lagrangian uses '.partial' and renames).\n"
     << "if (!exists('suffix')) suffix = ''\n\n";
  write_styles(os, 800, 560);
  bool any_energy = false;
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const WorkPrecisionSeries& sr = spec.series[k];
    const std::size_t n = sr.error.size();
    if (sr.wall_time_s.size() != n || sr.rhs_evaluations.size() != n || sr.energy_drift.size() != n)
      throw OptionError("plots: series '" + sr.name + "' has columns of different lengths");
    os << "# " << sr.name << ": wall time (s), RHS evaluations, error, relative energy drift\n"
       << "$s" << k << " << EOD\n";
    for (std::size_t i = 0; i < n; ++i) {
      os << positive(sr.wall_time_s[i]) << " " << positive(sr.rhs_evaluations[i]) << " " << positive(sr.error[i])
         << " " << positive(sr.energy_drift[i]) << "\n";
      any_energy = any_energy || (std::isfinite(sr.energy_drift[i]) && sr.energy_drift[i] > 0);
    }
    os << "EOD\n";
  }
  std::string formats;
  if (spec.png) formats = "png";
  if (spec.svg) formats += formats.empty() ? "svg" : " svg";
  os << "\nformats = '" << formats << "'\n";

  struct Diagram {
    const char* name;
    const char* what;
    const char* xlabel;
    const char* ylabel;  // empty: spec.error_label
    int x, y;            // columns of the data blocks
  };
  std::vector<Diagram> diagrams{{"work_precision_time", "error against wall time", "wall time (s)", "", 1, 3},
                                {"work_precision_rhs", "error against right-hand-side evaluations",
                                 "right-hand-side evaluations", "", 2, 3}};
  if (any_energy)
    diagrams.push_back({"work_precision_energy", "relative energy drift against wall time", "wall time (s)",
                        "max |E(t) - E(t0)| / E scale", 1, 4});
  std::vector<std::string> names;
  for (const Diagram& d : diagrams) {
    names.emplace_back(d.name);
    os << "\n# " << d.what << "\n"
       << "do for [fmt in formats] {\n"
       << "  reset\n"
       << "  eval setup\n"
       << "  if (fmt eq 'png') { eval png_terminal } else { eval svg_terminal }\n"
       << "  set output '" << d.name << "'.suffix.'.'.fmt\n"
       << "  set logscale xy\n"
       << "  set format x '%.0e'; set format y '%.0e'\n"
       << "  set title " << gp_str(spec.title + ": " + d.what) << "\n"
       << "  set xlabel " << gp_str(d.xlabel) << "\n"
       << "  set ylabel " << gp_str(*d.ylabel ? std::string(d.ylabel) : spec.error_label) << "\n"
       << "  set key outside right top\n"
       << "  set bmargin 6\n";
    if (!spec.note.empty()) os << "  set label 1 " << gp_str(spec.note) << " at screen 0.01, 0.025 font ',9'\n";
    os << "  plot ";
    bool first = true;
    for (std::size_t k = 0; k < spec.series.size(); ++k) {
      os << (first ? "" : ", \\\n       ") << "$s" << k << " using " << d.x << ":" << d.y << " with linespoints lt "
         << k % 10 + 1 << " title " << gp_str(spec.series[k].name);
      first = false;
    }
    if (d.y == 3 && spec.reference_accuracy > 0)
      os << (first ? "" : ", \\\n       ") << num(spec.reference_accuracy)
         << " with lines dt 2 lc rgb '#707070' title 'reference accuracy'";
    os << "\n  set output\n}\n";
  }
  const fs::path script = dir / "bench.gp";
  write_file(script, os.str());
  run_script(exe, dir, script, names, spec.png, spec.svg, result);
  return result;
}

PlotResult make_speed_plot(const SpeedPlotSpec& spec) {
  if (spec.speeds.size() < 2) throw OptionError("plots: a speed histogram needs at least 2 speeds");
  for (const double v : spec.speeds)
    if (!std::isfinite(v) || v < 0) throw OptionError("plots: speed " + num(v) + " is not finite and >= 0");
  if (!(spec.mass > 0) || !std::isfinite(spec.mass) || !(spec.kT > 0) || !std::isfinite(spec.kT))
    throw OptionError("plots: the speed plot needs mass > 0 and kT > 0, got " + num(spec.mass) + " kg and " +
                      num(spec.kT) + " J");
  PlotResult result;
  const std::string exe = gnuplot_for(spec.png, spec.svg, result);
  if (exe.empty()) return result;
  const fs::path dir = plot_directory(spec.out_dir);
  const std::size_t n = spec.speeds.size();
  const std::size_t bins = std::clamp<std::size_t>(static_cast<std::size_t>(std::sqrt(static_cast<double>(n))), 10, 60);
  const double vmax = *std::max_element(spec.speeds.begin(), spec.speeds.end());
  const double width = (vmax > 0 ? vmax : 1.0) / static_cast<double>(bins);
  std::vector<std::size_t> count(bins, 0);
  for (const double v : spec.speeds) ++count[std::min(bins - 1, static_cast<std::size_t>(v / width))];
  std::ostringstream os;
  os << "# Speeds against Maxwell-Boltzmann, written by lagrangian::make_speed_plot.\n"
     << "# Run with: gnuplot speeds.gp   (images speeds.png / .svg; `suffix` goes between\n"
     << "# the image name and the extension; lagrangian uses '.partial' and renames).\n"
     << "if (!exists('suffix')) suffix = ''\n\n";
  write_styles(os, 800, 560);
  os << "# bin centre (m/s), probability density (s/m), count\n$speeds << EOD\n";
  for (std::size_t b = 0; b < bins; ++b)
    os << num((static_cast<double>(b) + 0.5) * width) << " "
       << num(static_cast<double>(count[b]) / (static_cast<double>(n) * width)) << " " << count[b] << "\n";
  os << "EOD\n"
     << "m = " << num(spec.mass) << "   # kg\n"
     << "kT = " << num(spec.kT) << "   # J\n"
     << "maxwell(v) = 4*pi*v**2*(m/(2*pi*kT))**1.5*exp(-m*v**2/(2*kT))\n";
  std::string formats;
  if (spec.png) formats = "png";
  if (spec.svg) formats += formats.empty() ? "svg" : " svg";
  os << "formats = '" << formats << "'\n"
     << "do for [fmt in formats] {\n"
     << "  reset\n"
     << "  eval setup\n"
     << "  if (fmt eq 'png') { eval png_terminal } else { eval svg_terminal }\n"
     << "  set output 'speeds'.suffix.'.'.fmt\n"
     << "  set title " << gp_str(titled(spec.title, std::to_string(n) + " speeds against Maxwell–Boltzmann at kT = " +
                                                       short_num(spec.kT) + " J")) << "\n"
     << "  set xlabel 'speed |v| (m/s)'\n"
     << "  set ylabel 'probability density (s/m)'\n"
     << "  set xrange [0:" << num(bins * width) << "]\n"
     << "  set yrange [0:*]\n"
     << "  set key outside right top\n"
     << "  set style fill solid 0.35 border\n"
     << "  set bmargin 6\n";
  if (!spec.note.empty()) os << "  set label 1 " << gp_str(spec.note) << " at screen 0.01, 0.025 font ',9'\n";
  os << "  set samples 400\n"
     << "  plot $speeds using 1:2:(" << num(width) << ") with boxes lt 2 title 'the run', \\\n"
     << "       maxwell(x) with lines lt 1 lw 2 title 'Maxwell–Boltzmann'\n"
     << "  set output\n}\n";
  const fs::path script = dir / "speeds.gp";
  write_file(script, os.str());
  run_script(exe, dir, script, {"speeds"}, spec.png, spec.svg, result);
  return result;
}

void collect_plots(const std::function<PlotResult()>& make, std::vector<std::string>& files, std::string& note) {
  try {
    const PlotResult pr = make();
    files.insert(files.end(), pr.files.begin(), pr.files.end());
    if (!pr.gnuplot_found) note = pr.message;
  } catch (const Error& e) {
    note = std::string("plots failed: ") + e.what();
  }
}

PlotResult make_sweep_plots(const SweepPlotSpec& spec) {
  PlotResult result;
  const std::size_t dims = spec.axes.size();
  if (dims < 1 || dims > 2 || spec.axis_counts.size() != dims)
    throw OptionError("plots: a sweep plot needs one or two axes, got " + std::to_string(dims));
  const std::string exe = gnuplot_for(spec.png, spec.svg, result);
  if (exe.empty()) return result;
  const fs::path dir = plot_directory(spec.out_dir);
  auto value = [](double v) { return std::isfinite(v) ? num(v) : std::string("NaN"); };
  auto axis_label = [&](std::size_t a) {
    return with_unit(spec.axes[a], a < spec.axis_units.size() ? spec.axis_units[a] : std::string());
  };
  auto file_name = [](const std::string& name) {
    std::string out = "sweep_";
    for (char c : name) out += std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' ? c : '_';
    return out;
  };
  std::ostringstream os;
  os << "# Sweep plots, written by lagrangian::make_sweep_plots.\n"
     << "# Run with: gnuplot sweep.gp   (images sweep_<column>.png / .svg; `suffix` goes between\n"
     << "# the image name and the extension; lagrangian uses '.partial' and renames).\n"
     << "if (!exists('suffix')) suffix = ''\n\n";
  write_styles(os, 800, 560);
  std::string formats;
  if (spec.png) formats = "png";
  if (spec.svg) formats += formats.empty() ? "svg" : " svg";
  os << "\nformats = '" << formats << "'\n";
  std::vector<std::string> names;
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const SweepPlotSpec::Series& s = spec.series[k];
    if (s.x.size() != s.y.size()) throw OptionError("plots: series '" + s.name + "' has columns of different lengths");
    os << "\n$d" << k << " << EOD\n";
    for (std::size_t i = 0; i < s.y.size(); ++i) {
      if (s.x[i].size() != dims) throw OptionError("plots: series '" + s.name + "' has a point with the wrong axes");
      if (dims == 2 && i > 0 && spec.axis_counts[1] > 0 && i % static_cast<std::size_t>(spec.axis_counts[1]) == 0)
        os << "\n";  // a new row of the grid
      for (double x : s.x[i]) os << value(x) << " ";
      os << value(s.y[i]) << "\n";
    }
    os << "EOD\n";
    const std::string name = file_name(s.name);
    names.push_back(name);
    os << "do for [fmt in formats] {\n"
       << "  reset\n"
       << "  eval setup\n"
       << "  if (fmt eq 'png') { eval png_terminal } else { eval svg_terminal }\n"
       << "  set output '" << name << "'.suffix.'.'.fmt\n"
       << "  set title " << gp_str(spec.title + ": " + s.name) << "\n"
       << "  set xlabel " << gp_str(axis_label(0)) << "\n";
    if (spec.log_axes.size() > 0 && spec.log_axes[0]) os << "  set logscale x\n";
    if (dims == 1) {
      os << "  set ylabel " << gp_str(with_unit(s.name, s.unit)) << "\n"
         << "  plot $d" << k << " using 1:2 with linespoints lt 1 notitle\n";
    } else {
      if (spec.log_axes.size() > 1 && spec.log_axes[1]) os << "  set logscale y\n";
      os << "  set ylabel " << gp_str(axis_label(1)) << "\n"
         << "  set cblabel " << gp_str(with_unit(s.name, s.unit)) << "\n"
         << "  set palette rgbformulae 33,13,10\n"
         << "  set autoscale fix\n"
         << "  plot $d" << k << " using 1:2:3 with image notitle\n";
    }
    os << "  set output\n}\n";
  }
  const fs::path script = dir / "sweep.gp";
  write_file(script, os.str());
  run_script(exe, dir, script, names, spec.png, spec.svg, result);
  return result;
}

}  // namespace lagrangian
