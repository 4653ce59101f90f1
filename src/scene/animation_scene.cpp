// A scene's animation page: the figure from the scene (bodies, links,
// springs, planes, the box, surfaces) or from a built-in model's picture,
// the samples read back from the run's trajectory.csv (thinned while reading
// to the page's budget), the events from the run's report.

#include "animation_scene.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "lagrangian/detail/csv_header.hpp"
#include "lagrangian/scene/detail/contact_names.hpp"
#include "lagrangian/scene/detail/registry.hpp"
#include "lagrangian/errors.hpp"
#include "text_model_spec.hpp"

namespace lagrangian::scene::detail {
namespace {

view::Point point(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::size_t from = 0;
  for (;;) {
    const std::size_t at = line.find(',', from);
    out.push_back(line.substr(from, at == std::string::npos ? std::string::npos : at - from));
    if (at == std::string::npos) return out;
    from = at + 1;
  }
}

/// The rows of trajectory.csv kept for the page: t, the first `n`
/// coordinates and the energy, every `stride`-th data row and the last.
struct Rows {
  std::vector<double> t, q, energy;
  std::size_t total = 0;
};

std::size_t count_rows(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw OptionError("animation: cannot read '" + path + "'");
  std::size_t lines = 0;
  std::vector<char> buf(1 << 16);
  while (in.read(buf.data(), static_cast<std::streamsize>(buf.size())) || in.gcount() > 0) {
    lines += static_cast<std::size_t>(std::count(buf.data(), buf.data() + in.gcount(), '\n'));
    if (!in) break;
  }
  return lines > 0 ? lines - 1 : 0;  // less the header
}

Rows read_rows(const std::string& path, std::size_t n, std::size_t stride, std::size_t total) {
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) throw OptionError("animation: '" + path + "' is empty");
  std::vector<std::string> header = split(line);
  for (std::string& h : header) h = std::string(lagrangian::detail::csv_field_name(h));  // "energy [J]" is energy
  const auto energy_at = std::find(header.begin(), header.end(), "energy");
  if (header.size() < n + 1 || energy_at == header.end())
    throw OptionError("animation: '" + path + "' has no column 'energy' after " + std::to_string(n) + " coordinates");
  const std::size_t e_col = static_cast<std::size_t>(energy_at - header.begin());
  Rows rows;
  rows.total = total;
  std::size_t k = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const bool keep = k % stride == 0 || k + 1 == total;
    ++k;
    if (!keep) continue;
    const char* p = line.c_str();
    char* end = nullptr;
    std::size_t col = 0;
    double energy = std::nan("");
    std::vector<double> values;
    values.reserve(n + 1);
    while (*p && col <= std::max(n, e_col)) {
      errno = 0;
      const double v = std::strtod(p, &end);
      if (end == p)
        throw OptionError("animation: '" + path + "' row " + std::to_string(k) + " column " + std::to_string(col + 1) +
                          " is not a number");
      if (col <= n) values.push_back(v);
      if (col == e_col) energy = v;
      p = *end == ',' ? end + 1 : end;
      ++col;
      if (*end != ',') break;
    }
    if (values.size() != n + 1) throw OptionError("animation: '" + path + "' row " + std::to_string(k) + " is short");
    rows.t.push_back(values[0]);
    rows.q.insert(rows.q.end(), values.begin() + 1, values.end());
    rows.energy.push_back(energy);
  }
  return rows;
}

