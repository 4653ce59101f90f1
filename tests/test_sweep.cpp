// Sweeps: the options and points, and the example sweeps against closed forms
// derived here by hand (not taken from the code under test):
//  - range on flat ground and up an incline of angle β, launch (u, α):
//      time of flight T = 2u sin(α − β)/(g cos β) (from u sin α T − g T²/2 = u cos α T tan β),
//      landing x = u cos α T, greatest range along the plane at α = π/4 + β/2;
//  - kinetic energy lost in a direct impact with restitution e:
//      ΔKE = ½ μ (1 − e²) v_rel², μ = m1 m2/(m1 + m2);
//  - the double pendulum released from rest cannot flip where
//      2 cos θ1 + cos θ2 > 1 (energy below the lowest upright state).

#include <gtest/gtest.h>

#include "lagrangian/scene/plots.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "lagrangian/errors.hpp"
#include "lagrangian/scene/analysis.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/io.hpp"
#include "lagrangian/scene/run.hpp"
#include "lagrangian/scene/sweep.hpp"

namespace fs = std::filesystem;
using namespace lagrangian;
using namespace lagrangian::scene;

namespace {

#define REQUIRE_GNUPLOT_FOR_SWEEPS() \
  if (!lagrangian::gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed (scripts/setup installs it)"

constexpr double kPi = 3.141592653589793;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
const std::string kSweeps = std::string(LAGRANGIAN_SOURCE_DIR) + "/examples/sweeps/";

std::string out_dir(const std::string& name) {
  const fs::path p = fs::path(testing::TempDir()) / ("lagrangian_sweep_" + name);
  fs::remove_all(p);
  return p.string();
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

/// A sweep of `vary` on two threads into a fresh directory, without plots.
SweepOptions options(const std::string& name, std::vector<VarySpec> vary) {
  SweepOptions o;
  o.vary = std::move(vary);
  o.out_dir = out_dir(name);
  o.plots = false;
  o.threads = 2;
  return o;
}

/// The launch-angle sweep of a projectile scene: α in degrees, u = 20 m/s.
SweepOptions launch_sweep(double from, double to, int count, const std::string& name) {
  SweepOptions o = options(
      name, {parse_vary("alpha=" + std::to_string(from) + ":" + std::to_string(to) + ":" + std::to_string(count))});
  o.set = {parse_set("model.qd[0]=20*cos(alpha*pi/180)"), parse_set("model.qd[1]=20*sin(alpha*pi/180)")};
  return o;
}

/// A run of ke_loss.toml (m1 = 1 kg at 1 m/s, m2 at −0.5 m/s, v_rel = 1.5
/// m/s) with values (e, m2): ΔKE = ½ μ (1 − e²) v_rel² and the momentum kept.
void expect_impact_closed_form(const SweepRecord& rec) {
  ASSERT_TRUE(rec.ok()) << rec.status;
  const double m1 = 1, v_rel = 1.5, e = rec.values[0], m2 = rec.values[1];
  const double mu = m1 * m2 / (m1 + m2);
  EXPECT_NEAR(rec.impact_energy_loss, 0.5 * mu * (1 - e * e) * v_rel * v_rel, 1e-12) << "e " << e << " m2 " << m2;
  // Momentum kept: m1 v1 + m2 v2 = 1·1 + m2·(−0.5).
  EXPECT_NEAR(m1 * rec.qd[0] + m2 * rec.qd[1], 1.0 - 0.5 * m2, 1e-12);
}

std::size_t column(const SweepResult& r, const std::string& name) {
  const auto it = std::find(r.header.begin(), r.header.end(), name);
  EXPECT_NE(it, r.header.end()) << "no column " << name;
  return static_cast<std::size_t>(it - r.header.begin());
}

/// Checks every point's landing x against the hand-derived closed form and
/// the argmax of the range along the plane against π/4 + β/2.
void check_range(const SweepResult& r, double beta, double best_degrees) {
  const double u = 20, g = 9.81;
  ASSERT_EQ(r.failed, 0u);
  EXPECT_EQ(column(r, "alpha"), 1u);
  EXPECT_EQ(column(r, "status"), 4u);
  EXPECT_GT(column(r, "q_x"), 4u);
  double best_range = -1, best_alpha = 0;
  for (const SweepRecord& rec : r.records) {
    ASSERT_TRUE(rec.ok()) << rec.status;
    const double alpha = rec.values[0] * kPi / 180;
    const double flight = 2 * u * std::sin(alpha - beta) / (g * std::cos(beta));
    const double x = u * std::cos(alpha) * flight;
    EXPECT_NEAR(rec.q[0], x, 1e-8 * (1 + x)) << "alpha = " << rec.values[0];
    EXPECT_NEAR(rec.t_final, flight, 1e-9) << "alpha = " << rec.values[0];
    ASSERT_EQ(rec.events.count("stop"), 1u);  // landing ended the run
    const double along = std::hypot(rec.q[0], rec.q[1]);
    if (along > best_range) {
      best_range = along;
      best_alpha = rec.values[0];
    }
  }
  EXPECT_DOUBLE_EQ(best_alpha, best_degrees);
  EXPECT_NEAR(best_range, u * u / (g * (1 + std::sin(beta))), 1e-7);
}

}  // namespace

TEST(SweepOptions, ParsesGridsAndDistributions) {
  VarySpec v = parse_vary("model.parameters.e=0:1:5");
  EXPECT_EQ(v.key, "model.parameters.e");
  EXPECT_FALSE(v.variable());
  EXPECT_EQ(v.count, 5);
  EXPECT_DOUBLE_EQ(v.grid_value(1), 0.25);
  EXPECT_EQ(v.grid_value(4), 1.0);
  v = parse_vary("run.rtol=1e-3:1e-1:3:log");
  EXPECT_NEAR(v.grid_value(1), 1e-2, 1e-17);
  v = parse_vary("x=3:1:3");  // descending grids are allowed
  EXPECT_TRUE(v.variable());
  EXPECT_EQ(v.grid_value(1), 2.0);
  v = parse_vary("bodies[0].velocity[2]=normal:1:0.5");
  EXPECT_EQ(v.kind, VarySpec::Kind::normal);
  EXPECT_FALSE(v.grid());
}

TEST(SweepOptions, MalformedVaryNamesTheOptionAndTheValue) {
  for (const char* bad : {"model.parameters.e", "model.parameters.e=0:1:0", "model.parameters.e=0:x:3",
                          "model.parameters.e=0:1", "model.parameters.e=0:1:2.5", "e=uniform:2:1",
                          "e=normal:0:0", "e=1e-3:0:3:log", "=0:1:3", "a b=0:1:2", "e=0:1:3:lin"}) {
    try {
      parse_vary(bad);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const OptionError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("--vary", 0), 0u) << m;
    }
  }
  EXPECT_THROW(parse_set("model.qd[0]"), OptionError);
  EXPECT_THROW(parse_set("alpha=3"), OptionError);  // not a scene key
}

TEST(SweepOptions, InconsistentCombinationsAreRefused) {
  SweepOptions o;
  o.vary = {parse_vary("e=uniform:0:1")};
  EXPECT_THROW(o.validate(), OptionError);  // a distribution without --monte-carlo
  o.monte_carlo = 10;
  EXPECT_NO_THROW(o.validate());
  o.vary.push_back(parse_vary("f=0:1:3"));
  EXPECT_THROW(o.validate(), OptionError);  // a grid in a Monte Carlo sweep
  o = SweepOptions{};
  EXPECT_THROW(o.validate(), OptionError);  // nothing varied
  o.vary = {parse_vary("e=0:1:3")};
  o.outputs = {"final", "energie"};
  try {
    o.validate();
    ADD_FAILURE();
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'energy'"), std::string::npos) << e.what();
  }
}

TEST(SweepExpression, EvaluatesArithmeticAndFunctions) {
  const std::vector<std::string> names{"a", "b"};
  const double v[] = {2.0, 3.0};
  EXPECT_DOUBLE_EQ(Expression("a + b * 2 ^ 2", names, "t").evaluate(v), 14.0);
  EXPECT_DOUBLE_EQ(Expression("-a^2", names, "t").evaluate(v), -4.0);
  EXPECT_DOUBLE_EQ(Expression("(a - b) / 4", names, "t").evaluate(v), -0.25);
  EXPECT_DOUBLE_EQ(Expression("max(abs(-a), b) - min(a, b)", names, "t").evaluate(v), 1.0);
  EXPECT_NEAR(Expression("20*cos(60*pi/180)", names, "t").evaluate(v), 10.0, 1e-13);
  EXPECT_DOUBLE_EQ(Expression("atan2(0, -1)", names, "t").evaluate(v), kPi);
  EXPECT_THROW(Expression("a +", names, "t"), OptionError);
  EXPECT_THROW(Expression("sine(a)", names, "t"), OptionError);
  try {
    Expression("alpah * 2", {"alpha"}, "--set x.y");
    ADD_FAILURE();
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("did you mean 'alpha'"), std::string::npos) << e.what();
  }
}

