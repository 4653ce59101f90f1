// ScriptWriter's trajectory plots: bodies in space (with the planes, the
// impact marks and the positions at impacts) or the generalized coordinates
// against each other.
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

namespace lagrangian::plots_detail {

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

/// The axes of the particles' trajectory plot: the two with the largest
/// spread over all bodies (in axis order) when the motion is planar or
/// nothing moves, else the one with the largest (av = -1: against time).
std::pair<int, int> ScriptWriter::particle_axes() const {
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
  return {ah, av};
}

/// The data blocks $start (each drawn body's first point, with its line
/// type) and $impact_points (where the listed bodies were at impacts), in
/// the plane of hcols and vcols or, not in_plane, hcols against time;
/// the number of impact points.
std::size_t ScriptWriter::start_and_impact_points(const std::vector<std::size_t>& drawable,
                                                  const std::vector<std::size_t>& hcols,
                                                  const std::vector<std::size_t>& vcols, bool in_plane) {
  const auto& bodies = spec_.bodies;
  os_ << "$start << EOD\n# h v linetype\n";
  for (std::size_t k = 0; k < drawable.size(); ++k) {
    const double h = in_plane ? tr_.first[hcols[k]] : tr_.first[0];
    const double v = in_plane ? tr_.first[vcols[k]] : tr_.first[hcols[k]];
    os_ << num(h) << " " << num(v) << " " << (drawable[k] % 10) + 1 << "\n";
  }
  os_ << "EOD\n";
  std::size_t marks = 0;
  std::ostringstream pts;
  for (const Impact& imp : positions_) {
    for (std::size_t k = 0; k < drawable.size(); ++k) {
      if (!names_body(imp.bodies, bodies[drawable[k]].name) || !tr_.kept(hcols[k]) ||
          (in_plane && !tr_.kept(vcols[k])))
        continue;
      const double h = in_plane ? tr_.at(imp, hcols[k]) : imp.t;
      const double v = in_plane ? tr_.at(imp, vcols[k]) : tr_.at(imp, hcols[k]);
      pts << num(h) << " " << num(v) << "\n";
      ++marks;
    }
  }
  if (marks) os_ << "$impact_points << EOD\n# h v\n" << pts.str() << "EOD\n";
  return marks;
}

void ScriptWriter::particle_trajectory() {
  const auto& bodies = spec_.bodies;
  const auto [ah, av] = particle_axes();
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

  const std::size_t marks = start_and_impact_points(drawable, hcols, vcols, av >= 0);
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

}  // namespace lagrangian::plots_detail
