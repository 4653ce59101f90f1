// ScriptWriter's members: the data blocks read once from the trajectory, then
// the coordinates, energy and phase plots of make_plots() (the trajectory
// plots are in script_trajectory.cpp).
#include "script_writer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "gnuplot_text.hpp"
#include "lagrangian/view/detail/energy_chart.hpp"

namespace lagrangian::plots_detail {

ScriptWriter::ScriptWriter(const PlotSpec& spec, const Trajectory& tr, const Columns& cols,
                           const std::vector<Impact>& impacts, const std::vector<Impact>& times,
                           const std::vector<Impact>& positions, const std::vector<Impact>& marks,
                           std::vector<std::string> coords, std::vector<std::string> units, std::string data_path)
    : spec_(spec),
      tr_(tr),
      cols_(cols),
      impacts_(times),
      positions_(positions),
      marks_(marks),
      impacts_total_(impacts.size()),
      coords_(std::move(coords)),
      units_(std::move(units)),
      data_path_(std::move(data_path)) {
  every_ = tr_.every;
  for (const Impact& imp : impacts)
    if (imp.ke_before - imp.ke_after > 1e-9 * std::abs(imp.ke_before)) impacts_lose_energy_ = true;
}

std::string ScriptWriter::write() {
  trajectory();
  coordinates();
  energy();
  phase();
  std::ostringstream head;
  preamble(head);
  write_blocks(head);
  return head.str() + os_.str();
}

ScriptWriter::Quantity ScriptWriter::column_q(std::size_t col) const {
  return {"column(" + std::to_string(col + 1) + ")", tr_.header[col]};
}

std::string ScriptWriter::source(const std::vector<Quantity>& qs, bool with_t) {
  auto find_in = [&](std::size_t b, const Quantity& q) -> int {
    for (std::size_t k = 0; k < blocks_[b].size(); ++k)
      if (blocks_[b][k].expr == q.expr) return static_cast<int>(k) + 2;  // column 1 is t
    return 0;
  };
  std::size_t block = blocks_.size();
  for (std::size_t b = 0; b < blocks_.size() && block == blocks_.size(); ++b) {
    bool all = true;
    for (const Quantity& q : qs) all = all && find_in(b, q);
    if (all) block = b;
  }
  if (block == blocks_.size()) {  // add the missing ones to the last block, or open a new one
    if (!blocks_.empty()) {
      std::size_t missing = 0;
      for (const Quantity& q : qs) missing += find_in(blocks_.size() - 1, q) ? 0 : 1;
      if (blocks_.back().size() + missing <= kBlockColumns - 1) block = blocks_.size() - 1;
    }
    if (block == blocks_.size()) blocks_.emplace_back();
    for (const Quantity& q : qs)
      if (!find_in(block, q)) blocks_[block].push_back(q);
  }
  std::string out = "$rows" + std::to_string(block + 1) + " using " + (with_t ? "1" : "");
  for (std::size_t k = 0; k < qs.size(); ++k)
    out += (with_t || k ? ":" : "") + std::to_string(find_in(block, qs[k]));
  return out;
}

void ScriptWriter::write_blocks(std::ostringstream& os) const {
  os << "# The data the plots use: every n-th row of the trajectory, only the columns\n"
     << "# needed, read once per block below into memory (column 1 of each block is t).\n"
     << "# Values are written with 12 significant digits.\n"
     << "g(x) = sprintf('%.12g', x)\n"
     << "set datafile separator comma\n";
  for (std::size_t b = 0; b < blocks_.size(); ++b) {
    os << "set table $rows" << b + 1 << "    # t";
    for (const Quantity& q : blocks_[b]) os << ", " << q.label;
    os << "\nplot data every n::1 using (g(column(1)))";  // point 0 of the file is its header
    for (const Quantity& q : blocks_[b]) os << ":(g(" << q.expr << "))";
    os << " with table\nunset table\n";
  }
  os << "set datafile separator whitespace\n\n";
}

double ScriptWriter::t0() const { return tr_.first[0]; }

double ScriptWriter::t1() const { return tr_.last[0]; }

std::pair<double, double> ScriptWriter::time_range() const {
  return t1() > t0() ? std::pair{t0(), t1()} : padded(t0(), t1());
}

std::pair<double, double> ScriptWriter::col_range(const std::vector<std::size_t>& cols) const {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t k : cols) {
    lo = std::min(lo, tr_.lo[k]);
    hi = std::max(hi, tr_.hi[k]);
  }
  return padded(lo, hi);
}