TEST(SweepPoints, GridRunsTheFirstKeySlowest) {
  SweepOptions o;
  o.vary = {parse_vary("a=0:1:2"), parse_vary("b=10:30:3")};
  ASSERT_EQ(point_count(o), 6u);
  EXPECT_EQ(point_values(o, 0), (std::vector<double>{0, 10}));
  EXPECT_EQ(point_values(o, 2), (std::vector<double>{0, 30}));
  EXPECT_EQ(point_values(o, 4), (std::vector<double>{1, 20}));
}

TEST(SweepPoints, MonteCarloDrawsDependOnSeedAndIndexOnly) {
  SweepOptions o;
  o.vary = {parse_vary("u=uniform:2:5"), parse_vary("n=normal:1:0.5")};
  o.monte_carlo = 20000;
  o.seed = 42;
  const std::vector<double> p7 = point_values(o, 7);
  EXPECT_EQ(point_values(o, 7), p7);  // again: the same
  o.seed = 43;
  EXPECT_NE(point_values(o, 7), p7);
  o.seed = 42;
  // The uniforms lie in [2, 5) with mean 3.5 and variance 9/12; the normals
  // have mean 1 and standard deviation 0.5 (within 5 standard errors).
  double su = 0, su2 = 0, sn = 0, sn2 = 0;
  const double n = static_cast<double>(o.monte_carlo);
  for (std::uint64_t i = 0; i < o.monte_carlo; ++i) {
    const auto v = point_values(o, i);
    ASSERT_GE(v[0], 2.0);
    ASSERT_LT(v[0], 5.0);
    su += v[0];
    su2 += v[0] * v[0];
    sn += v[1];
    sn2 += v[1] * v[1];
  }
  EXPECT_NEAR(su / n, 3.5, 5 * std::sqrt(0.75 / n));
  EXPECT_NEAR(su2 / n - (su / n) * (su / n), 0.75, 0.03);
  EXPECT_NEAR(sn / n, 1.0, 5 * 0.5 / std::sqrt(n));
  EXPECT_NEAR(std::sqrt(sn2 / n - (sn / n) * (sn / n)), 0.5, 0.015);
  // splitmix64 of consecutive indices: distinct seeds.
  EXPECT_NE(point_seed(42, 0), point_seed(42, 1));
}

