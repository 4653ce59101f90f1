// The built-in models a scene can name: the catalog and the registry agree,
// a scene's default model is the C++ default model, a registry run is the same run
// as a direct simulate(), the physics comes out right through the registry
// (pendulum period, rebound height, range, Kepler period), bad input is a
// SceneError naming its key, and the inspection reports ranks, degrees of
// freedom and conserved momenta.

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <gtest/gtest.h>

#include "lagrangian/scene/detail/registry.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/models/projectile.hpp"
#include "lagrangian/models/two_body.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/models.hpp"
#include "lagrangian/integrate/simulate.hpp"

namespace {

namespace fs = std::filesystem;
using namespace lagrangian;
using lagrangian::scene::ModelSpec;
using lagrangian::scene::SampleRow;
using lagrangian::scene::SceneError;
using lagrangian::scene::detail::find_entry;
using lagrangian::scene::detail::ModelEntry;
namespace lm = lagrangian::models;

// -- helpers ------------------------------------------------------------------

const ModelEntry& entry(const std::string& name) {
  const ModelEntry* e = find_entry(name);
  if (!e) throw std::runtime_error("no registry entry " + name);
  return *e;
}

/// A fresh directory for one test's files.
struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& tag) {
    path = fs::temp_directory_path() / ("lagrangian_scene_models_" + tag + "_" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
};

/// A trajectory CSV: header names and rows of numbers.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  /// The column named `name`, its unit aside ("z" finds "z [m]"); -1 when none.
  int column(const std::string& name) const {
    const auto it = std::find_if(header.begin(), header.end(),
                                 [&](const std::string& h) { return h == name || h.starts_with(name + " ["); });
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  }
};

Csv read_csv(const std::string& path) {
  Csv csv;
  std::ifstream in(path);
  std::string line;
  if (!std::getline(in, line)) return csv;
  std::stringstream hs(line);
  for (std::string cell; std::getline(hs, cell, ',');) csv.header.push_back(cell);
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ls(line);
    for (std::string cell; std::getline(ls, cell, ',');) row.push_back(std::strtod(cell.c_str(), nullptr));
    csv.rows.push_back(std::move(row));
  }
  return csv;
}

SimulationOptions options(double t_end, double output_interval = 0.01) {
  SimulationOptions o;
  o.t_end = t_end;
  o.output_interval = output_interval;
  return o;
}

/// The first (or, with last, the last) line of `text` that starts with
/// `label` after its indentation, with runs of spaces collapsed to one; ""
/// when there is none.
std::string row(const std::string& text, const std::string& label, bool last = false) {
  std::stringstream ss(text);
  std::string found;
  for (std::string line; std::getline(ss, line);) {
    std::stringstream words(line);
    std::string collapsed;
    for (std::string w; words >> w;) collapsed += (collapsed.empty() ? "" : " ") + w;
    if (collapsed.rfind(label, 0) == 0) {
      found = collapsed;
      if (!last) break;
    }
  }
  return found;
}

/// Runs a registry entry and expects a SceneError; returns it.
template <class F>
SceneError expect_scene_error(F&& f) {
  try {
    f();
  } catch (const SceneError& e) {
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected a SceneError, got: " << e.what();
    throw;
  }
  ADD_FAILURE() << "expected a SceneError, nothing was thrown";
  throw std::runtime_error("no SceneError");
}

// -- catalog and registry -------------------------------------------------------

TEST(SceneModels, EveryCatalogEntryHasExactlyOneRegistryEntryAndViceVersa) {
  const auto& catalog = scene::builtin_models();
  const auto& entries = scene::detail::model_entries();
  ASSERT_EQ(catalog.size(), entries.size());
  std::set<std::string> names;
  for (const auto& info : catalog) {
    EXPECT_TRUE(names.insert(info.name).second) << "catalog lists " << info.name << " twice";
    EXPECT_EQ(std::count_if(entries.begin(), entries.end(), [&](const ModelEntry& e) { return e.name == info.name; }),
              1)
        << info.name;
    EXPECT_EQ(scene::find_model(info.name), &info);
    ASSERT_NE(find_entry(info.name), nullptr) << info.name;
    EXPECT_EQ(find_entry(info.name)->name, info.name);
    EXPECT_EQ(info.coordinates.size(), info.units.size()) << info.name;
    EXPECT_FALSE(info.description.empty()) << info.name;
    std::set<std::string> params;
    for (const auto& p : info.parameters) {
      EXPECT_TRUE(params.insert(p.name).second) << info.name << "." << p.name;
      EXPECT_FALSE(p.unit.empty()) << info.name << "." << p.name;
      EXPECT_FALSE(p.description.empty()) << info.name << "." << p.name;
    }
  }
  for (const auto& e : entries) EXPECT_NE(scene::find_model(e.name), nullptr) << e.name;
  EXPECT_TRUE(std::is_sorted(catalog.begin(), catalog.end(),
                             [](const auto& a, const auto& b) { return a.name < b.name; }));
  EXPECT_TRUE(std::is_sorted(entries.begin(), entries.end(),
                             [](const auto& a, const auto& b) { return a.name < b.name; }));
  EXPECT_EQ(scene::find_model("no_such_model"), nullptr);
  EXPECT_EQ(find_entry("no_such_model"), nullptr);
  EXPECT_EQ(catalog.size(), 25u);
}

