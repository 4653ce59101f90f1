// Running and inspecting scenes: chooses the engine once (built-in model,
// ODE particle engine or the exact event-driven hard-sphere engine), writes
// the outputs through partial files and makes the plots.

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <sstream>

#include "lagrangian/scene/detail/registry.hpp"
#include "lagrangian/detail/text_output.hpp"
#include "lagrangian/scene/hard_spheres.hpp"
#include "lagrangian/integrate/observers.hpp"
#include "lagrangian/params.hpp"
#include "lagrangian/scene/plots.hpp"
#include "lagrangian/scene/progress.hpp"
#include "lagrangian/scene/models.hpp"
#include "lagrangian/scene/run.hpp"
#include "animation_scene.hpp"
#include "gas_check.hpp"
#include "output_manifest.hpp"
#include "particle_engine.hpp"
#include "text_model_spec.hpp"

namespace lagrangian::scene {
namespace {

namespace fs = std::filesystem;

/// Creates the output directory and proves it can be written.
void prepare_directory(const Scene& scene) {
  const std::string& dir = scene.output.directory;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw SceneError("output.directory", "cannot create directory '" + dir + "': " + ec.message(), scene.source);
  const fs::path probe = fs::path(dir) / ".lagrangian-write-test";
  std::FILE* f = std::fopen(probe.c_str(), "w");
  if (!f)
    throw SceneError("output.directory", "directory '" + dir + "' is not writable: " + std::strerror(errno),
                     scene.source);
  std::fclose(f);
  fs::remove(probe, ec);
}

/// Removes what an earlier or a failed run may have left (output_manifest.hpp).
void remove_outputs(const std::string& dir) {
  detail::remove_listed_outputs(dir, {"trajectory.csv", "events.csv", "report.json", "animation.html"});
}

/// report.json: the scene, the engine, the effect counts and the run report.
void write_report(const Scene& scene, const RunResult& r, const std::string& path) {
  std::ostringstream os;
  os << "{\n  \"scene\": ";
  lagrangian::detail::json_string(os, scene.name);
  os << ",\n  \"engine\": ";
  lagrangian::detail::json_string(os, r.engine);
  os << ",\n  \"declared\": [";
  const auto declared = scene.declared();
  for (std::size_t k = 0; k < declared.size(); ++k) {
    if (k) os << ", ";
    lagrangian::detail::json_string(os, declared[k]);
  }
  os << "],\n  \"effect_evaluations\": {";
  std::size_t k = 0;
  for (const auto& [name, count] : r.effect_evaluations) {
    if (k++) os << ", ";
    lagrangian::detail::json_string(os, name);
    os << ": " << count;
  }
  os << "}";
  if (r.gas) {
    const GasCheck& g = *r.gas;
    os << ",\n  \"gas\": {\"molecules\": " << g.molecules;
    const std::pair<const char*, double> f[] = {
        {"mass", g.mass}, {"radius", g.radius}, {"volume", g.volume}, {"duration", g.duration},
        {"mean_square_speed", g.mean_square_speed}, {"kT", g.kT}, {"temperature", g.temperature},
        {"pressure", g.pressure}, {"pressure_error", g.pressure_error}, {"pressure_ideal", g.pressure_ideal},
        {"pressure_expected", g.pressure_expected}, {"ks_distance", g.ks_distance}, {"ks_critical", g.ks_critical}};
    for (const auto& [name, value] : f) os << ", \"" << name << "\": " << lagrangian::detail::format_number(value);
    os << "}";
  }
  os << ",\n  \"report\": " << r.report.to_json() << "\n}\n";
  lagrangian::detail::write_text_file(path, os.str(), "report file");
}

std::string engine_of(const Scene& scene) {
  if (scene.model) return "model";
  if (scene.run.engine == "event_driven") return "event_driven";
  if (scene.run.engine == "ode") return "ode";
  return detail::event_driven_eligible(scene) ? "event_driven" : "ode";
}

RunReport run_event_driven(const Scene& scene, CsvSink* csv, const detail::SampleTick& tick, std::vector<double>& q_final,
                           std::vector<double>& qd_final) {
  const HardSphereSystem sys = detail::hard_sphere_system(scene);
  const HardSphereOptions opt = detail::hard_sphere_options(scene, scene.run);
  const int n = static_cast<int>(sys.spheres.size());
  Sample<Dynamic> s;
  s.q.resize(3 * n);
  s.qd.resize(3 * n);
  auto sampler = [&](double t, const std::vector<HardSphere>& spheres) {
    q_final.resize(static_cast<std::size_t>(3 * n));
    qd_final.resize(static_cast<std::size_t>(3 * n));
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) {
        q_final[static_cast<std::size_t>(3 * i + k)] = spheres[static_cast<std::size_t>(i)].position[k];
        qd_final[static_cast<std::size_t>(3 * i + k)] = spheres[static_cast<std::size_t>(i)].velocity[k];
      }
    if (!csv && !tick) return;
    double T = 0;
    for (int i = 0; i < n; ++i) {
      const HardSphere& h = spheres[static_cast<std::size_t>(i)];
      s.q.segment<3>(3 * i) = h.position;
      s.qd.segment<3>(3 * i) = h.velocity;
      T += 0.5 * h.mass * h.velocity.squaredNorm();
    }
    s.t = t;
    s.energy = T;
    s.total_energy = T;
    if (csv) (*csv)(s);
    if (tick) tick(SampleRow{t, {q_final.data(), q_final.size()}, {qd_final.data(), qd_final.size()}, T, T});
  };
  return run_hard_spheres(sys, opt, sampler);
}

PlotSpec plot_spec(const Scene& scene, const RunResult& r) {
  PlotSpec p;
  p.title = scene.name;
  p.out_dir = scene.output.directory;
  p.trajectory_csv = (fs::path(p.out_dir) / "trajectory.csv").string();
  p.events_csv = (fs::path(p.out_dir) / "events.csv").string();
  p.coordinates = r.report.coordinates;
  p.energy_scale = r.report.energy_scale;
  p.png = scene.output.png;
  p.svg = scene.output.svg;
  if (scene.model) {
    const std::optional<ModelInfo> info = detail::model_info(*scene.model);
    if (info) p.units = info->units;
  }
  if (p.units.size() != p.coordinates.size()) {
    p.units.assign(p.coordinates.size(), "m");
  }
  auto plane = [](const std::string& name, const Vec3& point, const Vec3& normal) {
    PlotSpec::Plane pl;
    pl.name = name;
    for (int a = 0; a < 3; ++a) pl.point[a] = point[a], pl.normal[a] = normal[a];
    return pl;
  };
  if (!scene.model) {
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
      const int c = static_cast<int>(3 * i);
      p.bodies.push_back({scene.bodies[i].name, c, c + 1, c + 2});
    }
    for (const PlaneContact& pc : scene.planes) p.planes.push_back(plane(pc.name, pc.point, pc.normal));
    for (const Surface& sf : scene.surfaces)
      if (sf.kind == Surface::Kind::plane) p.planes.push_back(plane(sf.name, sf.point, sf.normal));
    if (scene.box)
      for (int a = 0; a < 3; ++a) {
        const Vec3 n = Vec3::Unit(a);
        p.planes.push_back(plane("", scene.box->min, n));
        p.planes.push_back(plane("", scene.box->max, -n));
      }
  } else if (const detail::ModelEntry* entry = detail::entry_for(*scene.model)) {
    // A model of particles: every body's path in space, with its planes (an incline, a floor).
    const std::vector<std::array<int, 3>> axes = entry->particle_axes(*scene.model);
    std::vector<double> none;
    const view::Figure figure = entry->picture(*scene.model, nullptr, nullptr, 0, none);
    for (std::size_t i = 0; i < axes.size(); ++i)
      p.bodies.push_back({i < figure.bodies.size() ? figure.bodies[i].name : "particle " + std::to_string(i + 1),
                          axes[i][0], axes[i][1], axes[i][2]});
    for (const auto& pl : figure.planes)
      p.planes.push_back(plane(pl.name, Vec3(pl.point[0], pl.point[1], pl.point[2]),
                               Vec3(pl.normal[0], pl.normal[1], pl.normal[2])));
  }
  return p;
}