TEST(SweepExamples, RangeOnFlatGroundMatchesTheClosedFormAndPeaksAt45Degrees) {
  const SweepResult r = sweep(kSweeps + "range_flat.toml", launch_sweep(5, 85, 33, "flat"));
  ASSERT_EQ(r.records.size(), 33u);
  check_range(r, 0.0, 45.0);
}

TEST(SweepExamples, RangeUpAnInclinePeaksAt45DegreesPlusHalfTheSlope) {
  const double beta = 20 * kPi / 180;
  const SweepResult r = sweep(kSweeps + "range_incline.toml", launch_sweep(21, 89, 35, "incline"));
  ASSERT_EQ(r.records.size(), 35u);
  check_range(r, beta, 55.0);
  // Landed on the plane: y = x tan β.
  for (const SweepRecord& rec : r.records) EXPECT_NEAR(rec.q[1], rec.q[0] * std::tan(beta), 1e-8);
}

TEST(SweepExamples, KineticEnergyLossMatchesHalfMuOneMinusESquaredVrelSquared) {
  const SweepResult r = sweep(
      kSweeps + "ke_loss.toml",
      options("ke", {parse_vary("model.parameters.e=0:1:11"), parse_vary("model.parameters.m2=0.25:4:6")}));
  ASSERT_EQ(r.records.size(), 66u);
  ASSERT_EQ(r.failed, 0u);
  for (const SweepRecord& rec : r.records) expect_impact_closed_form(rec);
}