/// The model a scene names without parameters is the model's C++ default:
/// the registry builds it from its description's defaults by parameter name,
/// the constructor takes its defaults from the same description by argument;
/// q̈, p, M and h agree at a state away from every singular configuration.
template <class M>
void expect_scene_default_is_cpp_default(const M& cpp_default) {
  const std::string name(M::description.name);
  SCOPED_TRACE(name);
  ModelSpec spec;
  spec.name = name;
  constexpr int n = coordinate_count_v<M>;
  std::vector<double> q(n), qd(n);
  for (int i = 0; i < n; ++i) {
    q[static_cast<std::size_t>(i)] = 0.7 + 0.13 * i;
    qd[static_cast<std::size_t>(i)] = 0.4 - 0.11 * i;
  }
  const auto scene = entry(name).eom(spec, q.data(), qd.data(), 0.3);
  const auto cpp = lagrangian::detail::eom_sample(cpp_default, q.data(), qd.data(), 0.3);
  EXPECT_EQ(scene.qdd, cpp.qdd);
  EXPECT_EQ(scene.p, cpp.p);
  EXPECT_EQ(scene.mass, cpp.mass);
  EXPECT_EQ(scene.h, cpp.h);
}

TEST(SceneModels, ASceneModelWithoutParametersIsTheModelsCppDefault) {
  expect_scene_default_is_cpp_default(lm::SimplePendulum{});
  expect_scene_default_is_cpp_default(lm::HarmonicOscillator{});
  expect_scene_default_is_cpp_default(lm::DoublePendulum{});
  expect_scene_default_is_cpp_default(lm::SphericalPendulum{});
  expect_scene_default_is_cpp_default(lm::ElasticPendulum{});
  expect_scene_default_is_cpp_default(lm::BeadOnRotatingHoop{});
  expect_scene_default_is_cpp_default(lm::KeplerPolar{});
  expect_scene_default_is_cpp_default(lm::CartPendulum{});
  expect_scene_default_is_cpp_default(lm::DrivenPendulum{});
  expect_scene_default_is_cpp_default(lm::BeadOnRotatingWire{});
  expect_scene_default_is_cpp_default(lm::ParticleOnSphere{});
  expect_scene_default_is_cpp_default(lm::AtwoodMachine{});
  expect_scene_default_is_cpp_default(lm::CartesianDoublePendulum{});
  expect_scene_default_is_cpp_default(lm::KnifeEdge{});
  expect_scene_default_is_cpp_default(lm::BallAndPlane{});
  expect_scene_default_is_cpp_default(lm::Projectile<lm::Drag::none>{});
  expect_scene_default_is_cpp_default(lm::Projectile<lm::Drag::linear>{});
  expect_scene_default_is_cpp_default(lm::Projectile<lm::Drag::quadratic>{});
  // The drag models' default coefficients are positive (with b = 0 the
  // linear-drag closed form divides 0 by 0): q̈ differs from the drag-free one.
  ModelSpec none, linear;
  none.name = "projectile";
  linear.name = "projectile_linear_drag";
  const double q[2] = {1.0, 2.0}, qd[2] = {3.0, 4.0};
  EXPECT_LT(entry("projectile_linear_drag").eom(linear, q, qd, 0).qdd[0],
            entry("projectile").eom(none, q, qd, 0).qdd[0]);
  // The presets of template models (models::presets) are built from their
  // descriptions alone; RegistryRunsAreDirectSimulateRuns shows that their
  // parameters reach the model.
}

