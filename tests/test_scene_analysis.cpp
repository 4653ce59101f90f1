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

/// The model's scene run to t_end at rtol 1e-12, atol 1e-14.
scene::Scene tight_scene(const std::string& name, double t_end) {
  scene::Scene s = model_scene(name);
  s.run.t_end = t_end;
  s.run.rtol = 1e-12;
  s.run.atol = 1e-14;
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
// past the start, and a start whose contacts are shut (Newton's cradle with
// its spheres touching, where no tangent flow is derived, parameters or
// not). No model is refused for parameters of plain doubles. A model whose
// parameter names drifted from its scene's would fail here (the registry's
// std::logic_error: a scene parameter that is none of the model's).
TEST(SceneAnalysis, EveryBuiltInParameterHasItsColumnUnderItsScenesName) {
  const std::set<std::string> moves_the_manifold = {
      "atwood_machine c", "bead_on_rotating_wire omega", "cartesian_double_pendulum l1",
      "cartesian_double_pendulum l2", "particle_on_sphere R"};
  const std::set<std::string> shut_at_the_start = {"newtons_cradle e", "newtons_cradle m", "newtons_cradle r"};
  std::set<std::string> refused_manifold, refused_shut;
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
      } catch (const SimulationError& e) {
        EXPECT_NE(std::string(e.what()).find("the tangent flow through a closed contact is not derived"),
                  std::string::npos)
            << what << ": " << e.what();
        refused_shut.insert(what);
      }
    }
  }
  EXPECT_EQ(refused_manifold, moves_the_manifold);
  EXPECT_EQ(refused_shut, shut_at_the_start);
  std::printf("parameter columns: %d computed, %zu refused as moving the manifold, %zu at a shut contact\n", columns,
              refused_manifold.size(), refused_shut.size());
}

// pendulum_chain_3 names one mass m and one rod length l for its three
// links: their columns are the sums of the model's per-link ones (m1 … m3,
// l1 … l3). From rest only g/l sets the motion, q(t) = Θ(t √(g/l)), so
// ∂q/∂g = t q̇/(2g), l ∂x/∂l = −g ∂x/∂g and ∂x/∂m = 0 (the per-link forms
// are in test_sensitivity.cpp). With the initial state's columns in front,
// the summed columns follow them unchanged; a per-link name is not the
// scene's.
TEST(SceneAnalysis, OneValueForEveryLinkHasTheSumOfTheLinksColumns) {
  scene::Scene s = tight_scene("pendulum_chain_3", 1.5);
  scene::SensitivityRequest req;
  req.parameters = {"l", "m", "g"};
  req.initial_state = false;
  const scene::SensitivityRun r = scene::sensitivity(s, req);
  ASSERT_EQ(r.result.parameters, (std::vector<std::string>{"l", "m", "g"}));
  const Eigen::MatrixXd& c = r.result.sensitivities.back();
  ASSERT_EQ(c.cols(), 3);
  const Eigen::VectorXd x = r.result.states.back();
  const double g = 9.81, l = 1.0, T = 1.5;
  const Eigen::VectorXd q_along_g = T * x.tail(3) / (2 * g);
  const double scale = c.col(0).cwiseAbs().maxCoeff();
  std::printf("pendulum_chain_3 from the scene: dq/dg %.2e from t q'/(2g), l d/dl + g d/dg %.2e, d/dm %.2e "
              "(entries up to %.2f)\n",
              (c.col(2).head(3) - q_along_g).cwiseAbs().maxCoeff(), (l * c.col(0) + g * c.col(2)).cwiseAbs().maxCoeff(),
              c.col(1).cwiseAbs().maxCoeff(), scale);
  EXPECT_GT(scale, 0.1);
  EXPECT_LE((c.col(2).head(3) - q_along_g).cwiseAbs().maxCoeff(), 1e-8 * scale);
  EXPECT_LE((l * c.col(0) + g * c.col(2)).cwiseAbs().maxCoeff(), 1e-8 * scale);
  EXPECT_LE(c.col(1).cwiseAbs().maxCoeff(), 1e-8 * scale);

  // Φ first, then the summed columns: Φ as a run without parameters gives
  // it, the columns as above (the error control now also weighs Φ: to the
  // tolerance).
  req.initial_state = true;
  const scene::SensitivityRun full = scene::sensitivity(s, req);
  req.parameters.clear();
  const scene::SensitivityRun phi = scene::sensitivity(s, req);
  const Eigen::MatrixXd& f = full.result.sensitivities.back();
  ASSERT_EQ(f.cols(), 6 + 3);
  const double phi_scale = phi.result.sensitivities.back().cwiseAbs().maxCoeff();
  EXPECT_LE((f.leftCols(6) - phi.result.sensitivities.back()).cwiseAbs().maxCoeff(), 1e-8 * phi_scale);
  EXPECT_LE((f.rightCols(3) - c).cwiseAbs().maxCoeff(), 1e-8 * scale) << f.rightCols(3) << "\n\n" << c;

  req.parameters = {"m1"};
  req.initial_state = false;
  try {
    (void)scene::sensitivity(s, req);
    FAIL() << "a per-link parameter was taken for the scene's";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("'m1' is not a parameter of the model (m, l, g)"), std::string::npos)
        << e.what();
  }
}

