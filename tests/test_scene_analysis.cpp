// The analyses through the scene layer (scene/analysis.hpp): every built-in
// model either answers (finite numbers) or refuses with a one-line reason —
// never a crash, a hang or a NaN presented as a result; every parameter's
// sensitivity under the name its scene gives it.

#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

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

// Every parameter of every built-in model, named as its scene names it,
// asked for alone from the model's default start over 0.05 s: its column
// (2n finite values under that name), or one of two refusals, each for
// exactly the cases listed: a parameter that moves the constraint manifold
// past the start, and the models whose parameters are arrays of plain
// doubles. A model whose parameter_names drifted from its scene's names
// would fail here ("is not a parameter of the model").
TEST(SceneAnalysis, EveryBuiltInParameterHasItsColumnUnderItsScenesName) {
  const std::set<std::string> moves_the_manifold = {
      "atwood_machine c", "bead_on_rotating_wire omega", "cartesian_double_pendulum l1",
      "cartesian_double_pendulum l2", "particle_on_sphere R"};
  const std::set<std::string> plain_doubles = {"direct_impact", "newtons_cradle", "pendulum_chain_3",
                                               "spheres_in_box"};
  std::set<std::string> refused_manifold, refused_plain;
  int columns = 0;
  for (const scene::ModelInfo& info : scene::builtin_models()) {
    scene::Scene s = model_scene(info.name);
    s.run.t_end = 0.05;
    for (const scene::ParameterInfo& parameter : info.parameters) {
      const std::string what = info.name + " " + parameter.name;
      scene::SensitivityRequest req;
      req.parameters = {parameter.name};
      req.initial_state = false;
      try {
        const scene::SensitivityRun r = scene::sensitivity(s, req);
        ASSERT_EQ(r.result.parameters, std::vector<std::string>{parameter.name}) << what;
        const Eigen::MatrixXd& column = r.result.sensitivities.back();
        EXPECT_EQ(column.rows(), 2 * static_cast<int>(info.coordinates.size())) << what;
        EXPECT_EQ(column.cols(), 1) << what;
        EXPECT_TRUE(column.allFinite()) << what;
        ++columns;
      } catch (const AnalysisError& e) {
        EXPECT_NE(std::string(e.what()).find("parameter '" + parameter.name +
                                             "' moves the constraint manifold past the start"),
                  std::string::npos)
            << what << ": " << e.what();
        refused_manifold.insert(what);
      } catch (const OptionError& e) {
        EXPECT_NE(std::string(e.what()).find("does not offer parameter sensitivities"), std::string::npos)
            << what << ": " << e.what();
        refused_plain.insert(info.name);
      }
    }
  }
  EXPECT_EQ(refused_manifold, moves_the_manifold);
  EXPECT_EQ(refused_plain, plain_doubles);
  std::printf("parameter columns: %d computed, %zu refused as moving the manifold, %zu models of plain doubles\n",
              columns, refused_manifold.size(), refused_plain.size());
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
