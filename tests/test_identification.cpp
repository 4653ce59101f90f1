// Parameter identification with NLopt: known parameters recovered from
// synthetic records with seeded Gaussian noise.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/identification.hpp"

#include "bounce_record.hpp"
#include "drag_record.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;

constexpr double kNoise = 1e-3;  // m, standard deviation of the synthetic record's noise

using lagrangian::testing::BounceRecord;

TEST(Identification, RestitutionFromANoisyBouncingBall) {
  const BounceRecord record;
  const double e_true = BounceRecord::e_true, interval = BounceRecord::interval;
  const State<3>& x0 = record.x0;
  const Fit fit = fit_restitution(BallAndPlane(0.3, 0.05, 0.0, 9.81), x0, interval, record.heights);
  std::printf("restitution: true %.4f, fitted %.6f, rms residual %.3e m (noise %.1e), %d runs\n", e_true, fit.value,
              fit.rms_residual, kNoise, fit.evaluations);
  EXPECT_NEAR(fit.value, e_true, 2e-3);
  EXPECT_NEAR(fit.rms_residual, kNoise, 0.2 * kNoise);  // the residual is the noise: the model explains the rest
  // Without noise the fit is exact.
  const Fit exact = fit_restitution(BallAndPlane(0.3, 0.05, 0.0, 9.81), x0, interval, record.clean);
  EXPECT_NEAR(exact.value, e_true, 1e-7);
}

// The restitution fits fed by the column of e, which crosses every bounce
// and, for the trial values below about 0.69, the rest a plain run ends the
// bounces with within the record: each reaches the residual BOBYQA
// converged to, and converged they find BOBYQA's e.
TEST(Identification, RestitutionFitsFromTheSensitivityReachTheDerivativeFreeResidual) {
  const BounceRecord r;
  const BallAndPlane trial(0.3, 0.05, 0.0, 9.81);
  const Fit free = fit_restitution(trial, r.x0, BounceRecord::interval, r.heights);
  const double target = free.rms_residual * (1 + 1e-7);
  const Fit free_to_target = fit_restitution(trial, r.x0, BounceRecord::interval, r.heights, {FitMethod::bobyqa, target});
  std::printf("BOBYQA: converged e = %.12f in %d runs, to its residual %.15e m in %d runs\n", free.value,
              free.evaluations, free_to_target.rms_residual, free_to_target.evaluations);
  for (const FitMethod method : {FitMethod::gauss_newton, FitMethod::lbfgs, FitMethod::slsqp}) {
    const char* name = method == FitMethod::gauss_newton ? "Gauss-Newton" : method == FitMethod::lbfgs ? "L-BFGS" : "SLSQP";
    const Fit to_target = fit_restitution(trial, r.x0, BounceRecord::interval, r.heights, {method, target});
    const Fit converged = fit_restitution(trial, r.x0, BounceRecord::interval, r.heights, {method, 0.0});
    std::printf("%s: to BOBYQA's residual in %d runs (e = %.12f, %.15e m); converged e = %.12f in %d runs (%.15e m)\n",
                name, to_target.evaluations, to_target.value, to_target.rms_residual, converged.value,
                converged.evaluations, converged.rms_residual);
    EXPECT_LE(to_target.rms_residual, target) << name;
    EXPECT_NEAR(converged.value, free.value, 1e-6) << name;
    EXPECT_LE(converged.rms_residual, target) << name;
    if (method == FitMethod::gauss_newton) {
      EXPECT_LE(2 * converged.evaluations, free.evaluations);
    }
  }
  // The searches start at e = 0.5, where the ball comes to rest at
  // τ (1 + 2e/(1 − e)) = 3τ = 1.35 s, τ = √(2 (1.05 − R)/g): at 2.5 s it lies
  // on the floor, z = R, ż = 0, whatever e near 0.5, so the column of e
  // carried through the bounces and the rest ends at 0.
  SensitivityOptions so;
  so.run.t_end = 2.5;
  so.initial_state = false;
  so.parameters = {"e"};
  const SensitivityResult at_rest = sensitivities(BallAndPlane(0.3, 0.05, 0.5, 9.81), r.x0, so);
  EXPECT_NEAR(at_rest.states.back()[2], 0.05, 1e-9);
  EXPECT_LE(at_rest.sensitivities.back().cwiseAbs().maxCoeff(), 1e-9) << at_rest.sensitivities.back();
  EXPECT_GT(at_rest.impacts, 10);
}

using lagrangian::testing::DragRecord;