TEST(SceneModels, EveryModelRunsAndInspectsWithItsDefaults) {
  for (const auto& info : scene::builtin_models()) {
    SCOPED_TRACE(info.name);
    const ModelEntry& e = entry(info.name);
    ModelSpec spec;
    spec.name = info.name;
    RunReport r;
    ASSERT_NO_THROW(r = e.run(spec, options(0.2), "", {}));
    EXPECT_EQ(r.coordinates, info.coordinates);
    EXPECT_GT(r.steps, 0u);
    EXPECT_GE(r.samples, 2u);
    const std::string text = e.inspect(spec, 0.0, false);
    EXPECT_NE(text.find(info.name), std::string::npos);
    EXPECT_NE(text.find("Initial state"), std::string::npos);
    EXPECT_NE(text.find("energy function h"), std::string::npos);
    for (const auto& p : info.parameters) EXPECT_NE(text.find(p.description), std::string::npos) << p.name;
  }
}

TEST(SceneModels, EveryModelWritesItsTrajectoryAndTicksEverySample) {
  TempDir dir("csv");
  for (const std::string name : {"double_pendulum", "knife_edge", "newtons_cradle", "projectile"}) {
    SCOPED_TRACE(name);
    ModelSpec spec;
    spec.name = name;
    int ticks = 0;
    double last = -1;
    std::vector<double> last_row;  // t, q, q̇ of the last tick
    const std::string path = dir.file(name + ".csv");
    const RunReport r = entry(name).run(spec, options(0.5, 0.05), path, [&](const SampleRow& row) {
      ++ticks;
      EXPECT_GT(row.t, last);
      last = row.t;
      last_row.assign(1, row.t);
      last_row.insert(last_row.end(), row.q.begin(), row.q.end());
      last_row.insert(last_row.end(), row.qd.begin(), row.qd.end());
    });
    EXPECT_EQ(static_cast<std::uint64_t>(ticks), r.samples);
    EXPECT_FALSE(fs::exists(path + ".partial"));
    const Csv csv = read_csv(path);
    ASSERT_EQ(csv.rows.size(), r.samples);
    // Each tick carries the sample the file has (17 digits: the same doubles).
    ASSERT_EQ(last_row.size(), 1 + 2 * r.coordinates.size());
    for (std::size_t c = 0; c < last_row.size(); ++c) EXPECT_EQ(csv.rows.back()[c], last_row[c]) << "column " << c;
    EXPECT_EQ(csv.header[0], "t [s]");
    EXPECT_EQ(csv.header[1].substr(0, csv.header[1].find(' ')), r.coordinates[0]);
  }
}

// The trajectory's header carries each coordinate's unit as the catalog
// states it (the model's own coordinate_units(), written by CsvSink), its
// rate's, and the energies' in J: the catalog and the models agree.
TEST(SceneModels, EveryModelsTrajectoryHeaderCarriesTheCatalogUnits) {
  TempDir dir("units");
  for (const scene::ModelInfo& info : scene::builtin_models()) {
    SCOPED_TRACE(info.name);
    ModelSpec spec;
    spec.name = info.name;
    const std::string path = dir.file(info.name + ".csv");
    entry(info.name).run(spec, options(0.02, 0.01), path, {});
    const Csv csv = read_csv(path);
    const std::size_t n = info.coordinates.size();
    ASSERT_GE(csv.header.size(), 2 * n + 2);
    EXPECT_EQ(csv.header[0], "t [s]");
    for (std::size_t i = 0; i < n; ++i) {
      EXPECT_EQ(csv.header[1 + i], info.coordinates[i] + " [" + info.units[i] + "]");
      EXPECT_EQ(csv.header[1 + n + i], info.coordinates[i] + "_dot [" + info.units[i] + "/s]");
    }
    EXPECT_EQ(csv.header[1 + 2 * n], "energy [J]");
  }
}

// -- the registry runs the same run as simulate() ---------------------------------