// Cancelled before it starts: no run, no table, no working directory; an
// earlier table in the directory is gone too.
// The plots' axes carry the units of the keys and columns: the catalog's
// for model parameters and coordinates, J for the impact's loss.
TEST(SweepPlots, AxesCarryUnits) {
  REQUIRE_GNUPLOT_FOR_SWEEPS();
  SweepOptions o = options("units_1d", {parse_vary("model.parameters.m2=0.5:2:4")});
  o.plots = true;
  o.plot_columns = {"impact_energy_loss", "q_x1", "qd_x2"};
  sweep(kSweeps + "ke_loss.toml", o);
  const std::string script = slurp(o.out_dir + "/sweep.gp");
  EXPECT_NE(script.find("set xlabel 'model.parameters.m2 (kg)'"), std::string::npos) << script.substr(0, 600);
  EXPECT_NE(script.find("set ylabel 'impact_energy_loss (J)'"), std::string::npos);
  EXPECT_NE(script.find("set ylabel 'q_x1 (m)'"), std::string::npos);
  EXPECT_NE(script.find("set ylabel 'qd_x2 (m/s)'"), std::string::npos);
  // Two keys: both axes, the colour bar the column's.
  SweepOptions o2 = options("units_2d", {parse_vary("model.parameters.e=0:1:3"), parse_vary("model.qd[0]=0.5:1.5:3")});
  o2.plots = true;
  o2.plot_columns = {"impact_energy_loss"};
  sweep(kSweeps + "ke_loss.toml", o2);
  const std::string map = slurp(o2.out_dir + "/sweep.gp");
  EXPECT_NE(map.find("set xlabel 'model.parameters.e'\n"), std::string::npos) << map.substr(0, 600);  // unitless
  EXPECT_NE(map.find("set ylabel 'model.qd[0] (m/s)'"), std::string::npos);
  EXPECT_NE(map.find("set cblabel 'impact_energy_loss (J)'"), std::string::npos);
}

TEST(SweepCancel, ACancelledSweepWritesNothingAndSaysHowFarItGot) {
  SweepOptions o = options("cancelled", {parse_vary("model.parameters.e=0:1:50")});
  std::filesystem::create_directories(o.out_dir);
  std::ofstream(o.out_dir + "/sweep.csv") << "an earlier table\n";
  const std::atomic<bool> stop{true};
  o.cancel = &stop;
  try {
    sweep(kSweeps + "ke_loss.toml", o);
    ADD_FAILURE() << "a cancelled sweep returned";
  } catch (const SweepInterrupted& e) {
    EXPECT_EQ(e.done_runs, 0u);
    EXPECT_EQ(e.total_runs, 50u);
    EXPECT_NE(std::string(e.what()).find("sweep interrupted after 0 of 50 runs; no table written"), std::string::npos);
  }
  EXPECT_FALSE(std::filesystem::exists(o.out_dir + "/sweep.csv"));
  EXPECT_FALSE(std::filesystem::exists(o.out_dir + "/.work-rank0"));
}

TEST(SweepExamples, MonteCarloKineticEnergyLossFollowsTheClosedFormPointByPointAndOnAverage) {
  SweepOptions o =
      options("mc", {parse_vary("model.parameters.e=uniform:0:1"), parse_vary("model.parameters.m2=normal:2:0.1")});
  o.monte_carlo = 400;
  o.seed = 2026;
  const SweepResult r = sweep(kSweeps + "ke_loss.toml", o);
  ASSERT_EQ(r.records.size(), 400u);
  ASSERT_EQ(r.failed, 0u);
  double sum = 0;
  for (std::size_t i = 0; i < r.records.size(); ++i) {
    const SweepRecord& rec = r.records[i];
    EXPECT_EQ(rec.values, point_values(o, i));  // the run used point i's draws
    expect_impact_closed_form(rec);
    sum += rec.impact_energy_loss;
  }
  // E[ΔKE] over e ~ U(0, 1): ½ μ v_rel² E[1 − e²] = ½ μ v_rel² · 2/3, with μ at
  // m2 ≈ 2 (the spread of m2 moves μ by well under the tolerance); the
  // standard error of the mean of 400 draws is about 0.75 · 0.3 / 20 ≈ 0.011.
  EXPECT_NEAR(sum / 400, 0.5 * (2.0 / 3.0) * 2.25 * (2.0 / 3.0), 0.05);
}