/// A model whose picture has no bodies (a text model without points, a C++
/// model without particles; every built-in model draws some): nothing in
/// space for the animation page.
bool nothing_to_draw(const Scene& scene) {
  const detail::ModelEntry* entry = scene.model ? detail::entry_for(*scene.model) : nullptr;
  if (!entry) return false;
  std::vector<double> none;
  return entry->picture(*scene.model, nullptr, nullptr, 0, none).bodies.empty();
}

/// A built-in, text or user model's run through its registry entry, the
/// trajectory into `csv_path` ("" for none).
void run_model(const Scene& scene, const std::string& csv_path, const detail::SampleTick& tick, RunResult& result) {
  const detail::ModelEntry* entry = detail::entry_for(*scene.model);
  if (!entry) throw SceneError("model.name", "unknown model '" + scene.model->name + "'", scene.source);
  try {
    detail::FinalState last;
    result.report =
        entry->run(*scene.model, scene.run, csv_path, tick, &last);
    result.q_final = std::move(last.q);
    result.qd_final = std::move(last.qd);
  } catch (const SceneError& e) {
    if (!e.key().empty() && e.line() == 0 && !scene.source.file.empty())
      throw SceneError(e.key(), e.message(), scene.source);  // point at the scene file's line
    throw;
  }
}