/// The final state of a registry run (from its CSV) against a direct simulate().
template <int N, class M>
void expect_same_run(const std::string& name, const ModelSpec& spec, const M& model, const State<N>& x0,
                     const SimulationOptions& opt) {
  SCOPED_TRACE(name);
  TempDir dir("same_" + name);
  const RunReport via_registry = entry(name).run(spec, opt, dir.file("t.csv"), {});
  Recorder<N> rec;
  const RunReport direct = simulate(model, x0, opt, rec);
  const Csv csv = read_csv(dir.file("t.csv"));
  ASSERT_EQ(csv.rows.size(), rec.samples.size());
  ASSERT_FALSE(csv.rows.empty());
  const auto& last = csv.rows.back();
  const auto& end = rec.samples.back();
  ASSERT_GE(last.size(), static_cast<std::size_t>(1 + 2 * N));
  EXPECT_EQ(last[0], end.t);
  double worst = 0;
  for (int i = 0; i < N; ++i) {
    EXPECT_NEAR(last[static_cast<std::size_t>(1 + i)], end.q[i], 1e-14 * std::max(1.0, std::abs(end.q[i]))) << i;
    EXPECT_NEAR(last[static_cast<std::size_t>(1 + N + i)], end.qd[i], 1e-14 * std::max(1.0, std::abs(end.qd[i])))
        << i;
    worst = std::max({worst, std::abs(last[static_cast<std::size_t>(1 + i)] - end.q[i]),
                      std::abs(last[static_cast<std::size_t>(1 + N + i)] - end.qd[i])});
  }
  EXPECT_EQ(via_registry.steps, direct.steps);
  EXPECT_EQ(via_registry.rhs_evaluations, direct.rhs_evaluations);
  EXPECT_EQ(via_registry.events.size(), direct.events.size());
  EXPECT_EQ(via_registry.model, direct.model);
  std::printf("  %-16s final state: registry vs direct simulate, max |difference| %.3g (%llu steps)\n",
              name.c_str(), worst, static_cast<unsigned long long>(direct.steps));
}

TEST(SceneModels, RegistryRunsAreDirectSimulateRuns) {
  {
    ModelSpec spec{"double_pendulum", {{"m1", 1.3}, {"m2", 0.7}, {"l1", 0.9}, {"l2", 1.1}, {"g", 9.8}},
                   {1.2, -0.4}, {0.3, 0.1}};
    State<2> x0;
    x0.q << 1.2, -0.4;
    x0.qd << 0.3, 0.1;
    expect_same_run("double_pendulum", spec, lm::DoublePendulum(1.3, 0.7, 0.9, 1.1, 9.8), x0, options(3.0));
  }
  {
    // A constrained model (constrained.hpp): the masses start at c/2.
    ModelSpec spec{"atwood_machine", {{"m1", 2.0}, {"m2", 1.5}, {"c", 4.0}}, {}, {}};
    State<2> x0;
    x0.q << 2.0, 2.0;
    expect_same_run("atwood_machine", spec, lm::AtwoodMachine(2.0, 1.5, 9.81, 4.0), x0, options(1.0));
  }
  {
    // Contacts (impacts.hpp), default parameters of the registry.
    ModelSpec spec{"direct_impact", {{"e", 0.6}}, {0.0, 0.7}, {1.0, -0.5}};
    State<2> x0;
    x0.q << 0.0, 0.7;
    x0.qd << 1.0, -0.5;
    expect_same_run("direct_impact", spec, lm::SpheresOnLine<2>({1.0, 2.0}, {0.1, 0.1}, 0.6), x0, options(1.0));
  }
  {
    // Watched events and a closed form (two_body.hpp): the default state.
    ModelSpec spec{"kepler", {{"mu", 0.5}, {"k", 2.0}}, {}, {}};
    const lm::RelativeMotion<2> model(0.5, lm::NewtonianGravity{2.0});
    expect_same_run("kepler", spec, model, model.default_state(), options(8.0, 0.05));
  }
}

// -- physics through the registry ------------------------------------------------------

/// Times where q (column c of the CSV, with its velocity in column cd)
/// falls through zero, by cubic Hermite interpolation between samples.
std::vector<double> downward_crossings(const Csv& csv, int c, int cd) {
  std::vector<double> out;
  for (std::size_t k = 0; k + 1 < csv.rows.size(); ++k) {
    const auto& a = csv.rows[k];
    const auto& b = csv.rows[k + 1];
    const double y0 = a[static_cast<std::size_t>(c)], y1 = b[static_cast<std::size_t>(c)];
    if (!(y0 > 0 && y1 <= 0)) continue;
    const double t0 = a[0], h = b[0] - a[0];
    const double d0 = a[static_cast<std::size_t>(cd)] * h, d1 = b[static_cast<std::size_t>(cd)] * h;
    auto hermite = [&](double s) {
      const double s2 = s * s, s3 = s2 * s;
      return (2 * s3 - 3 * s2 + 1) * y0 + (s3 - 2 * s2 + s) * d0 + (-2 * s3 + 3 * s2) * y1 + (s3 - s2) * d1;
    };
    double lo = 0, hi = 1;
    for (int it = 0; it < 80; ++it) {
      const double mid = 0.5 * (lo + hi);
      (hermite(mid) > 0 ? lo : hi) = mid;
    }
    out.push_back(t0 + 0.5 * (lo + hi) * h);
  }
  return out;
}