view::Figure particle_figure(const Scene& scene) {
  view::Figure f;
  auto index = [&](const std::string& name) {
    for (std::size_t i = 0; i < scene.bodies.size(); ++i)
      if (scene.bodies[i].name == name) return static_cast<int>(i);
    return -1;
  };
  for (const Body& b : scene.bodies) f.bodies.push_back({b.name, b.radius, -1});
  for (const Link& l : scene.links) {
    view::Figure::Segment s{index(l.a), l.b.empty() ? -1 : index(l.b), point(l.anchor)};
    f.rods.push_back(s);
    if (s.b < 0) f.pivots.push_back(s.anchor);
  }
  for (const Spring& sp : scene.springs) {
    view::Figure::Segment s{index(sp.a), sp.b.empty() ? -1 : index(sp.b), point(sp.anchor)};
    f.springs.push_back(s);
    if (s.b < 0) f.pivots.push_back(s.anchor);
  }
  for (const PlaneContact& p : scene.planes) f.planes.push_back({p.name, point(p.point), point(p.normal)});
  if (scene.box) f.boxes.push_back({point(scene.box->min), point(scene.box->max)});
  for (const Surface& s : scene.surfaces)
    if (s.kind == Surface::Kind::sphere)
      f.spheres.push_back({point(s.point), s.radius});
    else
      f.planes.push_back({s.name, point(s.point), point(s.normal)});
  if (scene.gravity && scene.gravity->g.norm() > 0) f.up = point(-scene.gravity->g.normalized());
  return f;
}

}  // namespace

SceneView scene_view(const Scene& scene, const RunResult& result) {
  const std::string traj = (std::filesystem::path(scene.output.directory) / "trajectory.csv").string();
  const std::size_t n = result.report.coordinates.size();
  const ModelEntry* entry = scene.model ? entry_for(*scene.model) : nullptr;
  view::Figure figure;
  if (entry) {
    std::vector<double> none;
    figure = entry->picture(*scene.model, nullptr, nullptr, 0, none);
  } else {
    figure = particle_figure(scene);
  }
  SceneView out;
  view::Options& options = out.options;
  options.title = scene.name;
  options.description = scene.description;
  const std::size_t total = count_rows(traj);
  const std::size_t stride = view::sample_stride(total, figure.bodies.size(), options);
  Rows rows = read_rows(traj, n, stride, total);

  view::Track& track = out.track;
  track.t = rows.t;
  track.samples_total = rows.total;
  if (entry) {
    figure = entry->picture(*scene.model, rows.t.data(), rows.q.data(), rows.t.size(), track.positions);
  } else {
    track.positions = rows.q;  // x, y, z of each body in turn
  }
  track.energy = {result.engine == "event_driven" ? "kinetic energy T" : "energy E = T + V", "J", rows.energy};
  track.energy_scale = result.report.energy_scale;
  // Coordinates: a model's, or the bodies' x, y, z for a few bodies.
  const std::optional<ModelInfo> info = entry ? model_info(*scene.model) : std::nullopt;
  if (entry || scene.bodies.size() <= 4) {
    for (std::size_t c = 0; c < n; ++c) {
      view::Series s{result.report.coordinates[c], info && c < info->units.size() ? info->units[c] : "m", {}};
      s.values.reserve(rows.t.size());
      for (std::size_t r = 0; r < rows.t.size(); ++r) s.values.push_back(rows.q[r * n + c]);
      track.coordinates.push_back(std::move(s));
    }
  } else {
    track.coordinates_note =
        std::to_string(scene.bodies.size()) + " bodies: coordinates not plotted (trajectory.csv has them)";
  }
  // Events: the bodies a contact names are flashed ("ball-floor", "m1-m2";
  // detail::names_body, as the plots mark them).
  constexpr std::size_t max_events = 5000;
  const auto& events = result.report.events;
  const std::size_t every = events.size() > max_events ? (events.size() + max_events - 1) / max_events : 1;
  for (std::size_t k = 0; k < events.size(); k += every) {
    const EventRecord& e = events[k];
    view::Event ev{e.t, to_string(e.kind), e.name, {}};
    for (std::size_t b = 0; b < figure.bodies.size(); ++b)
      if (lagrangian::detail::names_body(e.name, figure.bodies[b].name)) ev.bodies.push_back(static_cast<int>(b));
    track.events.push_back(std::move(ev));
  }
  if (every > 1)
    track.coordinates_note += std::string(track.coordinates_note.empty() ? "" : "; ") + "events: one in " +
                              std::to_string(every) + " of " + std::to_string(events.size()) + " marked";
  out.figure = std::move(figure);
  return out;
}

}  // namespace lagrangian::scene::detail