double ScriptWriter::spread(std::size_t col) const {
  return tr_.hi[col] >= tr_.lo[col] ? tr_.hi[col] - tr_.lo[col] : 0.0;
}

bool ScriptWriter::varies(std::size_t i, bool rate) const {
  const auto& cols = rate ? cols_.qd : cols_.q;
  double largest = 0;
  for (std::size_t j = 0; j < coords_.size(); ++j)
    if (units_[j] == units_[i]) largest = std::max(largest, spread(cols[j]));
  return spread(cols[i]) > 1e-9 * largest;
}

void ScriptWriter::preamble(std::ostringstream& os) const {
  os << "# Plots of the run" << (spec_.title.empty() ? "" : " " + gp_str(spec_.title))
      << ", written by lagrangian::make_plots.\n"
      << "# Draw them again with:   cd <this directory> && gnuplot plots.gp\n"
      << "# Set before the script with -e: formats (default below), suffix (added to each\n"
      << "# image name before the extension; make_plots uses '.partial' and renames).\n"
      << "if (!exists(\"formats\")) formats = " << gp_str(formats()) << "\n"
      << "if (!exists(\"suffix\")) suffix = ''\n\n"
      << "data = " << gp_str(data_path_) << "\n"
      << "n = " << every_ << "    # plot every n-th row: " << tr_.rows << " rows, about " << kPointsPerLine
      << " points per line\n"
      << "E0 = " << num(tr_.first[cols_.energy]) << "    # energy at t0 (J)\n";
  if (cols_.total_energy)
    os << "Etot0 = " << num(tr_.first[cols_.total_energy]) << "    # T + V at t0 (J)\n";
  os << "Escale = " << num(spec_.energy_scale) << "    # energy scale (J)\n\n";

  write_styles(os, 1000, 700);

  // Impact times and, per plot, the impact points: inline data blocks.
  if (!impacts_.empty()) {
    os << "# Impacts (events of kind 'impact')";
    if (impacts_total_ > impacts_.size())
      os << ": " << impacts_.size() << " of " << impacts_total_ << ", evenly chosen";
    os << ".\n$impacts << EOD\n# t (s)\n";
    for (const Impact& imp : impacts_) os << num(imp.t) << "\n";
    os << "EOD\n\n";
  }
}

std::string ScriptWriter::formats() const {
  std::string f;
  if (spec_.png) f = "png";
  if (spec_.svg) f += f.empty() ? "svg" : " svg";
  return f;
}

void ScriptWriter::begin_plot(const char* name) {
  os_ << "do for [fmt in formats] {\n"
      << "  reset\n"
      << "  eval setup\n"
      << "  if (fmt eq 'png') { eval png_terminal } else { eval svg_terminal }\n"
      << "  set output '" << name << "'.suffix.'.'.fmt\n";
}

void ScriptWriter::end_plot() { os_ << "  set output\n}\n\n"; }

std::string ScriptWriter::line_style(std::size_t i, std::size_t k, bool dashes) const {
  const auto& bodies = spec_.bodies;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const int idx[3] = {bodies[b].x, bodies[b].y, bodies[b].z};
    for (int a = 0; a < 3; ++a)
      if (idx[a] == static_cast<int>(i))
        return "lt " + std::to_string(b % 10 + 1) + (dashes ? std::string(kAxisDash[a]) : std::string());
  }
  return "lt " + std::to_string(k % 10 + 1);
}

std::string ScriptWriter::impact_lines(bool with_title) const {
  if (impacts_.empty()) return {};
  const bool rug = impacts_.size() > kMaxImpactLines;
  const std::string title = rug ? "impact (ticks)" : "impact";
  return std::string(", \\\n       $impacts using 1:") + (rug ? "(0.965):(0):(0.035)" : "(0):(0):(1)") +
         " axes x1y2 with vectors nohead " + (rug ? "lw 1 lc rgb '#60000000' " : "dt 2 lw 1 lc rgb '#707070' ") +
         (with_title ? "title " + gp_str(title) : std::string("notitle"));
}

std::string ScriptWriter::impact_point_style(std::size_t marks) {
  return marks <= kMaxImpactCircles ? "with points pt 6 ps 1.6 lw 1.5 lc rgb 'black' title 'impact'"
                                    : "with points pt 7 ps 0.5 lc rgb '#a0000000' title 'impact'";
}

void ScriptWriter::impact_axis() {
  if (!impacts_.empty()) os_ << "  set y2range [0:1]; unset y2tics\n";
}