/// A scene of bodies on the event-driven engine (hard spheres) or the ODE
/// engine (particles with effects, constraints and contacts), the
/// trajectory into `csv_path` ("" for none).
void run_bodies(const Scene& scene, const std::string& csv_path, const detail::SampleTick& tick, RunResult& result) {
  std::optional<CsvSink> csv;
  Columns columns;
  columns.coordinates = detail::body_coordinates(scene);
  columns.units.assign(columns.coordinates.size(), "m");
  columns.total_energy = false;
  if (!csv_path.empty()) csv.emplace(csv_path);
  if (result.engine == "event_driven") {
    if (csv) csv->begin(columns);
    result.report = run_event_driven(scene, csv ? &*csv : nullptr, tick, result.q_final, result.qd_final);
  } else {
    Sample<Dynamic> s;
    const int dim = 3 * static_cast<int>(scene.bodies.size());
    s.q.resize(dim);
    s.qd.resize(dim);
    detail::ParticleOutput output;
    // The header names the constraint rows (lambda_<row>, then Qc_<coordinate>).
    output.begin = [&](const std::vector<std::string>& rows, const std::vector<std::string>& units) {
      if (!csv) return;
      columns.constraints = rows;
      columns.constraint_units = units;
      csv->begin(columns);
    };
    output.sample = [&](double t, const double* q, const double* qd, int n, double energy,
                        const Eigen::VectorXd& multipliers, const Eigen::VectorXd& forces) {
      if (!csv) return;
      s.t = t;
      s.q = Eigen::Map<const Eigen::VectorXd>(q, n);
      s.qd = Eigen::Map<const Eigen::VectorXd>(qd, n);
      s.energy = energy;
      s.multipliers = multipliers;
      s.constraint_forces = forces;
      (*csv)(s);
    };
    auto run = detail::run_particles(scene, output, tick);
    result.report = std::move(run.report);
    result.effect_evaluations = std::move(run.effect_evaluations);
    result.contact_locations = run.contact_locations;
    result.q_final = std::move(run.q_final);
    result.qd_final = std::move(run.qd_final);
  }
  if (csv) csv->finish();
  // Spheres in a box that cannot collide with each other are rarely what
  // was meant, and cost the ODE engine's time: say so.
  const auto spheres = std::count_if(scene.bodies.begin(), scene.bodies.end(), [](const Body& b) { return b.radius > 0; });
  if (result.engine == "ode" && scene.run.engine == "auto" && scene.box && !scene.sphere_contacts && spheres >= 2)
    result.report.warnings.push_back(
        "the spheres have radii but the scene declares no [contacts.spheres]: they pass through each other, "
        "and the scene ran on the ODE engine; declare [contacts.spheres] for collisions between them (and the "
        "exact event-driven engine, far faster for spheres in a box)");
}

/// The plots of a run that wrote its trajectory (and the speed distribution of a gas).
void write_plots(const Scene& scene, RunResult& result) {
  const std::string& dir = scene.output.directory;
  collect_plots([&] { return make_plots(plot_spec(scene, result)); }, result.files, result.plot_note);
  if (result.gas && result.plot_note.empty()) {
    SpeedPlotSpec sp;
    sp.title = scene.name;
    sp.out_dir = dir;
    sp.speeds = result.gas->speeds;
    sp.mass = result.gas->mass;
    sp.kT = result.gas->kT;
    char note[200];
    std::snprintf(note, sizeof note,
                  "at t = %.6g s (T = %.4g K); Kolmogorov-Smirnov distance D = %.3g (5 %% point 1.36/sqrt(N) = %.3g)",
                  result.report.t_final, result.gas->temperature, result.gas->ks_distance, result.gas->ks_critical);
    sp.note = note;
    sp.png = scene.output.png;
    sp.svg = scene.output.svg;
    collect_plots([&] { return make_speed_plot(sp); }, result.files, result.plot_note);
  }
}