TEST(SweepExamples, DoublePendulumNeverFlipsWhereEnergyForbidsIt) {
  SweepOptions o = options("flip", {parse_vary("model.q[0]=-3:3:9"), parse_vary("model.q[1]=-3:3:9")});
  o.first_times = {parse_first_time("flip=max(abs(theta1),abs(theta2))-pi")};
  const SweepResult r = sweep(kSweeps + "flip_map.toml", o);
  ASSERT_EQ(r.failed, 0u);
  int forbidden = 0, flipped = 0;
  for (const SweepRecord& rec : r.records) {
    const double t1 = rec.values[0], t2 = rec.values[1];
    ASSERT_EQ(rec.first_times.size(), 1u);
    if (2 * std::cos(t1) + std::cos(t2) > 1) {
      ++forbidden;
      EXPECT_TRUE(std::isnan(rec.first_times[0])) << t1 << " " << t2 << " flipped at " << rec.first_times[0];
      EXPECT_LT(std::max(std::abs(rec.q[0]), std::abs(rec.q[1])), kPi);
    } else if (!std::isnan(rec.first_times[0])) {
      ++flipped;
      EXPECT_GT(rec.first_times[0], 0.0);
      EXPECT_LE(rec.first_times[0], 10.0);
    }
  }
  EXPECT_GT(forbidden, 5);
  EXPECT_GT(flipped, 5);
  // Started upright with θ1 = ±3 and θ2 = ±3 the pendulum flips almost at once.
  EXPECT_LT(r.records.front().first_times[0], 1.0);
}

// The first times come from the samples in memory; they are those of the
// run's own trajectory.csv (17 digits: the same doubles), read back here and
// crossed by the same rule: linear interpolation between the last sample at
// or below 0 and the first above.
TEST(SweepExamples, FirstTimesAreThoseOfTheTrajectoryFile) {
  SweepOptions o = options("first_csv", {parse_vary("model.q[0]=2.5:3:2")});
  o.first_times = {parse_first_time("flip=max(abs(theta1),abs(theta2))-pi"),
                   parse_first_time("spin=theta1_dot-1"), parse_first_time("low=-energy-10")};
  const SweepResult r = sweep(kSweeps + "flip_map.toml", o);
  ASSERT_EQ(r.failed, 0u);
  ASSERT_EQ(r.records.size(), 2u);
  int crossed = 0;
  for (const SweepRecord& rec : r.records) {
    Scene s = load_scene(kSweeps + "flip_map.toml",
                         {parse_key_setting("model.q[0]=" + std::to_string(rec.values[0]))});
    s.output.directory = out_dir("first_csv_run");
    s.output.plots = false;
    s.output.animation = false;
    run(s);
    std::ifstream in(s.output.directory + "/trajectory.csv");
    std::string line;
    ASSERT_TRUE(std::getline(in, line));
    std::vector<std::string> header;
    {
      std::istringstream h(line);
      for (std::string f; std::getline(h, f, ',');) header.push_back(f.substr(0, f.find(' ')));
    }
    auto col = [&](const std::string& name) {
      return static_cast<std::size_t>(std::find(header.begin(), header.end(), name) - header.begin());
    };
    const std::size_t t = col("t"), a = col("theta1"), b = col("theta2"), w = col("theta1_dot"), e = col("energy");
    ASSERT_LT(std::max({t, a, b, w, e}), header.size()) << line;
    std::array<double, 3> first{kNaN, kNaN, kNaN}, prev{kNaN, kNaN, kNaN};
    double prev_t = kNaN;
    while (std::getline(in, line)) {
      std::vector<double> row;
      std::istringstream c(line);
      for (std::string f; std::getline(c, f, ',');) row.push_back(std::stod(f));
      const std::array<double, 3> v{std::max(std::abs(row[a]), std::abs(row[b])) - kPi, row[w] - 1, -row[e] - 10};
      for (std::size_t k = 0; k < 3; ++k) {
        if (std::isnan(first[k]) && v[k] > 0)
          first[k] = std::isfinite(prev[k]) && prev[k] <= 0 ? prev_t + (row[t] - prev_t) * (0 - prev[k]) / (v[k] - prev[k])
                                                             : row[t];
        prev[k] = v[k];
      }
      prev_t = row[t];
    }
    ASSERT_EQ(rec.first_times.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
      if (std::isnan(first[k])) {
        EXPECT_TRUE(std::isnan(rec.first_times[k])) << k;
      } else {
        EXPECT_DOUBLE_EQ(rec.first_times[k], first[k]) << "expression " << k << ", q0 = " << rec.values[0];
      }
    }
    crossed += static_cast<int>(std::count_if(first.begin(), first.end(), [](double v) { return !std::isnan(v); }));
    // h = T + V is conserved at V(q0) = -g (2 cos q0 + cos 0.5) = 7.1 J and 10.8 J: never below -10 J.
    EXPECT_TRUE(std::isnan(rec.first_times[2]));
  }
  EXPECT_GE(crossed, 2);  // not a comparison of blanks only
}