void ScriptWriter::coordinates() {
  // Panels by unit, in order of first appearance.
  std::vector<std::string> unit_order;
  std::map<std::string, std::vector<std::size_t>> groups;
  for (std::size_t i = 0; i < coords_.size(); ++i) {
    if (!groups.count(units_[i])) unit_order.push_back(units_[i]);
    groups[units_[i]].push_back(i);
  }
  const std::size_t panels = unit_order.size();
  const double top = 0.90, bottom = 0.09;
  os_ << "# 2. Coordinates against time, one panel per unit\n";
  begin_plot("coordinates");
  os_ << "  set multiplot layout " << panels << ",1 margins 0.10,0.80," << bottom << "," << top
      << " spacing 0,0.035 title " << gp_str(titled(spec_.title, "coordinates against time")) << "\n"
      << "  set xrange " << range(time_range()) << "\n";
  impact_axis();
  for (std::size_t p = 0; p < panels; ++p) {
    const std::string& unit = unit_order[p];
    std::vector<std::size_t> members = groups[unit];
    const std::size_t total = members.size();
    std::string shown;  // legend title when not all are drawn
    if (members.size() > kMaxLinesPerPanel) {
      // Too many for one panel: those that move (a constant coordinate
      // says little), at most kMaxLinesPerPanel.
      std::vector<std::size_t> moving;
      for (std::size_t i : members)
        if (varies(i, false)) moving.push_back(i);
      if (!moving.empty()) members = moving;
      if (members.size() > kMaxLinesPerPanel) members.resize(kMaxLinesPerPanel);
      shown = std::to_string(members.size()) + " of " + std::to_string(total) +
              (moving.empty() || moving.size() > kMaxLinesPerPanel ? "" : " (moving)");
    }
    std::vector<std::string> names;
    std::vector<std::size_t> cols;
    for (std::size_t i : members) {
      names.push_back(coords_[i]);
      cols.push_back(cols_.q[i]);
    }
    std::string what = total <= 3 ? join(names, ", ") : "coordinates";
    if (unit.empty() && total > 3) what = "unitless coordinates";
    const bool last = p + 1 == panels;
    os_ << "  # " << (unit.empty() ? "no unit" : unit) << "\n"
        << "  set ylabel " << gp_str(with_unit(what, unit)) << "\n"
        << "  set yrange " << range(col_range(cols)) << "\n"
        << (last ? "  set xlabel 't (s)'; set format x '%g'\n" : "  unset xlabel; set format x ''\n");
    // A legend unless the panel has a single line (named by the y label).
    if (members.size() == 1 && !(p == 0 && !impacts_.empty())) {
      os_ << "  unset key\n";
    } else {
      os_ << "  set key outside right top title " << gp_str(shown) << "\n";
    }
    os_ << "  plot ";
    for (std::size_t k = 0; k < members.size(); ++k)
      os_ << (k ? ", \\\n       " : "") << source({column_q(cols[k])}, true) << " with lines "
          << line_style(members[k], k) << " title " << gp_str(names[k]);
    os_ << impact_lines(p == 0) << "\n";
  }
  os_ << "  unset multiplot\n";
  end_plot();
}