TEST(SceneModels, SimplePendulumSmallAmplitudePeriodIsTwoPiRootLOverG) {
  const double l = 2.0, g = 9.81, theta0 = 1e-3;
  const double period = 2 * std::numbers::pi * std::sqrt(l / g);  // amplitude correction θ0²/16 = 6e-8
  TempDir dir("pendulum");
  ModelSpec spec{"simple_pendulum", {{"l", l}, {"g", g}, {"m", 0.5}}, {theta0}, {0.0}};
  entry("simple_pendulum").run(spec, options(2.3 * period, 1e-3), dir.file("t.csv"), {});
  const Csv csv = read_csv(dir.file("t.csv"));
  const auto t = downward_crossings(csv, csv.column("theta"), csv.column("theta_dot"));
  ASSERT_GE(t.size(), 2u);
  const double measured = t[1] - t[0];
  std::printf("  pendulum period %.12f s, 2 pi sqrt(l/g) = %.12f s, relative difference %.2e\n", measured, period,
              std::abs(measured - period) / period);
  EXPECT_NEAR(measured / period, 1.0, 1e-6);
  // What is left is the finite-amplitude correction 1 + θ0²/16.
  EXPECT_NEAR(measured / (period * (1 + theta0 * theta0 / 16)), 1.0, 1e-9);
  EXPECT_NEAR(t[0], 0.25 * period, 1e-6 * period);
}

TEST(SceneModels, BallAndPlaneReboundsToESquaredTimesTheDropHeight) {
  const double e = 0.7, R = 0.05, h = 1.0, g = 9.81;
  TempDir dir("ball");
  ModelSpec spec{"ball_and_plane", {{"e", e}, {"R", R}, {"m", 0.2}}, {0.0, 0.0, h + R}, {0.0, 0.0, 0.0}};
  const RunReport r = entry("ball_and_plane").run(spec, options(1.0), dir.file("t.csv"), {});
  ASSERT_GE(r.events.size(), 1u);
  const double t1 = r.events[0].t;
  EXPECT_NEAR(t1, std::sqrt(2 * h / g), 1e-10);
  // The height of the first rebound's apex from any free-flight sample after
  // the bounce: z + ż²/(2g) (energy in flight), above the floor by R.
  const Csv csv = read_csv(dir.file("t.csv"));
  const int z = csv.column("z"), zd = csv.column("z_dot");
  double worst = 0;
  int used = 0;
  const double t2 = r.events.size() > 1 ? r.events[1].t : 1.0;
  for (const auto& row : csv.rows) {
    if (row[0] <= t1 + 1e-6 || row[0] >= t2) continue;
    const double apex = row[static_cast<std::size_t>(z)] +
                        row[static_cast<std::size_t>(zd)] * row[static_cast<std::size_t>(zd)] / (2 * g) - R;
    worst = std::max(worst, std::abs(apex / h - e * e));
    ++used;
  }
  ASSERT_GT(used, 10);
  std::printf("  rebound height / drop height vs e^2 = %.2f: max |difference| %.2e over %d samples\n", e * e, worst,
              used);
  EXPECT_LT(worst, 1e-9);
}

