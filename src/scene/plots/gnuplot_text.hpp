#pragma once
// Internal: text and number formatting for the gnuplot scripts the plots
// write (quoted strings, numbers, labels, axis ranges) and their common styles.

#include <iosfwd>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace lagrangian::plots_detail {

// A gnuplot single-quoted string: no escapes inside, a quote is doubled; a
// line break (which would end the command) becomes a space.
std::string gp_str(std::string_view s);

// The shortest text that reads back as exactly v; NaN for a non-finite value.
std::string num(double v);

std::string short_num(double v);

std::string with_unit(const std::string& what, const std::string& unit);

std::string rate_unit(const std::string& unit);

std::string join(const std::vector<std::string>& parts, const std::string& sep);

std::string titled(const std::string& scene, const std::string& what);

// A padded axis range around [lo, hi] (finite values only).
std::pair<double, double> padded(double lo, double hi, double pad = 0.05);

// Widens h or v (about its centre) so that their spans have the ratio `aspect`.
void fill_aspect(std::pair<double, double>& h, std::pair<double, double>& v, double aspect);

std::string range(std::pair<double, double> r);

std::string trim(std::string s);

// Colours (the Tableau 10 palette), the settings every plot starts from
// (`setup`) and the two terminals (`png_terminal`, `svg_terminal`) at
// width × height pixels.
void write_styles(std::ostream& os, int width, int height);

}  // namespace lagrangian::plots_detail
