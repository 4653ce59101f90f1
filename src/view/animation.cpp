// The animation page: checks a figure and a track, thins the samples to the
// size budget and writes the page template with the data embedded as JSON.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "check.hpp"
#include "lagrangian/view/detail/energy_chart.hpp"
#include "lagrangian/detail/text_output.hpp"
#include "lagrangian/view/view.hpp"
#include "page.hpp"

namespace lagrangian::view {
namespace {

using lagrangian::detail::json_string;  // escapes <, > and & too: safe inside the page's <script>

std::string number(double v, int digits) {
  if (!std::isfinite(v)) return "null";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string html_escaped(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '&':
        out += "&amp;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

void point(std::ostringstream& os, const Point& p) {
  os << '[' << number(p[0], 17) << ',' << number(p[1], 17) << ',' << number(p[2], 17) << ']';
}

std::string base64(const std::vector<float>& values) {
  static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
  const std::size_t n = values.size() * sizeof(float);
  std::string out;
  out.reserve((n + 2) / 3 * 4);
  for (std::size_t i = 0; i < n; i += 3) {
    const std::uint32_t b0 = bytes[i], b1 = i + 1 < n ? bytes[i + 1] : 0, b2 = i + 2 < n ? bytes[i + 2] : 0;
    const std::uint32_t w = (b0 << 16) | (b1 << 8) | b2;
    out += digits[(w >> 18) & 63];
    out += digits[(w >> 12) & 63];
    out += i + 1 < n ? digits[(w >> 6) & 63] : '=';
    out += i + 2 < n ? digits[w & 63] : '=';
  }
  return out;
}

[[noreturn]] void bad(const std::string& field, const std::string& what) {
  throw std::invalid_argument("animation: " + field + ": " + what);
}

void check_point(const std::string& field, const Point& p) {
  for (const double v : p)
    if (!std::isfinite(v)) bad(field, "is not finite (" + number(v, 6) + ")");
}

}  // namespace

void detail::check(const Figure& figure, const Track& track) {
  const std::size_t nb = figure.bodies.size(), n = track.t.size();
  if (n == 0) bad("track.t", "has no samples");
  for (std::size_t b = 0; b < nb; ++b)
    if (!(figure.bodies[b].radius >= 0) || !std::isfinite(figure.bodies[b].radius))
      bad("figure.bodies[" + std::to_string(b) + "].radius",
          "must be finite and >= 0, is " + number(figure.bodies[b].radius, 6));
  auto check_segments = [&](const std::vector<Figure::Segment>& list, const std::string& name) {
    for (std::size_t k = 0; k < list.size(); ++k) {
      const auto& s = list[k];
      const std::string field = "figure." + name + "[" + std::to_string(k) + "]";
      if (s.a < 0 || static_cast<std::size_t>(s.a) >= nb) bad(field + ".a", "no body " + std::to_string(s.a));
      if (s.b >= 0 && static_cast<std::size_t>(s.b) >= nb) bad(field + ".b", "no body " + std::to_string(s.b));
      check_point(field + ".anchor", s.anchor);
    }
  };
  check_segments(figure.rods, "rods");
  check_segments(figure.springs, "springs");
  for (std::size_t k = 0; k < figure.pivots.size(); ++k)
    check_point("figure.pivots[" + std::to_string(k) + "]", figure.pivots[k]);
  for (std::size_t k = 0; k < figure.planes.size(); ++k) {
    check_point("figure.planes[" + std::to_string(k) + "].point", figure.planes[k].point);
    check_point("figure.planes[" + std::to_string(k) + "].normal", figure.planes[k].normal);
  }
  for (std::size_t k = 0; k < figure.boxes.size(); ++k) {
    check_point("figure.boxes[" + std::to_string(k) + "].min", figure.boxes[k].min);
    check_point("figure.boxes[" + std::to_string(k) + "].max", figure.boxes[k].max);
  }
  for (std::size_t k = 0; k < figure.spheres.size(); ++k) {
    check_point("figure.spheres[" + std::to_string(k) + "].centre", figure.spheres[k].centre);
    if (!(figure.spheres[k].radius > 0) || !std::isfinite(figure.spheres[k].radius))
      bad("figure.spheres[" + std::to_string(k) + "].radius", "must be finite and > 0");
  }
  for (std::size_t k = 0; k < figure.circles.size(); ++k) {
    check_point("figure.circles[" + std::to_string(k) + "].centre", figure.circles[k].centre);
    check_point("figure.circles[" + std::to_string(k) + "].normal", figure.circles[k].normal);
    if (!(figure.circles[k].radius > 0) || !std::isfinite(figure.circles[k].radius))
      bad("figure.circles[" + std::to_string(k) + "].radius", "must be finite and > 0");
  }
  check_point("figure.up", figure.up);
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(track.t[k])) bad("track.t[" + std::to_string(k) + "]", "is not finite");
    if (k > 0 && track.t[k] < track.t[k - 1])
      bad("track.t[" + std::to_string(k) + "]",
          "decreases (" + number(track.t[k], 17) + " after " + number(track.t[k - 1], 17) + ")");
  }
  if (track.positions.size() != n * nb * 3)
    bad("track.positions", "has " + std::to_string(track.positions.size()) + " values, expected samples (" +
                               std::to_string(n) + ") x bodies (" + std::to_string(nb) + ") x 3");
  for (std::size_t i = 0; i < track.positions.size(); ++i)
    if (!std::isfinite(track.positions[i])) {
      const std::size_t k = i / (3 * nb), b = (i / 3) % nb;
      bad("track.positions", "body '" + figure.bodies[b].name + "' at t = " + number(track.t[k], 10) +
                                 " s is not finite (" + number(track.positions[i], 6) + ")");
    }
  auto check_series = [&](const Series& s, const std::string& field) {
    if (!s.values.empty() && s.values.size() != n)
      bad(field,
          "'" + s.name + "' has " + std::to_string(s.values.size()) + " values for " + std::to_string(n) + " samples");
  };
  check_series(track.energy, "track.energy");
  for (const Series& s : track.coordinates) check_series(s, "track.coordinates");
  for (std::size_t k = 0; k < track.events.size(); ++k)
    for (const int b : track.events[k].bodies)
      if (b < 0 || static_cast<std::size_t>(b) >= nb)
        bad("track.events[" + std::to_string(k) + "].bodies", "no body " + std::to_string(b));
}

namespace {

void segments(std::ostringstream& os, const std::vector<Figure::Segment>& list) {
  os << '[';
  for (std::size_t k = 0; k < list.size(); ++k) {
    os << (k ? "," : "") << "{\"a\":" << list[k].a << ",\"b\":" << list[k].b << ",\"anchor\":";
    point(os, list[k].anchor);
    os << '}';
  }
  os << ']';
}

void series_json(std::ostringstream& os, const Series& s, const std::vector<std::size_t>& kept) {
  os << "{\"name\":";
  json_string(os, s.name);
  os << ",\"unit\":";
  json_string(os, s.unit);
  os << ",\"values\":[";
  for (std::size_t k = 0; k < kept.size(); ++k) os << (k ? "," : "") << number(s.values[kept[k]], 9);
  os << "]}";
}

/// The energy as the page charts it: its relative change (E − E0)/|E0| (relative to the run's energy scale
/// where E0 = 0, or the largest |E| without one) at each kept sample, computed here from the full-precision
/// values, with E0, what it is relative to, the largest |change| and the chart's floor (kEnergyChartFloor:
/// a smaller change draws flat).
void energy_json(std::ostringstream& os, const Series& s, double scale, const std::vector<std::size_t>& kept) {
  double e0 = std::nan(""), largest = 0;
  for (double v : s.values)
    if (std::isfinite(v)) {
      if (!std::isfinite(e0)) e0 = v;
      largest = std::max(largest, std::abs(v));
    }
  const bool of_e0 = std::isfinite(e0) && e0 != 0, of_scale = !of_e0 && scale > 0;
  const double ref =
      lagrangian::detail::energy_chart_reference(e0, of_scale ? scale : largest > 0 ? largest : 1.0);
  double span = 0;  // over every sample, those between the kept ones too
  for (double v : s.values)
    if (std::isfinite(v)) span = std::max(span, std::abs(v - e0) / ref);
  std::vector<double> change(kept.size(), std::nan(""));
  for (std::size_t k = 0; k < kept.size(); ++k)
    if (const double v = s.values[kept[k]]; std::isfinite(v)) change[k] = (v - e0) / ref;
  os << "{\"name\":";
  json_string(os, s.name);
  os << ",\"unit\":";
  json_string(os, s.unit);
  os << ",\"e0\":" << number(std::isfinite(e0) ? e0 : 0.0, 17) << ",\"relative_to\":";
  json_string(os, of_e0 ? "|E0|" : of_scale ? "the energy scale " + number(scale, 4) + " J" : "max |E|");
  os << ",\"reference\":" << number(ref, 17) << ",\"span\":" << number(span, 3)
     << ",\"floor\":" << number(lagrangian::detail::kEnergyChartFloor, 3) << ",\"values\":[";
  for (std::size_t k = 0; k < kept.size(); ++k) os << (k ? "," : "") << number(change[k], 9);
  os << "]}";
}

bool moves(const Series& s) {
  if (s.values.empty()) return false;
  const auto [lo, hi] = std::minmax_element(s.values.begin(), s.values.end());
  return *hi > *lo;
}

std::string si_bytes(double b) {
  char buf[32];
  if (b >= 1 << 20)
    std::snprintf(buf, sizeof buf, "%.1f MB", b / (1 << 20));
  else
    std::snprintf(buf, sizeof buf, "%.0f kB", b / 1024);
  return buf;
}

void replace_all(std::string& s, const std::string& from, const std::string& to) {
  for (std::size_t at = s.find(from); at != std::string::npos; at = s.find(from, at + to.size()))
    s.replace(at, from.size(), to);
}

}  // namespace

std::size_t sample_stride(std::size_t samples, std::size_t bodies, const Options& options) {
  const std::size_t per_sample = std::max<std::size_t>(1, bodies * 3 * sizeof(float));
  const std::size_t fit =
      std::max<std::size_t>(2, std::min(options.max_frames, options.max_position_bytes / per_sample));
  if (samples <= fit) return 1;
  // every k-th sample and the last: ceil((samples - 1) / k) + 1 <= fit
  return (samples - 1 + fit - 2) / (fit - 1);
}

bool page_available() { return !detail::page_template.empty(); }

Written write_animation(const std::string& path, const Figure& figure, const Track& track, const Options& options) {
  if (!page_available())
    throw std::runtime_error(
        "animation: this build of lagrangian has no animation page (configured with "
        "LAGRANGIAN_ANIMATION=OFF; run scripts/setup, which installs web/'s npm packages, and "
        "build again)");
  detail::check(figure, track);
  const std::size_t nb = figure.bodies.size(), n = track.t.size();
  const std::size_t stride = sample_stride(n, nb, options);
  std::vector<std::size_t> kept;
  for (std::size_t k = 0; k < n; k += stride) kept.push_back(k);
  if (kept.back() != n - 1) kept.push_back(n - 1);

  std::vector<float> xyz;
  xyz.reserve(kept.size() * nb * 3);
  for (const std::size_t k : kept)
    for (std::size_t i = 0; i < nb * 3; ++i) xyz.push_back(static_cast<float>(track.positions[k * nb * 3 + i]));

  const std::size_t total = track.samples_total ? track.samples_total : n;
  std::ostringstream note;
  note << kept.size() << " of " << total << " samples shown";
  if (kept.size() < total)
    note << " (thinned evenly to keep the file small: " << si_bytes(xyz.size() * 4.0) << " of positions)";
  const double interval =
      kept.size() > 1 ? (track.t[kept.back()] - track.t[kept.front()]) / static_cast<double>(kept.size() - 1) : 0.0;

  std::ostringstream os;
  os << "{\"title\":";
  json_string(os, options.title);
  os << ",\"up\":";
  point(os, figure.up);
  os << ",\"bodies\":[";
  for (std::size_t b = 0; b < nb; ++b) {
    os << (b ? "," : "") << "{\"name\":";
    json_string(os, figure.bodies[b].name);
    os << ",\"radius\":" << number(figure.bodies[b].radius, 17);
    if (figure.bodies[b].color >= 0) os << ",\"color\":" << figure.bodies[b].color;
    os << '}';
  }
  os << "],\"rods\":";
  segments(os, figure.rods);
  os << ",\"springs\":";
  segments(os, figure.springs);
  os << ",\"pivots\":[";
  for (std::size_t k = 0; k < figure.pivots.size(); ++k) {
    if (k) os << ',';
    point(os, figure.pivots[k]);
  }
  os << "],\"planes\":[";
  for (std::size_t k = 0; k < figure.planes.size(); ++k) {
    const auto& p = figure.planes[k];
    os << (k ? "," : "") << "{\"name\":";
    json_string(os, p.name);
    os << ",\"point\":";
    point(os, p.point);
    os << ",\"normal\":";
    point(os, p.normal);
    os << '}';
  }
  os << "],\"boxes\":[";
  for (std::size_t k = 0; k < figure.boxes.size(); ++k) {
    os << (k ? "," : "") << "{\"min\":";
    point(os, figure.boxes[k].min);
    os << ",\"max\":";
    point(os, figure.boxes[k].max);
    os << '}';
  }
  os << "],\"spheres\":[";
  for (std::size_t k = 0; k < figure.spheres.size(); ++k) {
    os << (k ? "," : "") << "{\"centre\":";
    point(os, figure.spheres[k].centre);
    os << ",\"radius\":" << number(figure.spheres[k].radius, 17) << '}';
  }
  os << "],\"circles\":[";
  for (std::size_t k = 0; k < figure.circles.size(); ++k) {
    os << (k ? "," : "") << "{\"centre\":";
    point(os, figure.circles[k].centre);
    os << ",\"normal\":";
    point(os, figure.circles[k].normal);
    os << ",\"radius\":" << number(figure.circles[k].radius, 17) << '}';
  }
  os << "],\"frames\":{\"t\":[";
  for (std::size_t k = 0; k < kept.size(); ++k) os << (k ? "," : "") << number(track.t[kept[k]], 17);
  os << "],\"positions\":\"" << base64(xyz) << "\",\"note\":";
  json_string(os, note.str());
  os << ",\"interval\":" << number(interval, 9) << "},\"energy\":";
  if (track.energy.values.empty()) {
    os << "null";
  } else {
    energy_json(os, track.energy, track.energy_scale, kept);
  }
  os << ",\"coordinates\":[";
  std::size_t plotted = 0, moving = 0;
  for (const Series& s : track.coordinates) {
    if (!moves(s)) continue;
    ++moving;
    if (plotted == options.max_coordinates) continue;
    if (plotted++) os << ',';
    series_json(os, s, kept);
  }
  std::string coordinates_note = track.coordinates_note;
  if (moving > plotted) {
    if (!coordinates_note.empty()) coordinates_note += "; ";
    coordinates_note += "coordinates: the first " + std::to_string(plotted) + " of the " + std::to_string(moving) +
                        " that move are plotted";
  }
  os << "],\"coordinates_note\":";
  json_string(os, coordinates_note);
  os << ",\"events\":[";
  for (std::size_t k = 0; k < track.events.size(); ++k) {
    const Event& e = track.events[k];
    os << (k ? "," : "") << "{\"t\":" << number(e.t, 17) << ",\"kind\":";
    json_string(os, e.kind);
    os << ",\"label\":";
    json_string(os, e.label);
    os << ",\"bodies\":[";
    for (std::size_t j = 0; j < e.bodies.size(); ++j) os << (j ? "," : "") << e.bodies[j];
    os << "]}";
  }
  os << "]}";

  std::string legend;
  const bool points =
      std::any_of(figure.bodies.begin(), figure.bodies.end(), [](const auto& b) { return b.radius == 0; });
  if (nb <= 12) {
    for (std::size_t b = 0; b < nb; ++b)
      legend += (b ? ", " : "") + html_escaped(figure.bodies[b].name) +
                (figure.bodies[b].radius > 0 ? " (r = " + number(figure.bodies[b].radius, 3) + " m)" : "");
  } else {
    legend = std::to_string(nb) + " bodies";
  }
  if (points) legend += " · point masses drawn at 2.5 % of the scene's size";
  legend += " · drag to orbit, right-drag to pan, wheel to zoom";

  std::string page(detail::page_template);
  replace_all(page, "<!--LAGRANGIAN-TITLE-->", html_escaped(options.title));
  replace_all(page, "<!--LAGRANGIAN-DESCRIPTION-->", html_escaped(options.description));
  replace_all(page, "<!--LAGRANGIAN-LEGEND-->", legend);
  const std::string data = os.str();
  const std::size_t at = page.find("<!--LAGRANGIAN-DATA-->");
  page.replace(at, std::strlen("<!--LAGRANGIAN-DATA-->"), data);

  const std::string partial = path + ".partial";
  {
    std::ofstream out(partial, std::ios::binary);
    out << page;
    out.close();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(partial, ec);
      throw std::runtime_error("animation: cannot write '" + partial + "'");
    }
  }
  std::error_code ec;
  std::filesystem::rename(partial, path, ec);
  if (ec) {
    std::filesystem::remove(partial, ec);
    throw std::runtime_error("animation: cannot rename '" + partial + "' to '" + path + "': " + ec.message());
  }
  return {path, total, kept.size(), page.size()};
}

}  // namespace lagrangian::view