// A ball dropped from rest onto a plane tilted by α (normal n = (sin α, 0,
// cos α)), e = 0.5, with one step to the end (a free flight is a parabola,
// which the stepper integrates exactly, so its steps grow past the next
// bounce). Across the normal the bounces are those of a ball on a floor
// under g cos α: the first impact at t1 = √(2 d0 / (g cos α)) (d0 the
// start's height above the plane), then flights shrinking by e, the rest
// at t1 (1 + 2e / (1 − e)). Along the slope nothing changes at an impact:
// the ball has slid ½ g sin α t² down it at every time.
TEST(SceneModels, BallOnATiltedPlaneBouncesToRestAndSlides) {
  const double e = 0.5, R = 0.1, g = 9.81, sa = 0.6, ca = 0.8, z0 = 1.0, t_end = 2.0;
  ModelSpec spec{"ball_and_plane", {{"e", e}, {"R", R}, {"nx", sa}, {"nz", ca}}, {0.0, 0.0, z0}, {0.0, 0.0, 0.0}};
  scene::detail::FinalState last;
  const RunReport r = entry("ball_and_plane").run(spec, options(t_end, t_end), "", {}, &last);
  const double gn = g * ca, t1 = std::sqrt(2 * (ca * z0 - R) / gn);
  ASSERT_GE(r.events.size(), 2u);
  EXPECT_NEAR(r.events[0].t, t1, 1e-10);
  EXPECT_NEAR(r.events[1].t, t1 * (1 + 2 * e), 1e-9);
  ASSERT_EQ(r.events.back().kind, EventKind::rest);
  EXPECT_NEAR(r.events.back().t, t1 * (1 + 2 * e / (1 - e)), 1e-5);
  ASSERT_EQ(last.t, t_end);
  const double x = last.q[0], z = last.q[2];
  EXPECT_NEAR(sa * x + ca * z, R, 1e-9);  // on the plane
  EXPECT_NEAR(ca * x - sa * (z - z0), 0.5 * g * sa * t_end * t_end, 1e-8);  // down the slope
}

TEST(SceneModels, ProjectileRangeIsUSquaredSinTwoAlphaOverG) {
  const double u = 15.0, alpha = 0.6, g = 9.81;
  TempDir dir("projectile");
  ModelSpec spec{"projectile", {{"g", g}}, {0.0, 0.0}, {u * std::cos(alpha), u * std::sin(alpha)}};
  const RunReport r = entry("projectile").run(spec, options(10.0), dir.file("t.csv"), {});
  EXPECT_EQ(r.stopped_by, "landing");
  const Csv csv = read_csv(dir.file("t.csv"));
  ASSERT_FALSE(csv.rows.empty());
  const auto& last = csv.rows.back();
  const double range = u * u * std::sin(2 * alpha) / g;
  std::printf("  range %.12f m, u^2 sin 2a / g = %.12f m, difference %.2e m; flight time %.12f s\n", last[1], range,
              std::abs(last[1] - range), r.t_final);
  EXPECT_NEAR(last[0], r.t_final, 1e-12);
  EXPECT_NEAR(last[1], range, 1e-9);
  EXPECT_NEAR(last[2], 0.0, 1e-9);
  EXPECT_NEAR(r.t_final, 2 * u * std::sin(alpha) / g, 1e-10);
}

TEST(SceneModels, KeplerPeriodIsTwoPiRootACubedOverGM) {
  const double mu = 2.0, k = 3.0, gm = k / mu, a = 1.0;  // the default state: periapsis of a = 1 m, e = 0.5
  const double period = 2 * std::numbers::pi * std::sqrt(a * a * a / gm);
  ModelSpec spec{"kepler", {{"mu", mu}, {"k", k}}, {}, {}};
  SimulationOptions o = options(3.5 * period, 0.05);
  o.rtol = 1e-12;
  o.atol = 1e-14;
  const RunReport r = entry("kepler").run(spec, o, "", {});
  std::vector<double> t;
  for (const auto& ev : r.events)
    if (ev.name == "periapsis" && ev.kind == EventKind::watched) t.push_back(ev.t);
  ASSERT_GE(t.size(), 3u);
  double worst = std::abs(t[0] - period);
  for (std::size_t i = 1; i < t.size(); ++i) worst = std::max(worst, std::abs(t[i] - t[i - 1] - period));
  std::printf("  Kepler: %zu periapsis passages, period %.12f s vs 2 pi sqrt(a^3/GM) = %.12f s, max |difference| "
              "%.2e s; closed-form error %.2e m\n",
              t.size(), t[1] - t[0], period, worst, r.reference_error_max);
  EXPECT_LT(worst / period, 1e-9);
  EXPECT_TRUE(r.has_reference);
  EXPECT_LT(r.reference_error_max, 1e-9);
}

// -- bad input ------------------------------------------------------------------------

TEST(SceneModels, BadParameterIsASceneErrorNamingTheKeyAndTheValue) {
  ModelSpec spec{"simple_pendulum", {{"l", -1.0}}, {}, {}};
  const SceneError e = expect_scene_error([&] { entry("simple_pendulum").run(spec, options(1.0), "", {}); });
  EXPECT_EQ(e.key(), "model.parameters.l");
  const std::string what = e.what();
  EXPECT_NE(what.find("model.parameters.l"), std::string::npos) << what;
  EXPECT_NE(what.find("-1"), std::string::npos) << what;
  // inspect() validates alike.
  EXPECT_EQ(expect_scene_error([&] { entry("simple_pendulum").inspect(spec, 0.0, false); }).key(), "model.parameters.l");
}

