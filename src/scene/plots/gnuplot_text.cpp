// Text and number formatting for the gnuplot scripts: quoted strings, exact
// and short numbers, labels, padded and equal-aspect axis ranges, the styles.
#include "gnuplot_text.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <ostream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace lagrangian::plots_detail {

std::string gp_str(std::string_view s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += "''";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out + "'";
}

std::string num(double v) {
  if (!std::isfinite(v)) return "NaN";
  char buf[40];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : "NaN";
}

std::string short_num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string with_unit(const std::string& what, const std::string& unit) {
  return unit.empty() ? what : what + " (" + unit + ")";
}

std::string rate_unit(const std::string& unit) { return unit.empty() ? "1/s" : unit + "/s"; }

std::string join(const std::vector<std::string>& parts, const std::string& sep) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? sep : "") + parts[i];
  return out;
}

std::string titled(const std::string& scene, const std::string& what) {
  return scene.empty() ? what : scene + ": " + what;
}

std::pair<double, double> padded(double lo, double hi, double pad) {
  if (!(lo <= hi)) return {-1, 1};  // no finite value at all
  const double span = hi - lo;
  if (span > 0) return {lo - pad * span, hi + pad * span};
  const double half = std::max(1e-3, 0.1 * std::abs(lo));
  return {lo - half, hi + half};
}

void fill_aspect(std::pair<double, double>& h, std::pair<double, double>& v, double aspect) {
  const double hs = h.second - h.first, vs = v.second - v.first;
  if (!(hs > 0) || !(vs > 0)) return;
  if (vs < aspect * hs) {
    const double grow = (aspect * hs - vs) / 2;
    v = {v.first - grow, v.second + grow};
  } else {
    const double grow = (vs / aspect - hs) / 2;
    h = {h.first - grow, h.second + grow};
  }
}

std::string range(std::pair<double, double> r) { return "[" + num(r.first) + ":" + num(r.second) + "]"; }

std::string trim(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  std::size_t i = 0;
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  return s.substr(i);
}

void write_styles(std::ostream& os, int width, int height) {
  os << "# Colours (the Tableau 10 palette) and the settings every plot starts from.\n";
  static const char* palette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                  "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  for (int i = 0; i < 10; ++i) os << "set linetype " << i + 1 << " lc rgb '" << palette[i] << "' lw 1.5 pt 7 ps 0.8\n";
  const std::string size = std::to_string(width) + "," + std::to_string(height);
  os << "set linetype cycle 10\n"
     << "setup = \"set encoding utf8; "
        "set grid lc rgb '#d9d9d9' lw 1 dt 1; set key noautotitle spacing 1.2; set tics front\"\n"
     << "png_terminal = \"set terminal pngcairo size " << size
     << " noenhanced font 'Sans,11' linewidth 1 background rgb 'white'\"\n"
     << "svg_terminal = \"set terminal svg size " << size
     << " noenhanced dynamic font 'Sans,12' linewidth 1 background rgb 'white'\"\n\n";
}

}  // namespace lagrangian::plots_detail
