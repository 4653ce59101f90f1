// ScriptWriter's members: the data blocks read once from the trajectory, then
// the trajectory, coordinates, energy and phase plots of make_plots().
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

constexpr std::size_t kMaxImpactLines = 50;    // beyond, impact times are ticks, not lines across
constexpr std::size_t kMaxImpactCircles = 50;  // beyond, impact positions are small translucent dots
constexpr std::size_t kMaxLinesPerPanel = 10;  // coordinates drawn per unit panel (one colour each)
constexpr int kMaxPhasePanels = 4;

// Height / width of the plot area of a 1000×700 page with a title and axis
// labels, with and without a legend on the right.
constexpr double kAspectWithKey = 0.74;
constexpr double kAspectNoKey = 0.64;

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

void ScriptWriter::plane_lines(int ah, int av, std::pair<double, double> hr, std::pair<double, double> vr) {
  int k = 0;
  for (const PlotSpec::Plane& pl : spec_.planes) {
    const double nn =
        std::sqrt(pl.normal[0] * pl.normal[0] + pl.normal[1] * pl.normal[1] + pl.normal[2] * pl.normal[2]);
    if (!(nn > 0)) continue;
    double h0, v0, h1, v1;
    if (ah < 0) {  // position along av against t: a plane across that axis is a level
      if (std::abs(pl.normal[av]) < (1 - 1e-9) * nn) continue;
      h0 = hr.first, h1 = hr.second, v0 = v1 = pl.point[av];
      if (v0 < vr.first || v0 > vr.second) continue;
    } else {
      const int third = 3 - ah - av;
      if (std::abs(pl.normal[third]) > 1e-9 * nn) continue;  // oblique to the plotted plane
      // The line n_h (h − p_h) + n_v (v − p_v) = 0, clipped to hr × vr.
      const double ph = pl.point[ah], pv = pl.point[av], dh = -pl.normal[av], dv = pl.normal[ah];
      double lo = -1e300, hi = 1e300;
      const auto clip = [&](double p, double d, double a, double b) {
        if (d == 0) return p >= a && p <= b;
        double s0 = (a - p) / d, s1 = (b - p) / d;
        if (s0 > s1) std::swap(s0, s1);
        lo = std::max(lo, s0);
        hi = std::min(hi, s1);
        return lo <= hi;
      };
      if (!clip(ph, dh, hr.first, hr.second) || !clip(pv, dv, vr.first, vr.second)) continue;
      h0 = ph + lo * dh, v0 = pv + lo * dv, h1 = ph + hi * dh, v1 = pv + hi * dv;
    }
    ++k;
    os_ << "  set arrow " << k << " from " << num(h0) << "," << num(v0) << " to " << num(h1) << "," << num(v1)
        << " nohead back lw 2.5 lc rgb '#8c8677'\n";
    if (!pl.name.empty()) {  // named at its right-hand end, inside the plot
      const bool first = h0 > h1;
      os_ << "  set label " << 100 + k << " " << gp_str(pl.name) << " at " << num(first ? h0 : h1) << ","
          << num(first ? v0 : v1) << " right offset -0.5,0.8 tc rgb '#6b665a' font ',9'\n";
    }
  }
}

std::string ScriptWriter::mark_block(std::size_t hcol, std::size_t vcol) {
  std::ostringstream rows;
  std::size_t n = 0;
  for (const Impact& m : marks_) {
    if ((hcol != std::string::npos && !tr_.kept(hcol)) || !tr_.kept(vcol)) continue;
    const double h = hcol == std::string::npos ? m.t : tr_.at(m, hcol);
    std::string name = m.bodies;  // a data block's string column: in double quotes, none inside
    name.erase(std::remove(name.begin(), name.end(), '"'), name.end());
    rows << num(h) << " " << num(tr_.at(m, vcol)) << " \"" << name << "\"\n";
    ++n;
  }
  if (n == 0) return "";
  os_ << "$marks << EOD\n# h v name\n" << rows.str() << "EOD\n";
  return ", \\\n       $marks using 1:2 with points pt 9 ps 1.6 lc rgb '#222222' title 'events'"
         ", \\\n       $marks using 1:2:3 with labels left offset 0.8,0.6 font ',9' notitle";
}

void ScriptWriter::trajectory() {
  os_ << "# 1. Trajectory\n";
  if (!spec_.bodies.empty()) {
    particle_trajectory();
  } else {
    generalized_trajectory();
  }
}