// newtons_cradle's one m and one r for its five spheres, started with its
// gaps open (0.025 m each; sphere 1 at 1 m/s, e = 1): each impact hands the
// whole velocity on, every sphere but the last stops after crossing its
// gap, and the last leaves at 1 m/s once all four gaps are crossed. One r
// for all narrows each gap by 2 dr: spheres 1–4 end 2 dr short, sphere 5
// 8 dr ahead (test_impact_sensitivity.cpp has each sphere's radius); only
// mass ratios enter, so m's column is zero.
TEST(SceneAnalysis, NewtonsCradleWithOpenGapsHasTheSumOfTheSpheresColumns) {
  scene::Scene s = tight_scene("newtons_cradle", 0.3);
  s.model->q = {0.0, 0.05, 0.1, 0.15, 0.2};
  s.model->qd = {1.0, 0.0, 0.0, 0.0, 0.0};
  scene::SensitivityRequest req;
  req.parameters = {"r", "m"};
  req.initial_state = false;
  const scene::SensitivityRun r = scene::sensitivity(s, req);
  ASSERT_EQ(r.result.parameters, (std::vector<std::string>{"r", "m"}));
  EXPECT_EQ(r.result.impacts, 4);
  const Eigen::MatrixXd& c = r.result.sensitivities.back();
  Eigen::VectorXd expected = Eigen::VectorXd::Zero(10);
  expected << -2, -2, -2, -2, 8, 0, 0, 0, 0, 0;
  std::printf("newtons_cradle from the scene, gaps open: d/dr %.2e from the closed form, d/dm %.2e\n",
              (c.col(0) - expected).cwiseAbs().maxCoeff(), c.col(1).cwiseAbs().maxCoeff());
  EXPECT_LE((c.col(0) - expected).cwiseAbs().maxCoeff(), 1e-9) << c.col(0);
  EXPECT_LE(c.col(1).cwiseAbs().maxCoeff(), 1e-9) << c.col(1);
}

// spheres_in_box's one m for its three discs under gravity (9.81 m/s²
// along −y): T and V both scale with the masses, so m's column is zero;
// one r moves every impact. Over 1 s the last step, after an impact at
// 0.991 s, ends within rounding of t_end, which the loops count as t_end:
// the tangent run did not, and stopped with "the run stopped before
// t_end" (tangent_run.hpp).
TEST(SceneAnalysis, DiscsInABoxHaveNoColumnOfTheirCommonMass) {
  scene::Scene box = tight_scene("spheres_in_box", 1.0);
  box.model->parameters["g"] = 9.81;
  scene::SensitivityRequest req;
  req.parameters = {"m", "r"};
  req.initial_state = false;
  const scene::SensitivityRun b = scene::sensitivity(box, req);
  ASSERT_EQ(b.result.parameters, (std::vector<std::string>{"m", "r"}));
  const Eigen::MatrixXd& bc = b.result.sensitivities.back();
  std::printf("spheres_in_box from the scene under gravity (%d impacts): d/dm %.2e, d/dr up to %.2f\n",
              b.result.impacts, bc.col(0).cwiseAbs().maxCoeff(), bc.col(1).cwiseAbs().maxCoeff());
  EXPECT_GE(b.result.impacts, 2);
  EXPECT_GT(bc.col(1).cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LE(bc.col(0).cwiseAbs().maxCoeff(), 1e-8 * bc.col(1).cwiseAbs().maxCoeff());
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
