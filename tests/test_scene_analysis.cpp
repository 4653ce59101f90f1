// The analyses through the scene layer (scene/analysis.hpp): every built-in
// model either answers (finite numbers) or refuses with a one-line reason —
// never a crash, a hang or a NaN presented as a result.

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "lagrangian/scene/analysis.hpp"
#include "lagrangian/scene/models.hpp"

using namespace lagrangian;

namespace {

scene::Scene model_scene(const std::string& name) {
  scene::Scene s;
  s.name = name;
  s.model = scene::ModelSpec{name, {}, {}, {}};
  return s;
}

}  // namespace

TEST(SceneAnalysis, EveryBuiltInModelAnswersOrRefuses) {
  int answered = 0, refused = 0;
  for (const scene::ModelInfo& info : scene::builtin_models()) {
    scene::AnalysisRequest req;
    req.equilibria = true;
    req.modes = true;
    req.starts = 8;
    try {
      const std::string text = scene::analyse(model_scene(info.name), req);
      EXPECT_NE(text.find("Equilibria"), std::string::npos) << info.name;
      EXPECT_EQ(text.find("nan"), std::string::npos) << info.name << "\n" << text;
      ++answered;
    } catch (const AnalysisError& e) {
      EXPECT_FALSE(std::string(e.what()).empty());
      ++refused;
    }
  }
  EXPECT_GE(answered, 15);  // the pendulums, oscillators, orbits and constrained models
  EXPECT_GE(refused, 3);    // contacts, the knife edge's Pfaffian constraint
  std::printf("equilibria and modes: %d models answered, %d refused\n", answered, refused);
}

TEST(SceneAnalysis, EveryBuiltInModelSolvesOrRefusesABoundaryValueProblem) {
  int solved = 0, refused = 0, failed = 0;
  for (const scene::ModelInfo& info : scene::builtin_models()) {
    scene::BvpRequest req;
    req.from.assign(info.coordinates.size(), 0.5);
    req.to.assign(info.coordinates.size(), 0.6);
    req.t1 = 0.3;
    req.steps = 50;
    try {
      const scene::BvpRun r = scene::solve_bvp(model_scene(info.name), req);
      EXPECT_TRUE(r.result.q.allFinite()) << info.name;
      EXPECT_TRUE(r.result.qd.allFinite()) << info.name;
      EXPECT_LT(r.result.residual, 1e-8) << info.name;
      ++solved;
    } catch (const OptionError& e) {  // constraints, forces, dissipation
      EXPECT_NE(std::string(e.what()).find("solve-bvp"), std::string::npos) << e.what();
      ++refused;
    } catch (const AnalysisError& e) {  // singular or no convergence: a reason, not a NaN
      EXPECT_FALSE(std::string(e.what()).empty());
      ++failed;
    }
  }
  EXPECT_GE(solved, 10);
  EXPECT_GE(refused, 5);
  std::printf("boundary-value problems: %d solved, %d refused, %d failed with a reason\n", solved, refused, failed);
}

TEST(SceneAnalysis, ParticleScenesAndBadRequestsAreRefused) {
  scene::Scene particles;
  particles.name = "ball";
  scene::AnalysisRequest req;
  req.equilibria = true;
  EXPECT_THROW(scene::analyse(particles, req), OptionError);
  req.starts = 0;
  EXPECT_THROW(scene::analyse(model_scene("double_pendulum"), req), OptionError);
  scene::BvpRequest bvp;
  bvp.from = {0.1};
  bvp.to = {0.2, 0.3};
  EXPECT_THROW(scene::solve_bvp(model_scene("harmonic_oscillator"), bvp), OptionError);
  bvp.to = {NAN};
  EXPECT_THROW(scene::solve_bvp(model_scene("harmonic_oscillator"), bvp), OptionError);
  bvp.to = {0.2};
  bvp.t1 = -1;
  EXPECT_THROW(scene::solve_bvp(model_scene("harmonic_oscillator"), bvp), OptionError);
}