/// The animation page and the video of a run that writes its outputs, or
/// the note that says why not.
void write_pictures(const Scene& scene, const RunControls& controls, RunResult& result) {
  const std::string& dir = scene.output.directory;
  const bool video = !controls.video_path.empty();
  if ((scene.output.animation || video) && nothing_to_draw(scene)) {
    // Nothing to draw in space: the coordinates and energy are in the plots.
    result.animation_note = scene.model->text ? "animation: not written: the model places no points in space "
                                                "([[model.points]]); its coordinates and energy are in the plots"
                                              : "animation: not written: the model declares no particles() to "
                                                "draw; its coordinates and energy are in the plots";
  } else if (scene.output.trajectory && (scene.output.animation || video)) {
    std::optional<detail::SceneView> v;
    try {
      v = detail::scene_view(scene, result);
    } catch (const std::exception& e) {
      result.animation_note = std::string("animation failed: ") + e.what();
    }
    if (v && scene.output.animation) {
      const std::string page = (fs::path(dir) / "animation.html").string();
      try {
        result.files.push_back(view::write_animation(page, v->figure, v->track, v->options).path);
      } catch (const std::exception& e) {
        result.animation_note = std::string("animation failed: ") + e.what();
      }
    }
    if (v && video) {
      try {
        view::write_video(controls.video_path, v->figure, v->track, controls.video);
        result.video_written = true;
        result.files.push_back(controls.video_path);
      } catch (const std::exception& e) {
        result.animation_note += std::string(result.animation_note.empty() ? "" : "; ") + e.what();
      }
    }
  } else if (video) {
    result.animation_note = "video: not written: the scene writes no trajectory (output.trajectory = false)";
  }
}

}  // namespace

RunResult run(const Scene& input, const RunControls& controls) {
  input.validate();
  Scene scene = input;
  scene.expand_gas();
  RunResult result;
  result.engine = engine_of(scene);
  const std::string dir = scene.output.directory;
  const bool write = controls.write_outputs;
  std::error_code exists_ec;
  const bool created = write && !fs::exists(dir, exists_ec);  // removed again, while empty, if the run fails
  if (write) prepare_directory(scene);
  if (write && !controls.video_path.empty()) {  // an older video must not pass for this run's
    std::error_code ec;
    fs::remove(controls.video_path, ec);
  }
  const std::string traj = (fs::path(dir) / "trajectory.csv").string();
  const bool show_progress = controls.progress && Progress::stderr_is_terminal();
  Progress progress(scene.run.t0, scene.run.t_end, show_progress);
  // Without a progress bar or an on_sample the engines get no per-sample callback at all.
  detail::SampleTick tick;
  if (show_progress || controls.on_sample)
    tick = [&progress, show_progress, &on_sample = controls.on_sample](const SampleRow& row) {
      if (show_progress) progress.update(row.t);
      if (on_sample) on_sample(row);
    };
  try {
    if (write) remove_outputs(dir);
    const bool want_csv = write && scene.output.trajectory;
    if (result.engine == "model")
      run_model(scene, want_csv ? traj : std::string(), tick, result);
    else
      run_bodies(scene, want_csv ? traj : std::string(), tick, result);
    progress.finish();
    result.gas = detail::gas_check(scene, result);
    if (write) {
      if (scene.output.trajectory) result.files.push_back(traj);
      const std::string events = (fs::path(dir) / "events.csv").string();
      // Every contact a scene can have, a particle scene's or a built-in
      // model's, has a distance for its gap φ (m).
      result.report.write_events_csv(events, "m");
      result.files.push_back(events);
      const std::string json = (fs::path(dir) / "report.json").string();
      write_report(scene, result, json);
      result.files.push_back(json);
    }
  } catch (...) {
    progress.finish();
    if (write) remove_outputs(dir);
    std::error_code ec;
    if (created && fs::is_empty(dir, ec)) fs::remove(dir, ec);
    throw;
  }
  if (write && scene.output.trajectory && scene.output.plots && (scene.output.png || scene.output.svg))
    write_plots(scene, result);
  if (write) write_pictures(scene, controls, result);
  if (write) detail::write_output_manifest(dir, result.files);
  return result;
}

std::string inspect(const Scene& input, bool as_json) {
  input.validate();
  Scene scene = input;
  scene.expand_gas();
  if (scene.model) {
    const detail::ModelEntry* entry = detail::entry_for(*scene.model);
    if (!entry) throw SceneError("model.name", "unknown model '" + scene.model->name + "'", scene.source);
    try {
      return entry->inspect(*scene.model, scene.run.t0, as_json);
    } catch (const SceneError& e) {
      if (!e.key().empty() && e.line() == 0 && !scene.source.file.empty())
        throw SceneError(e.key(), e.message(), scene.source);
      throw;
    }
  }
  return detail::inspect_particles(scene, as_json);
}

}  // namespace lagrangian::scene