void ScriptWriter::energy() {
  // Each line is its energy's relative change (E − E0)/|E0| (relative to E_scale where E0 = 0) on an axis at
  // least ±kEnergyChartFloor wide: round-off draws as the flat line it is, and the title says how constant.
  const double scale = spec_.energy_scale;
  struct Line {
    int col;
    double ref;
    double lo, hi;  // the relative change's range
  };
  std::vector<Line> lines;
  auto line = [&](int col) {
    const double e0 = tr_.first[col], ref = lagrangian::detail::energy_chart_reference(e0, scale);
    lines.push_back({col, ref, (tr_.lo[col] - e0) / ref, (tr_.hi[col] - e0) / ref});
  };
  line(cols_.energy);
  if (cols_.total_energy) line(cols_.total_energy);
  double lo = 0, hi = 0;  // the range always shows 0
  for (const Line& l : lines) {
    if (std::isfinite(l.lo)) lo = std::min(lo, l.lo);
    if (std::isfinite(l.hi)) hi = std::max(hi, l.hi);
  }
  const double span = std::max(-lo, hi);
  const bool flat = span <= lagrangian::detail::kEnergyChartFloor;
  const std::pair<double, double> yr =
      flat ? std::pair{-lagrangian::detail::kEnergyChartFloor, lagrangian::detail::kEnergyChartFloor} : padded(lo, hi);
  const double e0 = tr_.first[cols_.energy];
  const std::string ref_name = e0 != 0 ? "|E0|, E0 = " + short_num(e0) + " J" : "E_scale = " + short_num(scale) + " J";
  // With e < 1 the plot shows what the impacts took (the steps), with the
  // integration error between them: titled for that, not as an error.
  const std::string what = impacts_lose_energy_ ? "energy lost at the impacts (the steps), relative to " + ref_name
                           : flat ? (span > 0 ? "energy constant to " + short_num(span) + " of " + ref_name
                                             : "energy constant to the last digit (" + ref_name + ")")
                                  : "relative energy error (of " + ref_name + ")";
  os_ << "# 3. " << (impacts_lose_energy_ ? "Energy lost at the impacts" : "Relative energy error") << "\n";
  begin_plot("energy");
  os_ << "  set title " << gp_str(titled(spec_.title, what)) << "\n"
      << "  set xlabel 't (s)'\n"
      << "  set ylabel " << gp_str(e0 != 0 ? "(E − E0) / |E0|" : "(E − E0) / E_scale") << "\n"
      << "  set format y " << (std::max(-yr.first, yr.second) < 1e-2 ? "'%.1e'" : "'%g'") << "\n"
      << "  set xrange " << range(time_range()) << "\n"
      << "  set yrange " << range(yr) << "\n"
      << "  set key outside right top\n";
  impact_axis();
  const char* names[2][2] = {{"E0", "energy"}, {"Etot0", "total_energy"}};
  for (std::size_t k = 0; k < lines.size(); ++k) {
    const std::string expr = "(column(" + std::to_string(lines[k].col + 1) + ") - " + names[k][0] + ")/" + num(lines[k].ref);
    const std::string shown = "(" + std::string(names[k][1]) + " - " + names[k][0] + ")/" + short_num(lines[k].ref);
    os_ << (k ? ", \\\n       " : "  plot ") << source({{expr, shown}}, true)
        << (k ? " with lines lt 2 dt 2 title 'T + V'"
              : cols_.total_energy ? " with lines lt 1 title 'h = p·q̇ − L'" : " with lines lt 1 title 'energy'");
  }
  // With e < 1 the steps at the impacts are the energy they took, not error.
  os_ << impact_lines(true) << "\n";
  end_plot();
}

void ScriptWriter::phase() {
  // Up to four coordinates whose rate varies (the informative portraits),
  // else those that move at all, else the first ones.
  std::vector<std::size_t> chosen;
  for (std::size_t i = 0; i < coords_.size() && chosen.size() < kMaxPhasePanels; ++i)
    if (varies(i, true)) chosen.push_back(i);
  if (chosen.empty())
    for (std::size_t i = 0; i < coords_.size() && chosen.size() < kMaxPhasePanels; ++i)
      if (varies(i, false)) chosen.push_back(i);
  if (chosen.empty())
    for (std::size_t i = 0; i < std::min<std::size_t>(kMaxPhasePanels, coords_.size()); ++i) chosen.push_back(i);
  if (chosen.empty()) return;
  const std::size_t np = chosen.size();
  const std::size_t rows = np <= 2 ? 1 : 2, cols = np == 1 ? 1 : 2;
  std::string what = "phase portraits";
  if (np == 1) what = "phase portrait";
  if (coords_.size() > np) what += " (" + std::to_string(np) + " of " + std::to_string(coords_.size()) + " coordinates)";
  os_ << "# 4. Phase portraits\n";
  begin_plot("phase");
  os_ << "  set multiplot layout " << rows << "," << cols << " margins 0.09,0.97,0.09," << (rows == 1 ? 0.86 : 0.90)
      << " spacing 0.10,0.13 title " << gp_str(titled(spec_.title, what)) << "\n"
      << "  unset key\n";
  for (std::size_t k = 0; k < np; ++k) {
    const std::size_t i = chosen[k];
    os_ << "  set title " << gp_str(coords_[i]) << "\n"
        << "  set xlabel " << gp_str(with_unit(coords_[i], units_[i])) << "\n"
        << "  set ylabel " << gp_str(with_unit(coords_[i] + "_dot", rate_unit(units_[i]))) << "\n"
        << "  set xrange " << range(col_range({cols_.q[i]})) << "\n"
        << "  set yrange " << range(col_range({cols_.qd[i]})) << "\n"
        << "  plot " << source({column_q(cols_.q[i]), column_q(cols_.qd[i])}) << " with lines "
        << line_style(i, k, false) << "\n";
  }
  os_ << "  unset multiplot\n";
  end_plot();
}

}  // namespace lagrangian::plots_detail