TEST(SweepParallel, TheTableIsTheSameForOneAndTwoThreads) {
  SweepOptions o;
  o.vary = {parse_vary("model.q[0]=-2.5:2.5:5"), parse_vary("model.q[1]=-2:2:4")};
  o.plots = false;
  o.threads = 1;
  const std::string dir1 = out_dir("t1"), dir2 = out_dir("t2");
  o.out_dir = dir1;
  sweep(kSweeps + "flip_map.toml", o);
  o.threads = 2;
  o.out_dir = dir2;
  sweep(kSweeps + "flip_map.toml", o);
  const std::string one = slurp(dir1 + "/sweep.csv"), two = slurp(dir2 + "/sweep.csv");
  EXPECT_GT(one.size(), 1000u);
  EXPECT_EQ(one, two);
}

TEST(SweepFailures, AFailedRunIsARowAndTheSweepGoesOn) {
  SweepOptions o;
  o.vary = {parse_vary("model.parameters.e=0.5:1.5:3")};  // e = 1.5 is out of [0, 1]
  o.out_dir = out_dir("fail");
  o.plots = false;
  const SweepResult r = sweep(kSweeps + "ke_loss.toml", o);
  ASSERT_EQ(r.records.size(), 3u);
  EXPECT_EQ(r.failed, 1u);
  EXPECT_TRUE(r.records[0].ok());
  EXPECT_TRUE(r.records[1].ok());
  EXPECT_FALSE(r.records[2].ok());
  EXPECT_NE(r.records[2].status.find("model.parameters.e"), std::string::npos) << r.records[2].status;
  const std::string csv = slurp(o.out_dir + "/sweep.csv");
  const auto row = csv.find("\n2,1.5,");
  ASSERT_NE(row, std::string::npos) << csv;
  const std::string status = csv.substr(row + 7, 9);  // quoted when the message has a comma
  EXPECT_TRUE(status.rfind("failed: ", 0) == 0 || status.rfind("\"failed: ", 0) == 0) << csv;
  EXPECT_FALSE(fs::exists(o.out_dir + "/sweep.csv.partial"));
}

/// A sweep into a directory removes everything an earlier sweep wrote there
/// (its table and plots), and keeps the user's own files.
TEST(SweepFailures, NothingOfAnEarlierSweepSurvivesALaterOne) {
  SweepOptions o;
  o.vary = {parse_vary("model.parameters.e=0:1:3")};
  o.out_dir = out_dir("again");
  fs::remove_all(o.out_dir);
  o.plots = true;
  const SweepResult plotted = sweep(kSweeps + "ke_loss.toml", o);
  ASSERT_TRUE(plotted.plot_note.empty()) << plotted.plot_note;  // gnuplot is installed by scripts/setup
  std::vector<std::string> plots;
  for (const std::string& f : plotted.files)
    if (!f.ends_with("sweep.csv")) plots.push_back(f);
  ASSERT_FALSE(plots.empty());
  for (const auto& f : plots) ASSERT_TRUE(fs::exists(f)) << f;
  { std::ofstream(o.out_dir + "/mine.png") << "mine"; }
  o.plots = false;
  sweep(kSweeps + "ke_loss.toml", o);
  for (const auto& f : plots) EXPECT_FALSE(fs::exists(f)) << f << " survived";
  EXPECT_TRUE(fs::exists(o.out_dir + "/sweep.csv"));
  EXPECT_TRUE(fs::exists(o.out_dir + "/mine.png"));
  fs::remove_all(o.out_dir);
}