TEST(SceneModels, ParameterErrorsAreKeyedByTheRegistrysNames) {
  struct Case {
    std::string model;
    std::map<std::string, double> parameters;
    std::string key;
    std::string value;
  };
  const std::vector<Case> cases{
      {"newtons_cradle", {{"m", -2.0}}, "model.parameters.m", "-2"},         // SpheresOnLine names it m1
      {"newtons_cradle", {{"e", 1.5}}, "model.parameters.e", "1.5"},
      {"ball_and_plane", {{"nz", 0.0}}, "model.parameters.nz", "0"},         // BallAndPlane names it |normal|
      {"spheres_in_box", {{"r", 0.6}}, "model.parameters.r", "0.6"},         // "does not fit in the box"
      {"projectile_linear_drag", {{"b", 0.0}}, "model.parameters.b", "0"},
      {"projectile_quadratic_drag", {{"c", -1.0}}, "model.parameters.c", "-1"},
      {"projectile", {{"beta", 2.0}}, "model.parameters.beta", "2"},
      {"two_body", {{"k", -1.0}}, "model.parameters.k", "-1"},
      {"kepler", {{"mu", 0.0}}, "model.parameters.mu", "0"},
      {"double_pendulum", {{"g", -9.81}}, "model.parameters.g", "-9.81"},
      {"simple_pendulum", {{"length", 2.0}}, "model.parameters.length", "length"},  // unknown name
      {"simple_pendulum", {{"l", std::nan("")}}, "model.parameters.l", "nan"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.model + " " + c.key);
    const ModelSpec spec{c.model, c.parameters, {}, {}};
    const SceneError e = expect_scene_error([&] { entry(c.model).run(spec, options(0.1), "", {}); });
    EXPECT_EQ(e.key(), c.key);
    EXPECT_NE(std::string(e.what()).find(c.value), std::string::npos) << e.what();
  }
}

TEST(SceneModels, WrongStateIsASceneErrorNamingModelQ) {
  {
    const ModelSpec spec{"simple_pendulum", {}, {0.1, 0.2}, {}};
    const SceneError e = expect_scene_error([&] { entry("simple_pendulum").run(spec, options(1.0), "", {}); });
    EXPECT_EQ(e.key(), "model.q");
    EXPECT_NE(std::string(e.what()).find("model.q"), std::string::npos) << e.what();
  }
  {
    const ModelSpec spec{"double_pendulum", {}, {0.1, 0.2}, {1.0}};
    EXPECT_EQ(expect_scene_error([&] { entry("double_pendulum").run(spec, options(1.0), "", {}); }).key(), "model.qd");
  }
  {
    const ModelSpec spec{"kepler_polar", {}, {std::nan(""), 0.0}, {}};
    EXPECT_EQ(expect_scene_error([&] { entry("kepler_polar").inspect(spec, 0.0, false); }).key(), "model.q");
  }
  {
    // Off the rods of a constrained model: named model.q, and the failed run
    // leaves no trajectory file behind, complete or partial.
    TempDir dir("bad_state");
    const ModelSpec spec{"cartesian_double_pendulum", {}, {0.3, -0.5, 0.4, -1.2}, {}};
    const SceneError e = expect_scene_error(
        [&] { entry("cartesian_double_pendulum").run(spec, options(1.0), dir.file("t.csv"), {}); });
    EXPECT_EQ(e.key(), "model.q");
    EXPECT_NE(std::string(e.what()).find("rod1"), std::string::npos) << e.what();
    EXPECT_FALSE(fs::exists(dir.file("t.csv")));
    EXPECT_FALSE(fs::exists(dir.file("t.csv.partial")));
  }
}

// -- inspection ------------------------------------------------------------------------

