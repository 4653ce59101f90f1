// A C++ model given the outputs of `lagrangian run` in one call
// (scene::run_and_write, scene/model_run.hpp).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/models/projectile.hpp"
#include "lagrangian/scene/model_run.hpp"

namespace {

namespace fs = std::filesystem;
using namespace lagrangian;

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
  // A projectile (x, y in m, g along −y) declares its one particle.
  const scene::RunResult r = scene::run_and_write(models::Projectile(0.5, 9.81), s0, run, out);
  // The files, with the model's names and units.
  for (const char* f : {"trajectory.csv", "events.csv", "report.json", "animation.html"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  EXPECT_EQ(first_line(dir / "trajectory.csv").substr(0, 40), "t [s],x [m],y [m],x_dot [m/s],y_dot [m/s");
  std::stringstream report;
  report << std::ifstream(dir / "report.json").rdbuf();
  EXPECT_NE(report.str().find("\"scene\": \"projectile\""), std::string::npos) << report.str().substr(0, 200);
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
  // The simple pendulum's angle places nothing in space by itself.
  const scene::RunResult r = scene::run_and_write(models::SimplePendulum(), s0, run, out);
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
  EXPECT_THROW(scene::run_and_write(models::SimplePendulum(), s0, run, out), scene::SceneError);
  EXPECT_FALSE(fs::exists(dir / "trajectory.csv"));
}

}  // namespace