TEST(Identification, DragCoefficientFromANoisyProjectilePath) {
  const DragRecord record;
  const double b_true = DragRecord::b_true;
  const State<2>& x0 = record.x0;
  const double interval = DragRecord::interval;
  const std::vector<double>&xs = record.xs, &ys = record.ys;
  ASSERT_GT(xs.size(), 100u);
  const Fit fit = fit_drag(Projectile<Drag::linear>(0.145, 9.81, 0.0, 0.0), x0, interval, xs, ys, 1.0);
  std::printf("linear drag: true %.5f kg/s, fitted %.7f, rms residual %.3e m, %d runs\n", b_true, fit.value,
              fit.rms_residual, fit.evaluations);
  EXPECT_NEAR(fit.value, b_true, 0.01 * b_true);
  EXPECT_NEAR(fit.rms_residual, std::sqrt(2.0) * kNoise, 0.2 * kNoise);  // two noisy coordinates per sample
}

// The fits fed by the parameter sensitivity against the derivative-free one
// on the same record: each stopped when its residual reaches the one BOBYQA
// converged to gets there, and run to convergence they find the same b.
// Converged against converged, Gauss–Newton takes at most a third of
// BOBYQA's runs (the figure; the NLopt gradient algorithms,
// measured in docs/analysis.md, do not).
TEST(Identification, FitsFromTheSensitivityReachTheDerivativeFreeResidual) {
  const DragRecord r;
  const Projectile<Drag::linear> trial(0.145, 9.81, 0.0, 0.0);
  const Fit free = fit_drag(trial, r.x0, DragRecord::interval, r.xs, r.ys, 1.0);
  // Within 1e-7 of BOBYQA's residual: a run with the sensitivity beside the
  // state is controlled on more components than a plain run, and their
  // residuals at the same b differ by 5.5e-9 of it.
  const double target = free.rms_residual * (1 + 1e-7);
  const Fit free_to_target = fit_drag(trial, r.x0, DragRecord::interval, r.xs, r.ys, 1.0, {FitMethod::bobyqa, target});
  std::printf("BOBYQA: converged b = %.12f in %d runs, to its residual %.15e m in %d runs\n", free.value,
              free.evaluations, free_to_target.rms_residual, free_to_target.evaluations);
  for (const FitMethod method : {FitMethod::gauss_newton, FitMethod::lbfgs, FitMethod::slsqp}) {
    const char* name = method == FitMethod::gauss_newton ? "Gauss-Newton" : method == FitMethod::lbfgs ? "L-BFGS" : "SLSQP";
    const Fit to_target = fit_drag(trial, r.x0, DragRecord::interval, r.xs, r.ys, 1.0, {method, target});
    const Fit converged = fit_drag(trial, r.x0, DragRecord::interval, r.xs, r.ys, 1.0, {method, 0.0});
    std::printf("%s: to BOBYQA's residual in %d runs (b = %.12f, %.15e m); converged b = %.12f in %d runs (%.15e m)\n",
                name, to_target.evaluations, to_target.value, to_target.rms_residual, converged.value,
                converged.evaluations, converged.rms_residual);
    EXPECT_LE(to_target.rms_residual, target) << name;
    EXPECT_NEAR(converged.value, free.value, 1e-8 * free.value) << name;
    EXPECT_LE(converged.rms_residual, target) << name;
    if (method == FitMethod::gauss_newton) {
      EXPECT_LE(3 * converged.evaluations, free.evaluations);
    }
  }
}

TEST(Identification, BadRecordsAreClearErrors) {
  const BallAndPlane ball(0.3, 0.05, 0.0, 9.81);
  State<3> x0;
  x0.q << 0, 0, 1;
  x0.qd.setZero();
  EXPECT_THROW(fit_restitution(ball, x0, 0.01, {}), ParameterError);
  EXPECT_THROW(fit_restitution(ball, x0, -0.01, {1.0, 0.9}), ParameterError);
  try {
    fit_restitution(ball, x0, 0.01, {1.0, std::nan(""), 0.8});
    FAIL() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("fit_restitution: recorded value 1 is nan"), std::string::npos) << e.what();
  }
  const Projectile<Drag::quadratic> p(0.145, 9.81, 0.0, 0.0);
  EXPECT_THROW(fit_drag(p, p.launch(10.0, 0.5), 0.01, {0.0, 0.1}, {0.0}, 1.0), ParameterError);
  EXPECT_THROW(fit_drag(p, p.launch(10.0, 0.5), 0.01, {0.0, 0.1}, {0.0, 0.1}, -1.0), ParameterError);
}

}  // namespace