TEST(SceneModels, InspectionOfConstrainedModelsGivesRanksAndDegreesOfFreedom) {
  {
    const std::string text = entry("cartesian_double_pendulum").inspect({"cartesian_double_pendulum", {}, {}, {}}, 0.0, false);
    std::printf("%s\n", text.c_str());
    EXPECT_NE(row(text, "holonomic constraints").find("constraints 2"), std::string::npos);
    EXPECT_NE(row(text, "rank of dg/dq").find("dg/dq 2"), std::string::npos) << text;
    EXPECT_NE(row(text, "degrees of freedom").find("freedom 2 = 4 - 2"), std::string::npos) << text;
    EXPECT_NE(row(text, "velocity degrees of freedom").find("freedom 2 = 4 - 2"), std::string::npos) << text;
    EXPECT_NE(row(text, "redundant constraints").find("none"), std::string::npos) << text;
    EXPECT_NE(text.find("rod1, rod2"), std::string::npos);
  }
  {
    const std::string text = entry("knife_edge").inspect({"knife_edge", {}, {}, {}}, 0.0, false);
    EXPECT_NE(row(text, "rank of [dg/dq; A]").find("A] 1"), std::string::npos) << text;
    EXPECT_NE(row(text, "degrees of freedom").find("freedom 3 = 3 - 0"), std::string::npos) << text;
    EXPECT_NE(row(text, "velocity degrees of freedom").find("freedom 2 = 3 - 1"), std::string::npos) << text;
    EXPECT_NE(row(text, "Pfaffian constraints", true).find("no_sideslip"), std::string::npos) << text;
  }
}

TEST(SceneModels, InspectionOfKeplerPolarGivesTheConservedAngularMomentum) {
  const double m = 1.5, r = 2.0, rdot = 0.1, phidot = 0.35;
  const ModelSpec spec{"kepler_polar", {{"m", m}}, {r, 0.3}, {rdot, phidot}};
  const std::string text = entry("kepler_polar").inspect(spec, 0.0, false);
  std::printf("%s\n", text.c_str());
  const std::string line = row(text, "cyclic coordinates");
  ASSERT_NE(line.find("p_phi = "), std::string::npos) << text;
  const double p_phi = std::strtod(line.c_str() + line.find("p_phi = ") + 8, nullptr);
  EXPECT_NEAR(p_phi, m * r * r * phidot, 1e-12);  // 2.1 kg m^2/s
  EXPECT_EQ(text.find("p_r = "), std::string::npos);  // r is not cyclic
  EXPECT_NE(row(text, "energy function h").find("conserved"), std::string::npos);
  EXPECT_NE(row(text, "T + V").find("equals h"), std::string::npos);
}

TEST(SceneModels, InspectionTellsWhenTheEnergyFunctionIsConservedAndEqualsTPlusV) {
  {
    // The spinning hoop: h conserved, T + V is not h (the motor's term ½ m R² ω² sin²θ).
    const std::string text = entry("bead_on_rotating_hoop").inspect({"bead_on_rotating_hoop", {}, {}, {}}, 0.0, false);
    EXPECT_NE(row(text, "energy function h").find("conserved"), std::string::npos) << text;
    EXPECT_EQ(row(text, "energy function h").find("not conserved"), std::string::npos) << text;
    EXPECT_NE(row(text, "T + V").find("differs from h"), std::string::npos) << text;
  }
  {
    const std::string text = entry("driven_pendulum").inspect({"driven_pendulum", {}, {}, {}}, 0.0, false);
    EXPECT_NE(row(text, "energy function h").find("not conserved: L depends explicitly on t"),
              std::string::npos)
        << text;
  }
  {
    const std::string text = entry("bead_on_rotating_wire").inspect({"bead_on_rotating_wire", {}, {}, {}}, 0.0, false);
    EXPECT_NE(row(text, "energy function h").find("moving constraints do work"), std::string::npos) << text;
  }
  {
    const std::string text =
        entry("projectile_quadratic_drag").inspect({"projectile_quadratic_drag", {}, {}, {}}, 0.0, false);
    EXPECT_NE(row(text, "energy function h").find("dissipation"), std::string::npos) << text;
    EXPECT_NE(row(text, "watched events").find("landing (falling, stops the run)"), std::string::npos) << text;
    EXPECT_NE(row(text, "closed-form reference").find("no"), std::string::npos) << text;
  }
  {
    const std::string text = entry("direct_impact").inspect({"direct_impact", {}, {}, {}}, 0.0, false);
    EXPECT_NE(row(text, "restitution", true).find("e = 0.8"), std::string::npos) << text;
    EXPECT_NE(row(text, "energy function h").find("impacts with e < 1 dissipate"), std::string::npos) << text;
    EXPECT_NE(row(text, "unilateral constraints", true).find("s1-s2"), std::string::npos) << text;
  }
}

}  // namespace
