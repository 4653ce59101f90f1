// Equilibria, normal modes and stationary-action boundary-value problems of a
// scene's built-in model, Lyapunov exponents and Floquet multipliers of its
// model or its bodies (scene/analysis.hpp): dispatch through the registry
// (particle scenes: particle_tangent.cpp), the path written as CSV through a
// partial file, and its plots.

#include "lagrangian/scene/analysis.hpp"

#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "json_object.hpp"
#include "particle_engine.hpp"
#include "lagrangian/detail/csv_header.hpp"
#include "lagrangian/integrate/method.hpp"
#include "lagrangian/scene/detail/registry.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/scene/plots.hpp"
#include "lagrangian/scene/models.hpp"
#include "text_model_spec.hpp"

namespace lagrangian::scene {
namespace {

namespace fs = std::filesystem;

/// The registry entry of a built-in-model scene; OptionError naming `option` for particle scenes.
const detail::ModelEntry& model_entry(const Scene& input, const std::string& option) {
  input.validate();
  if (!input.model)
    throw OptionError(option + ": works on scenes of a built-in model ([model]); '" + input.name +
                      "' is a particle scene (bodies), which has no generalized-coordinate model to analyse");
  const detail::ModelEntry* entry = detail::entry_for(*input.model);
  if (!entry) throw SceneError("model.name", "unknown model '" + input.model->name + "'", input.source);
  return *entry;
}

/// The model's name in the results: a built-in model's, or its registry
/// entry's ("text") for one stated as text, which the summaries call "the
/// model stated as text".
std::string model_name(const Scene& scene, const detail::ModelEntry& entry) {
  return scene.model->text ? entry.name : scene.model->name;
}
std::string model_phrase(const std::string& name) {
  if (name == "text") return "the model stated as text";
  if (name == "particles") return "the bodies of the particle scene";
  if (name == "gas") return "the spheres of the gas";
  return name;
}

/// f() with a scene error that names a key but no line (the registry's:
/// parameters, initial state) placed at the key's line in the scene file.
template <class F>
auto with_scene_lines(const Scene& scene, F&& f) {
  try {
    return f();
  } catch (const SceneError& e) {
    if (!e.key().empty() && e.line() == 0 && !scene.source.file.empty())
      throw SceneError(e.key(), e.message(), scene.source);
    throw;
  }
}

std::string g17(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string g10(double v) {
  if (v == 0.0) v = 0.0;
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

/// How the analysis integrated: the method and rtol, or the gas's exact
/// event-driven flights.
std::string method_phrase(const std::string& model, const SimulationOptions& run) {
  if (model == "gas") return "event-driven engine, exact flights";
  return std::string(to_string(run.method)) + ", rtol " + g10(run.rtol);
}

/// "cost: …": steps and evaluations (`what` they evaluate), or the gas
/// engine's events.
std::string cost_line(const std::string& model, std::uint64_t steps, std::uint64_t evaluations, const char* what,
                      double seconds) {
  if (model == "gas")
    return "cost: " + std::to_string(steps) + " events of the event-driven engine (impacts and cell crossings), " +
           g10(seconds) + " s\n";
  return "cost: " + std::to_string(steps) + " steps, " + std::to_string(evaluations) + " " + what + ", " +
         g10(seconds) + " s\n";
}

/// Writes the path as `<dir>/bvp_path.csv` through `bvp_path.csv.partial`.
std::string write_path_csv(const std::string& dir, const BvpRun& run) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw OptionError("--out: cannot create directory '" + dir + "': " + ec.message());
  const fs::path path = fs::path(dir) / "bvp_path.csv";
  const fs::path partial = fs::path(dir) / "bvp_path.csv.partial";
  fs::remove(path, ec);
  {
    std::ofstream out(partial);
    if (!out) throw OptionError("--out: cannot write '" + partial.string() + "'");
    using lagrangian::detail::csv_field;
    const auto unit = [&](std::size_t i) { return i < run.units.size() ? run.units[i] : std::string(); };
    out << csv_field("t", "s");
    for (std::size_t i = 0; i < run.coordinates.size(); ++i) out << "," << csv_field(run.coordinates[i], unit(i));
    for (std::size_t i = 0; i < run.coordinates.size(); ++i)
      out << "," << csv_field(run.coordinates[i] + "_dot", lagrangian::detail::csv_rate_unit(unit(i)));
    out << "," << csv_field("energy", "J") << "\n";
    const BvpResult& r = run.result;
    for (std::size_t k = 0; k < r.t.size(); ++k) {
      const int row = static_cast<int>(k);
      out << g17(r.t[k]);
      for (int i = 0; i < r.q.cols(); ++i) out << "," << g17(r.q(row, i));
      for (int i = 0; i < r.qd.cols(); ++i) out << "," << g17(r.qd(row, i));
      out << "," << g17(r.energy[k]) << "\n";
    }
    out.flush();
    if (!out) {
      out.close();
      fs::remove(partial, ec);
      throw OptionError("--out: writing '" + partial.string() + "' failed");
    }
  }
  fs::rename(partial, path, ec);
  if (ec) {
    fs::remove(partial, ec);
    throw OptionError("--out: cannot rename '" + partial.string() + "' to '" + path.string() + "'");
  }
  return path.string();
}

}  // namespace

std::string analyse(const Scene& scene, const AnalysisRequest& request) {
  if (request.starts < 1) throw OptionError("--starts: must be at least 1, got " + std::to_string(request.starts));
  if (request.starts > 10000) throw OptionError("--starts: at most 10000, got " + std::to_string(request.starts));
  const detail::ModelEntry& entry = model_entry(scene, request.equilibria ? "--equilibria" : "--modes");
  return with_scene_lines(scene, [&] { return entry.analyse(*scene.model, scene.run.t0, request); });
}

BvpRun solve_bvp(const Scene& scene, const BvpRequest& request) {
  const detail::ModelEntry& entry = model_entry(scene, "solve-bvp");
  for (std::size_t i = 0; i < request.from.size(); ++i)
    if (!std::isfinite(request.from[i]))
      throw OptionError("--from: value " + std::to_string(i) + " is " + g10(request.from[i]) + "; it must be finite");
  for (std::size_t i = 0; i < request.to.size(); ++i)
    if (!std::isfinite(request.to[i]))
      throw OptionError("--to: value " + std::to_string(i) + " is " + g10(request.to[i]) + "; it must be finite");
  if (!std::isfinite(request.t0) || !std::isfinite(request.t1) || !(request.t1 > request.t0))
    throw OptionError("--time: need finite t0 < t1, got t0 = " + g10(request.t0) + " s, t1 = " + g10(request.t1) +
                      " s");
  if (request.steps < 2 || request.steps > 100000)
    throw OptionError("--steps: must be in 2 .. 100000, got " + std::to_string(request.steps));
  DiscreteRule rule;
  try {
    rule = discrete_rule_from_string(request.rule);
  } catch (const std::invalid_argument& e) {
    throw OptionError(std::string("--rule: ") + e.what());
  }
  BvpRun run;
  const std::optional<ModelInfo> info = detail::model_info(*scene.model);
  if (info) {
    run.coordinates = info->coordinates;
    run.units = info->units;
  }
  run.result = with_scene_lines(scene, [&] { return entry.bvp(*scene.model, request, rule); });
  if (!request.out_dir.empty()) {
    const std::string csv = write_path_csv(request.out_dir, run);
    run.files.push_back(csv);
    if (request.plots && (request.png || request.svg)) {
      PlotSpec p;
      p.title = scene.name + ": path of stationary action";
      p.trajectory_csv = csv;
      p.out_dir = request.out_dir;
      p.coordinates = run.coordinates;
      p.units = run.units;
      double scale = 0;
      for (double e : run.result.energy) scale = std::max(scale, std::abs(e));
      p.energy_scale = scale > 0 ? scale : 1.0;
      p.png = request.png;
      p.svg = request.svg;
      collect_plots([&] { return make_plots(p); }, run.files, run.plot_note);
    }
  }
  return run;
}

std::string BvpRun::summary() const {
  const BvpResult& r = result;
  const int K = static_cast<int>(r.t.size()) - 1;
  std::string out = "path of stationary discrete action, t = " + g10(r.t.front()) + " .. " + g10(r.t.back()) +
                    " s, " + std::to_string(K) + " steps (h = " + g10((r.t.back() - r.t.front()) / K) + " s)\n";
  out += "Newton iterations " + std::to_string(r.iterations) + ", residual of the discrete Euler-Lagrange equations " +
         g10(r.residual) + "\n";
  out += "action S = " + g10(r.action) + " J*s; ";
  if (r.negative_eigenvalues == 0) {
    out += "a local minimum of the action (Hessian positive definite";
  } else {
    out += "a saddle point of the action, not a minimum: the Hessian has " + std::to_string(r.negative_eigenvalues) +
           " negative eigenvalue" + (r.negative_eigenvalues == 1 ? "" : "s") +
           " (the time span passes a conjugate point; a minimiser would not find this path";
  }
  if (r.eigenvalues_computed) out += "; lowest eigenvalue " + g10(r.lowest_eigenvalue);
  out += ")\n";
  auto row = [&](const char* label, int k) {
    std::string s = std::string(label) + " qdot = [";
    for (int i = 0; i < r.qd.cols(); ++i) s += (i ? ", " : "") + g10(r.qd(k, i));
    s += "], p = [";
    for (int i = 0; i < r.p.cols(); ++i) s += (i ? ", " : "") + g10(r.p(k, i));
    return s + "]\n";
  };
  out += row("start:", 0);
  out += row("end:  ", K);
  double lo = r.energy.front(), hi = r.energy.front();
  for (double e : r.energy) {
    lo = std::min(lo, e);
    hi = std::max(hi, e);
  }
  out += "energy function h along the path: " + g10(r.energy.front()) + " J (spread " + g10(hi - lo) + " J)\n";
  return out;
}

namespace {
/// An analysis of the tangent flow (`what` names it in a refusal): of a
/// particle scene's bodies by `particles(scene)`, of its model by
/// `on_model(entry, spec)`; sets `model` to "particles" or the model's name.
template <class Particles, class OnModel>
auto tangent_analysis(const Scene& scene, const char* what, std::string& model, Particles&& particles,
                      OnModel&& on_model) {
  if (!scene.model) {
    scene.validate();
    model = scene.gas ? "gas" : "particles";
    return particles(scene);
  }
  const detail::ModelEntry& entry = model_entry(scene, what);
  model = model_name(scene, entry);
  return with_scene_lines(scene, [&] { return on_model(entry, *scene.model); });
}
}  // namespace

LyapunovRun lyapunov(const Scene& scene, const LyapunovRequest& request) {
  if (request.exponents < 0)
    throw OptionError("--exponents: must be at least 1 (or 0 for all), got " + std::to_string(request.exponents));
  if (!std::isfinite(request.interval) || request.interval < 0)
    throw OptionError("--interval: must be a finite time >= 0 s (0 lets the code choose), got " +
                      g10(request.interval));
  LyapunovRun out;
  out.run = scene.run;
  LyapunovOptions options;
  options.run = scene.run;
  options.exponents = request.exponents;
  options.interval = request.interval;
  out.result = tangent_analysis(
      scene, "lyapunov", out.model, [&](const Scene& s) { return detail::particle_lyapunov(s, options); },
      [&](const detail::ModelEntry& entry, const ModelSpec& spec) { return entry.lyapunov(spec, options); });
  return out;
}

std::string LyapunovRun::summary() const {
  const LyapunovResult& r = result;
  std::string out = "Lyapunov exponents of " + model_phrase(model) + " over t = " + g10(run.t0) + " .. " +
                    g10(run.t_end) + " s (" + method_phrase(model, run) + "), largest first, 1/s:\n";
  for (std::size_t i = 0; i < r.spectrum.size(); ++i)
    out += "  lambda_" + std::to_string(i + 1) + " = " + g10(r.spectrum[i]) + "\n";
  out += "sum " + g10(r.sum) + " 1/s (canonical coordinates: 0 for a Hamiltonian flow, to the integration error)\n";
  if (r.impacts > 0)
    out += "impacts crossed " + std::to_string(r.impacts) +
           " (each by its saltation matrix S: the sum includes sum ln|det S| / T, 2 ln e per bounce on a fixed "
           "plane)\n";
  if (r.rests > 0)
    out += "contacts at rest " + std::to_string(r.rests) + ", lifted off " + std::to_string(r.releases) +
           " (a contact held shut removes two directions, its gap and its rate: the exponents of the vectors it "
           "removed are -inf, and so is the sum)\n";
  out += "MEGNO <Y> = " + g10(r.megno_mean) + " (Y(t_end) = " + g10(r.megno) +
         "; -> 0 isochronous, -> 2 regular, grows as lambda_1 t / 2 when chaotic)\n";
  out += "renormalisations " + std::to_string(r.renormalisations) + ", intervals " + g10(r.interval_min) + " .. " +
         g10(r.interval_max) + " s\n";
  out += cost_line(model, r.steps, r.rhs_evaluations, "evaluations of q'' with its derivatives along the vectors",
                   r.seconds);
  return out;
}

std::string LyapunovRun::json() const {
  const LyapunovResult& r = result;
  detail::JsonObject o;
  o.string("model", model);
  o.raw("spectrum", detail::json_numbers(r.spectrum.data(), static_cast<int>(r.spectrum.size())));
  o.number("sum", r.sum);
  o.number("megno", r.megno_mean);
  o.number("megno_final", r.megno);
  o.number("t0", run.t0);
  o.number("t_end", r.t_final);
  o.string("method", std::string(to_string(run.method)));
  o.number("rtol", run.rtol);
  o.number("atol", run.atol);
  o.integer("renormalisations", r.renormalisations);
  o.integer("impacts", r.impacts);
  o.integer("rests", r.rests);
  o.integer("releases", r.releases);
  o.number("interval_min", r.interval_min);
  o.number("interval_max", r.interval_max);
  o.integer("steps", static_cast<long long>(r.steps));
  o.integer("evaluations", static_cast<long long>(r.rhs_evaluations));
  o.number("seconds", r.seconds);
  return o.str() + "\n";
}

FloquetRun floquet(const Scene& scene, const FloquetRequest& request) {
  if (!std::isfinite(request.period) || !(request.period > 0))
    throw OptionError("--period: must be a finite time > 0 s, got " + g10(request.period));
  if (!std::isfinite(request.tolerance) || request.tolerance < 0)
    throw OptionError("--tolerance: must be finite and >= 0, got " + g10(request.tolerance));
  FloquetRun out;
  out.run = scene.run;
  out.tolerance = request.tolerance;
  out.find_orbit = request.find_orbit;
  FloquetOptions options;
  options.run = scene.run;
  options.period = request.period;
  options.tolerance = request.tolerance;
  options.find_orbit = request.find_orbit;
  options.fixed_period = request.fixed_period;
  options.keep_energy = request.keep_energy;
  out.result = tangent_analysis(
      scene, "floquet", out.model, [&](const Scene& s) { return detail::particle_floquet(s, options); },
      [&](const detail::ModelEntry& entry, const ModelSpec& spec) { return entry.floquet(spec, options); });
  out.period = out.result.period;
  return out;
}

std::string FloquetRun::summary() const {
  const FloquetResult& r = result;
  std::string out;
  if (find_orbit) {
    out = "periodic orbit of " + model_phrase(model) + " found in " + std::to_string(r.iterations) +
          " Newton iterations: T = " +
          g10(period) + " s, at t0 = " + g10(run.t0) + " s q = [";
    for (std::size_t i = 0; i < r.q.size(); ++i) out += (i ? ", " : "") + g10(r.q[i]);
    out += "], qd = [";
    for (std::size_t i = 0; i < r.qd.size(); ++i) out += (i ? ", " : "") + g10(r.qd[i]);
    out += "]\n";
  }
  out += "Floquet multipliers of " + model_phrase(model) + " over one period T = " + g10(period) +
         " s from t0 = " + g10(run.t0) +
         " s (" + std::string(to_string(run.method)) + ", rtol " + g10(run.rtol) + "), largest modulus first:\n";
  for (std::size_t i = 0; i < r.multipliers.size(); ++i)
    out += "  mu_" + std::to_string(i + 1) + " = " + g10(r.multipliers[i].real()) +
           (r.multipliers[i].imag() < 0 ? " - " : " + ") + g10(std::abs(r.multipliers[i].imag())) + " i   |mu| = " +
           g10(std::abs(r.multipliers[i])) + "\n";
  out += std::string(r.stable ? "stable" : "unstable") + ": largest |mu| = " + g10(r.largest_modulus) +
         (r.stable ? " <= " : " > ") + "1 + " + g10(tolerance) + "\n";
  out += "closure max|x(t0 + T) - x(t0)| = " + g10(r.closure) +
         (r.closure > 1e-6 ? " (the motion from this state is not periodic with this T: the multipliers are those of "
                             "the one-period map, not a periodic motion's)"
                           : "") +
         "\n";
  if (r.impacts > 0) out += "impacts crossed over the period " + std::to_string(r.impacts) + " (each by its saltation matrix)\n";
  out += "cost: " + std::to_string(r.steps) + " steps, " + std::to_string(r.rhs_evaluations) +
         " evaluations of q'' with its Jacobian, " + g10(r.seconds) + " s\n";
  return out;
}

std::string FloquetRun::json() const {
  const FloquetResult& r = result;
  std::vector<std::string> pairs;
  for (const std::complex<double>& mu : r.multipliers) {
    const double reim[2] = {mu.real(), mu.imag()};
    pairs.push_back(detail::json_numbers(reim, 2));
  }
  detail::JsonObject o;
  o.string("model", model);
  o.raw("multipliers", detail::json_array(pairs));
  o.boolean("stable", r.stable);
  o.number("largest_modulus", r.largest_modulus);
  o.number("tolerance", tolerance);
  o.number("closure", r.closure);
  o.number("period", period);
  o.number("t0", run.t0);
  if (find_orbit) {
    o.raw("q", detail::json_numbers(r.q.data(), static_cast<int>(r.q.size())));
    o.raw("qd", detail::json_numbers(r.qd.data(), static_cast<int>(r.qd.size())));
    o.integer("iterations", r.iterations);
  }
  o.string("method", std::string(to_string(run.method)));
  o.number("rtol", run.rtol);
  o.number("atol", run.atol);
  o.integer("impacts", r.impacts);
  o.integer("steps", static_cast<long long>(r.steps));
  o.integer("evaluations", static_cast<long long>(r.rhs_evaluations));
  o.number("seconds", r.seconds);
  return o.str() + "\n";
}

SensitivityRun sensitivity(const Scene& scene, const SensitivityRequest& request) {
  SensitivityRun out;
  out.run = scene.run;
  SensitivityOptions options;
  options.run = scene.run;
  options.run.output_interval = 0;  // t0 and t_end only
  options.initial_state = request.initial_state;
  options.parameters = request.parameters;
  out.result = tangent_analysis(
      scene, "sensitivity", out.model, [&](const Scene& s) { return detail::particle_sensitivities(s, options); },
      [&](const detail::ModelEntry& entry, const ModelSpec& spec) { return entry.sensitivity(spec, options); });
  return out;
}

namespace {
/// [a, b, …] of the values of `v` in g10 format.
template <class V>
std::string bracketed(const V& v) {
  std::string s = "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) s += (i ? ", " : "") + g10(v[i]);
  return s + "]";
}
}  // namespace

std::string SensitivityRun::summary() const {
  const SensitivityResult& r = result;
  const Eigen::MatrixXd& s = r.sensitivities.back();
  const std::string start = "its state at t0 = " + g10(r.times.front()) + " s";
  const std::string of = r.state_columns == 0  ? "its parameters (from t0 = " + g10(r.times.front()) + " s)"
                         : r.parameters.empty() ? start
                                                : start + " and to its parameters";
  std::string out = "sensitivities of " + model_phrase(model) + " at t = " + g10(r.times.back()) + " s to " + of +
                    " (" + method_phrase(model, run) + "); x = (q, qdot):\n";
  out += "x(t) = " + bracketed(r.states.back()) + "\n";
  if (r.state_columns > 0) {
    out += "d x(t) / d x(t0), row i: x_i(t), column j: x_j(t0):\n";
    for (Eigen::Index i = 0; i < s.rows(); ++i) out += "  " + bracketed(s.row(i).head(r.state_columns)) + "\n";
  }
  for (std::size_t k = 0; k < r.parameters.size(); ++k)
    out += "d x(t) / d " + r.parameters[k] + " = " + bracketed(s.col(r.state_columns + static_cast<Eigen::Index>(k))) +
           "\n";
  if (r.impacts > 0) out += "impacts crossed " + std::to_string(r.impacts) + " (each by its saltation matrix)\n";
  out += cost_line(model, r.steps, r.rhs_evaluations, "evaluations of the state and its columns", r.seconds);
  return out;
}

std::string SensitivityRun::json() const {
  const SensitivityResult& r = result;
  const Eigen::MatrixXd& s = r.sensitivities.back();
  detail::JsonObject o;
  o.string("model", model);
  o.number("t0", r.times.front());
  o.number("t_end", r.times.back());
  o.raw("state", detail::json_numbers(r.states.back().data(), static_cast<int>(r.states.back().size())));
  if (r.state_columns > 0) {
    std::vector<std::string> rows;
    for (Eigen::Index i = 0; i < s.rows(); ++i) {
      const Eigen::RowVectorXd row = s.row(i).head(r.state_columns);
      rows.push_back(detail::json_numbers(row.data(), r.state_columns));
    }
    o.raw("state_transition", detail::json_array(rows));
  }
  detail::JsonObject p;
  for (std::size_t k = 0; k < r.parameters.size(); ++k) {
    const Eigen::VectorXd col = s.col(r.state_columns + static_cast<Eigen::Index>(k));
    p.raw(r.parameters[k], detail::json_numbers(col.data(), static_cast<int>(col.size())));
  }
  o.raw("parameters", p.str());
  o.integer("impacts", r.impacts);
  o.string("method", std::string(to_string(run.method)));
  o.number("rtol", run.rtol);
  o.number("atol", run.atol);
  o.integer("steps", static_cast<long long>(r.steps));
  o.integer("evaluations", static_cast<long long>(r.rhs_evaluations));
  o.number("seconds", r.seconds);
  return o.str() + "\n";
}

}  // namespace lagrangian::scene
