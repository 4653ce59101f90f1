// A C++ model given the outputs of `lagrangian run` in one call
// (scene::run_and_write, scene_model_run.hpp).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "lagrangian/scene_model_run.hpp"

namespace {

namespace fs = std::filesystem;
using namespace lagrangian;

/// A ball thrown in a plane (x, y in m, g along −y), written by a user,
/// with its one particle for the page.
struct Throw {
  static constexpr int coordinate_count = 2;
  double m = 0.5, g = 9.81;
  std::string name() const { return "thrown ball"; }
  std::array<std::string, 2> coordinate_names() const { return {"x", "y"}; }
  std::array<std::string, 2> coordinate_units() const { return {"m", "m"}; }
  std::array<Particle, 1> particles() const { return {Particle{m, {0, 1, -1}}}; }
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    return m * g * q[1];
  }
};

/// A pendulum angle alone: nothing placed in space.
struct Swing {
  static constexpr int coordinate_count = 1;
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    return 0.5 * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    using std::cos;
    return -9.81 * cos(q[0]);
  }
};

std::string first_line(const fs::path& p) {
  std::ifstream f(p);
  std::string line;
  std::getline(f, line);
  return line;
}

TEST(RunAndWrite, WritesTheRunOutputsOfACppModel) {
  const fs::path dir = fs::temp_directory_path() / "lagrangian_run_and_write_throw";
  fs::remove_all(dir);
  State<2> s0;
  s0.qd << 3.0, 4.0;
  scene::RunSpec run;
  run.t_end = 0.8;
  run.output_interval = 0.1;
  scene::OutputSpec out;
  out.directory = dir.string();
  out.plots = false;
  const scene::RunResult r = scene::run_and_write(Throw{}, s0, run, out);
  // The files, with the model's names and units.
  for (const char* f : {"trajectory.csv", "events.csv", "report.json", "animation.html"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  EXPECT_EQ(first_line(dir / "trajectory.csv").substr(0, 40), "t [s],x [m],y [m],x_dot [m/s],y_dot [m/s");
  std::stringstream report;
  report << std::ifstream(dir / "report.json").rdbuf();
  EXPECT_NE(report.str().find("\"scene\": \"thrown ball\""), std::string::npos);
  // The motion: x = 3t, y = 4t − g t²/2 at t = 0.8 s.
  ASSERT_EQ(r.q_final.size(), 2u);
  EXPECT_NEAR(r.q_final[0], 2.4, 1e-9);
  EXPECT_NEAR(r.q_final[1], 3.2 - 0.5 * 9.81 * 0.64, 1e-9);
  EXPECT_TRUE(r.report.conservative);
  fs::remove_all(dir);
}

TEST(RunAndWrite, AModelWithoutParticlesGetsNoPageAndSaysSo) {
  const fs::path dir = fs::temp_directory_path() / "lagrangian_run_and_write_swing";
  fs::remove_all(dir);
  State<1> s0;
  s0.q << 0.3;
  scene::OutputSpec out;
  out.directory = dir.string();
  out.plots = false;
  scene::RunSpec run;
  run.t_end = 1.0;
  const scene::RunResult r = scene::run_and_write(Swing{}, s0, run, out);
  EXPECT_TRUE(fs::exists(dir / "trajectory.csv"));
  EXPECT_FALSE(fs::exists(dir / "animation.html"));
  EXPECT_NE(r.animation_note.find("declares no particles()"), std::string::npos) << r.animation_note;
  fs::remove_all(dir);
}

TEST(RunAndWrite, BadOptionsAreSceneErrorsAndLeaveNothing) {
  const fs::path dir = fs::temp_directory_path() / "lagrangian_run_and_write_bad";
  fs::remove_all(dir);
  scene::RunSpec run;
  run.t_end = -1.0;
  scene::OutputSpec out;
  out.directory = dir.string();
  State<1> s0;
  EXPECT_THROW(scene::run_and_write(Swing{}, s0, run, out), scene::SceneError);
  EXPECT_FALSE(fs::exists(dir / "trajectory.csv"));
}

}  // namespace