TEST(SweepFailures, AnUnknownKeyIsBadInputWithTheScenesMessage) {
  SweepOptions o;
  o.vary = {parse_vary("run.rtoll=1e-8:1e-6:2")};
  o.out_dir = out_dir("unknown");
  o.plots = false;
  try {
    sweep(kSweeps + "ke_loss.toml", o);
    ADD_FAILURE();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.key(), "run.rtoll");
    EXPECT_NE(e.message().find("did you mean 'rtol'"), std::string::npos) << e.what();
  }
  o.vary = {parse_vary("model.parameters.ee=0:1:2")};
  EXPECT_THROW(sweep(kSweeps + "ke_loss.toml", o), SceneError);
  o.vary = {parse_vary("model.q[5]=0:1:2")};  // the scene's q has 2 elements
  EXPECT_THROW(sweep(kSweeps + "ke_loss.toml", o), OptionError);
  EXPECT_FALSE(fs::exists(o.out_dir + "/sweep.csv"));
}

// The chaos columns are scene::lyapunov()'s λ1 and ⟨Y⟩ at each point (one
// tangent vector over the scene's run), the same doubles as a direct call;
// the double pendulum is regular near the bottom and chaotic from
// (θ1, θ2) = (2, 2) rad (tests/test_lyapunov.cpp: λ1 ≈ 1.3 1/s over 25 s).
TEST(SweepChaos, TheChaosColumnsAreTheLyapunovExponentAndMegnoOfEachPoint) {
  SweepOptions o = options("chaos", {parse_vary("a=0.1:2:2")});
  o.set = {parse_set("model.q[0]=a"), parse_set("model.q[1]=a")};
  o.outputs = {"final", "chaos"};
  const SweepResult r = sweep(kSweeps + "flip_map.toml", o);
  ASSERT_EQ(r.failed, 0u);
  ASSERT_EQ(r.records.size(), 2u);
  EXPECT_EQ(r.header.back(), "megno");
  EXPECT_EQ(r.header[r.header.size() - 2], "lyapunov_max");
  EXPECT_NE(slurp(o.out_dir + "/sweep.csv").find(",lyapunov_max [1/s],megno\n"), std::string::npos);
  for (const SweepRecord& rec : r.records) {
    const std::string a = std::to_string(rec.values[0]);
    const Scene s = load_scene(kSweeps + "flip_map.toml",
                               {parse_key_setting("model.q[0]=" + a), parse_key_setting("model.q[1]=" + a)});
    const LyapunovRun direct = lyapunov(s, LyapunovRequest{1, 0.0});
    EXPECT_DOUBLE_EQ(rec.lyapunov_max, direct.result.spectrum.front()) << "a = " << a;
    EXPECT_DOUBLE_EQ(rec.megno, direct.result.megno_mean) << "a = " << a;
  }
  const SweepRecord &regular = r.records[0], &chaotic = r.records[1];
  EXPECT_LT(regular.lyapunov_max, 0.3);
  EXPECT_LT(regular.megno, 2.5);
  EXPECT_GT(chaotic.lyapunov_max, 0.5);
  EXPECT_GT(chaotic.megno, 3.0);
  // Without the group the columns are absent and the records hold NaN.
  o.outputs = {"final"};
  const SweepResult plain = sweep(kSweeps + "flip_map.toml", o);
  EXPECT_EQ(std::count(plain.header.begin(), plain.header.end(), "lyapunov_max"), 0);
  EXPECT_TRUE(std::isnan(plain.records[0].lyapunov_max));
}

// A gas takes the event-driven engine's tangent flow (scene/
// hard_spheres_tangent.hpp): its chaos columns are those of a direct
// scene::lyapunov() at each point, and a dilute gas's λ1 is positive.
TEST(SweepChaos, AGasHasTheChaosColumnsOfTheEventDrivenTangentFlow) {
  const std::string scene_file = out_dir("chaos_gas_scene") + ".toml";
  {
    std::ofstream f(scene_file);
    f << "name = \"small gas\"\n[run]\nt_end = 3.0\n[gas]\ncount = 20\nmass = 1.0\nradius = 0.05\n"
         "speed = 1.0\nseed = 3\n[contacts.spheres]\nrestitution = 1.0\n[contacts.box]\nmin = [0.0, 0.0, 0.0]\n"
         "max = [1.0, 1.0, 1.0]\nrestitution = 1.0\n";
  }
  SweepOptions o = options("chaos_gas", {parse_vary("gas.seed=3:4:2")});
  o.outputs = {"chaos"};
  const SweepResult r = sweep(scene_file, o);
  ASSERT_EQ(r.failed, 0u);
  ASSERT_EQ(r.records.size(), 2u);
  for (const SweepRecord& rec : r.records) {
    const std::string seed = std::to_string(static_cast<int>(rec.values[0]));
    const LyapunovRun direct = lyapunov(load_scene(scene_file, {parse_key_setting("gas.seed=" + seed)}),
                                        LyapunovRequest{1, 0.0});
    EXPECT_EQ(direct.model, "gas");
    EXPECT_DOUBLE_EQ(rec.lyapunov_max, direct.result.spectrum.front()) << "seed " << seed;
    EXPECT_DOUBLE_EQ(rec.megno, direct.result.megno_mean) << "seed " << seed;
    EXPECT_GT(rec.lyapunov_max, 0.5) << "seed " << seed;
  }
  EXPECT_NE(r.records[0].lyapunov_max, r.records[1].lyapunov_max);
}