void ScriptWriter::particle_trajectory() {
  const auto& bodies = spec_.bodies;
  // Spread of each Cartesian axis over all bodies.
  double lo[3], hi[3];
  bool present[3] = {false, false, false};
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::numeric_limits<double>::infinity();
    hi[a] = -lo[a];
  }
  for (const auto& b : bodies) {
    const int idx[3] = {b.x, b.y, b.z};
    for (int a = 0; a < 3; ++a) {
      if (idx[a] < 0) continue;
      present[a] = true;
      const std::size_t col = cols_.q[static_cast<std::size_t>(idx[a])];
      lo[a] = std::min(lo[a], tr_.lo[col]);
      hi[a] = std::max(hi[a], tr_.hi[col]);
    }
  }
  std::vector<int> axes;
  for (int a = 0; a < 3; ++a)
    if (present[a]) axes.push_back(a);
  auto axis_spread = [&](int a) { return hi[a] >= lo[a] ? hi[a] - lo[a] : 0.0; };
  std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) { return axis_spread(a) > axis_spread(b); });
  const bool planar = axes.size() >= 2 && axis_spread(axes[1]) > 1e-6 * axis_spread(axes[0]);
  const bool still = axes.size() >= 2 && axis_spread(axes[0]) == 0;  // nothing moves: show the positions
  int ah = axes.empty() ? 0 : axes[0], av = -1;
  if (planar || still) {
    ah = std::min(axes[0], axes[1]);
    av = std::max(axes[0], axes[1]);
  }
  static const char* axis_name[3] = {"x", "y", "z"};
  auto index_of = [](const PlotSpec::Body& b, int a) { return a == 0 ? b.x : a == 1 ? b.y : b.z; };

  // Bodies drawn: those with both axes; beyond kMaxBodiesUnlabelled only the first kLegendBodies.
  std::vector<std::size_t> drawable;
  for (std::size_t i = 0; i < bodies.size(); ++i)
    if (index_of(bodies[i], ah) >= 0 && (av < 0 || index_of(bodies[i], av) >= 0)) drawable.push_back(i);
  if (drawable.empty()) {  // no body has the axes: fall back to the configuration-space plot
    generalized_trajectory();
    return;
  }
  const std::size_t total = drawable.size();
  if (total > kMaxBodiesUnlabelled) drawable.resize(kLegendBodies);
  const bool legend = drawable.size() <= kLegendBodies;

  std::string unit_h, unit_v;
  std::vector<std::size_t> hcols, vcols;
  for (std::size_t i : drawable) {
    const auto ih = static_cast<std::size_t>(index_of(bodies[i], ah));
    hcols.push_back(cols_.q[ih]);
    if (unit_h.empty()) unit_h = units_[ih];
    if (av >= 0) {
      const auto iv = static_cast<std::size_t>(index_of(bodies[i], av));
      vcols.push_back(cols_.q[iv]);
      if (unit_v.empty()) unit_v = units_[iv];
    }
  }
  std::string what;
  if (av >= 0) {
    what = std::string("trajectory in the ") + axis_name[ah] + "–" + axis_name[av] + " plane";
  } else {
    what = std::string("position along ") + axis_name[ah] + " against time";
  }
  if (drawable.size() < total) {
    what += " (first " + std::to_string(drawable.size()) + " of " + std::to_string(total) + " bodies)";
  } else if (!legend) {
    what += " (" + std::to_string(total) + " bodies)";
  }

  // Start points and impact points.
  os_ << "$start << EOD\n# h v linetype\n";
  for (std::size_t k = 0; k < drawable.size(); ++k) {
    const double h = av >= 0 ? tr_.first[hcols[k]] : tr_.first[0];
    const double v = av >= 0 ? tr_.first[vcols[k]] : tr_.first[hcols[k]];
    os_ << num(h) << " " << num(v) << " " << (drawable[k] % 10) + 1 << "\n";
  }
  os_ << "EOD\n";
  std::size_t marks = 0;
  std::ostringstream pts;
  for (const Impact& imp : positions_) {
    for (std::size_t k = 0; k < drawable.size(); ++k) {
      if (!names_body(imp.bodies, bodies[drawable[k]].name) || !tr_.kept(hcols[k]) ||
          (av >= 0 && !tr_.kept(vcols[k])))
        continue;
      const double h = av >= 0 ? tr_.at(imp, hcols[k]) : imp.t;
      const double v = av >= 0 ? tr_.at(imp, vcols[k]) : tr_.at(imp, hcols[k]);
      pts << num(h) << " " << num(v) << "\n";
      ++marks;
    }
  }
  if (marks) os_ << "$impact_points << EOD\n# h v\n" << pts.str() << "EOD\n";
  const std::string named = drawable.size() == 1
                                ? mark_block(av >= 0 ? hcols[0] : std::string::npos, av >= 0 ? vcols[0] : hcols[0])
                                : std::string();

  std::pair<double, double> hr, vr;
  if (av >= 0) {
    hr = col_range(hcols);
    vr = col_range(vcols);
    // Equal scales: widen the shorter range (centred) so that the data
    // aspect matches the plot area and the picture fills the page.
    fill_aspect(hr, vr, legend ? kAspectWithKey : kAspectNoKey);
  } else {
    hr = time_range();
    vr = col_range(hcols);
  }

  begin_plot("trajectory");
  os_ << "  set title " << gp_str(titled(spec_.title, what)) << "\n";
  if (av >= 0) {
    os_ << "  set xlabel " << gp_str(with_unit(axis_name[ah], unit_h)) << "\n"
        << "  set ylabel " << gp_str(with_unit(axis_name[av], unit_v)) << "\n"
        << "  set size ratio -1    # equal scales on both axes\n";
  } else {
    os_ << "  set xlabel 't (s)'\n"
        << "  set ylabel " << gp_str(with_unit(axis_name[ah], unit_h)) << "\n";
  }
  os_ << "  set xrange " << range(hr) << "\n  set yrange " << range(vr) << "\n";
  if (av >= 0) plane_lines(ah, av, hr, vr);
  else plane_lines(-1, ah, hr, vr);
  os_ << (legend ? "  set key outside right top\n" : "  unset key\n");
  os_ << "  plot ";
  for (std::size_t k = 0; k < drawable.size(); ++k) {
    const std::string src =
        av >= 0 ? source({column_q(hcols[k]), column_q(vcols[k])}) : source({column_q(hcols[k])}, true);
    os_ << (k ? ", \\\n       " : "") << src << " with lines lt " << (drawable[k] % 10) + 1
        << " lw " << (legend ? "2" : "1") << " title " << gp_str(bodies[drawable[k]].name);
  }
  // Black under the coloured points: the legend shows a neutral "start".
  os_ << ", \\\n       $start using 1:2 with points pt 7 ps 1.2 lc rgb 'black' title 'start'"
      << ", \\\n       $start using 1:2:3 with points pt 7 ps 1.2 lc variable notitle";
  if (marks) os_ << ", \\\n       $impact_points using 1:2 " << impact_point_style(marks);
  os_ << named << "\n";
  end_plot();
}