// A scene without a tangent flow (a particle scene with links and sphere
// contacts) is refused before any run, with scene::lyapunov()'s reason.
TEST(SweepChaos, AModelWithoutATangentFlowIsRefusedBeforeAnyRun) {
  SweepOptions o = options("chaos_refused", {parse_vary("model.q[0]=1:2:3")});
  o.outputs = {"chaos"};
  // A text model of 7 coordinates: the tangent flow takes at most 6.
  const std::string file = out_dir("chaos_refused_scene") + ".toml";
  std::ofstream(file) << R"toml(name = "seven oscillators"
[model]
coordinates = ["a", "b", "c", "d", "e", "f", "h"]
kinetic = "0.5*(a_dot^2 + b_dot^2 + c_dot^2 + d_dot^2 + e_dot^2 + f_dot^2 + h_dot^2)"
potential = "0.5*(a^2 + b^2 + c^2 + d^2 + e^2 + f^2 + h^2)"
q = [1, 0, 0, 0, 0, 0, 0]
)toml";
  try {
    sweep(file, o);
    ADD_FAILURE() << "the sweep ran";
  } catch (const OptionError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind("--output chaos: ", 0), 0u) << m;
    EXPECT_NE(m.find("the model stated as text: the tangent flow is derived for models with at most 6 coordinates; "
                     "this one has 7"),
              std::string::npos)
        << m;
  }
  EXPECT_FALSE(fs::exists(o.out_dir + "/sweep.csv"));
}

// The double pendulum is symmetric under the mirror (θ1, θ2) → (−θ1, −θ2):
// the motion from −x0 is the mirror image of that from x0 and its Jacobian
// is the same matrix, so λ1 and ⟨Y⟩ of the two starts agree — regular and
// chaotic alike — while they differ between regular and chaotic starts.
TEST(SweepChaos, TheChaosMapHasTheMirrorSymmetryOfThePendulum) {
  SweepOptions o = options("chaos_mirror", {parse_vary("model.q[0]=-2.5:2.5:5"), parse_vary("model.q[1]=-2.5:2.5:5")});
  o.outputs = {"chaos"};
  const SweepResult r = sweep(kSweeps + "chaos_map.toml", o);
  ASSERT_EQ(r.failed, 0u);
  ASSERT_EQ(r.records.size(), 25u);
  for (std::size_t i = 0; i < 25; ++i) {
    const SweepRecord &a = r.records[i], &b = r.records[24 - i];  // point 24 − i is the mirror of point i
    ASSERT_DOUBLE_EQ(a.values[0], -b.values[0]);
    EXPECT_NEAR(a.lyapunov_max, b.lyapunov_max, 1e-6 * (1 + b.lyapunov_max)) << a.values[0] << " " << a.values[1];
    EXPECT_NEAR(a.megno, b.megno, 1e-6 * (1 + std::abs(b.megno))) << a.values[0] << " " << a.values[1];
  }
  // The origin (rest at the bottom): the linearised flow, two normal modes,
  // tangent vectors bounded — ⟨Y⟩ → 0 and a finite-time λ1 of order
  // ln(their largest stretch)/t_end (measured 0.063 1/s at 20 s, ⟨Y⟩ 0.026);
  // the corners, released with both rods high, chaotic (λ1 1.2 … 1.6 1/s).
  EXPECT_LT(r.records[12].lyapunov_max, 0.1);
  EXPECT_LT(r.records[12].megno, 0.1);
  EXPECT_GT(r.records[0].lyapunov_max, 0.5);
  EXPECT_GT(r.records[0].megno, 5.0);
}