void ScriptWriter::generalized_trajectory() {
  const std::size_t n = coords_.size();
  if (n == 0) return;
  const bool two = n >= 2;
  const std::size_t ch = two ? cols_.q[0] : 0, cv = two ? cols_.q[1] : cols_.q[0];
  const std::string uh = two ? units_[0] : "s", uv = two ? units_[1] : units_[0];
  os_ << "$start << EOD\n# h v\n" << num(tr_.first[ch]) << " " << num(tr_.first[cv]) << "\nEOD\n";
  if (!positions_.empty()) {
    os_ << "$impact_points << EOD\n# h v\n";
    for (const Impact& imp : positions_) os_ << num(tr_.at(imp, ch)) << " " << num(tr_.at(imp, cv)) << "\n";
    os_ << "EOD\n";
  }
  const std::string named = mark_block(two ? ch : std::string::npos, cv);
  auto hr = two ? col_range({ch}) : time_range();
  auto vr = col_range({cv});
  // Equal scales when both axes have the same unit and comparable spreads.
  const double sh = hr.second - hr.first, sv = vr.second - vr.first;
  const bool equal = two && uh == uv && sh > 0 && sv > 0 && sh / sv < 20 && sv / sh < 20;
  if (equal) fill_aspect(hr, vr, kAspectWithKey);

  begin_plot("trajectory");
  if (two) {
    os_ << "  set title " << gp_str(titled(spec_.title, "path in configuration space")) << "\n"
        << "  set xlabel " << gp_str(with_unit(coords_[0], uh)) << "\n";
  } else {
    os_ << "  set title " << gp_str(titled(spec_.title, coords_[0] + " against time")) << "\n"
        << "  set xlabel 't (s)'\n";
  }
  os_ << "  set ylabel " << gp_str(with_unit(two ? coords_[1] : coords_[0], uv)) << "\n";
  if (equal) os_ << "  set size ratio -1    # equal scales on both axes\n";
  os_ << "  set xrange " << range(hr) << "\n  set yrange " << range(vr) << "\n"
      << "  set key outside right top\n"
      << "  plot " << (two ? source({column_q(ch), column_q(cv)}) : source({column_q(cv)}, true))
      << " with lines lt 1 lw 1.5 title "
      << gp_str(two ? "path" : coords_[0]) << ", \\\n"
      << "       $start using 1:2 with points pt 7 ps 1.2 lc rgb 'black' title 'start'";
  if (!positions_.empty())
    os_ << ", \\\n       $impact_points using 1:2 " << impact_point_style(positions_.size());
  os_ << named << "\n";
  end_plot();
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
