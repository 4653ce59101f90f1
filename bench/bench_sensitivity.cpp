// What sensitivities cost (docs/performance.md, docs/analysis.md):
//  1. the double pendulum from (1.2, −0.4) rad, (0.3, 0.8) rad/s over 5 s,
//     dopri5 at rtol 1e-10: a plain run, the state transition matrix (4
//     columns), and it with the five parameters' columns, against central
//     differences of plain runs (2 runs per column) at the same tolerance,
//     each side's error measured against the sensitivities at rtol 1e-13;
//  2. fit_drag() and fit_restitution() on the records of
//     tests/test_identification.cpp by each FitMethod: runs and wall time
//     per fit (the restitution fits' runs cross the ball's bounces and, for
//     trial values below about 0.69, its rest);
//  3. across impacts: a ball (e = 0.75) on a tilted plane, two bounces in
//     1.4 s, dopri5 at rtol 1e-10: a plain run, Φ (6 columns, each impact
//     crossed by its saltation matrix) and central differences of plain
//     runs (12), errors against Φ at rtol 1e-13.
// Usage: bench_sensitivity [REPEATS] (default 3)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/integrate/observers.hpp"
#include "lagrangian/integrate/simulate.hpp"
#include "lagrangian/models/identification.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/models/pendulums.hpp"

#include "bounce_record.hpp"
#include "drag_record.hpp"
#include "final_state.hpp"

namespace {

namespace lm = lagrangian::models;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

using lagrangian::testing::final_state;

/// Φ = ∂x(T)/∂x(0) (2n × 2n) by central differences of plain runs, each
/// component of the start moved by ±h.
template <class M>
Eigen::MatrixXd state_by_differences(const M& m, const lagrangian::State<lagrangian::coordinate_count_v<M>>& s,
                                     const lagrangian::SimulationOptions& o, double h) {
  constexpr int n = lagrangian::coordinate_count_v<M>;
  Eigen::MatrixXd out(2 * n, 2 * n);
  for (int j = 0; j < 2 * n; ++j) {
    auto up = s, down = s;
    (j < n ? up.q[j] : up.qd[j - n]) += h;
    (j < n ? down.q[j] : down.qd[j - n]) -= h;
    out.col(j) = (final_state(m, up, o) - final_state(m, down, o)) / (2 * h);
  }
  return out;
}

/// The sensitivities of `o` at t_end computed at rtol 1e-13, atol 1e-15: the
/// reference both sides' errors are measured against.
template <class M>
Eigen::MatrixXd reference_of(const M& m, const lagrangian::State<lagrangian::coordinate_count_v<M>>& s,
                             lagrangian::SensitivityOptions o) {
  o.run.rtol = 1e-13;
  o.run.atol = 1e-15;
  return lagrangian::sensitivities(m, s, o).sensitivities.back();
}

/// The 4 × 9 matrix [Φ | ∂x/∂p] by central differences of plain runs.
Eigen::MatrixXd by_differences(const double (&p)[5], const lagrangian::State<2>& s,
                               const lagrangian::SimulationOptions& o) {
  Eigen::MatrixXd out(4, 9);
  const double h = 1e-5;
  out.leftCols(4) = state_by_differences(lm::DoublePendulum(p[0], p[1], p[2], p[3], p[4]), s, o, h);
  for (int j = 0; j < 5; ++j) {
    double up[5], down[5];
    for (int i = 0; i < 5; ++i) up[i] = down[i] = p[i];
    up[j] += h * p[j];
    down[j] -= h * p[j];
    out.col(4 + j) = (final_state(lm::DoublePendulum(up[0], up[1], up[2], up[3], up[4]), s, o) -
                      final_state(lm::DoublePendulum(down[0], down[1], down[2], down[3], down[4]), s, o)) /
                     (2 * h * p[j]);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 3;
  const double p[5] = {1.3, 0.8, 1.1, 0.7, 9.81};
  const lm::DoublePendulum dp(p[0], p[1], p[2], p[3], p[4]);
  lagrangian::State<2> s;
  s.q << 1.2, -0.4;
  s.qd << 0.3, 0.8;
  lagrangian::SensitivityOptions o;
  o.run.t_end = 5.0;
  o.run.rtol = 1e-10;
  o.run.atol = 1e-12;
  o.run.output_interval = -1;
  o.parameters = {"m1", "m2", "l1", "l2", "g"};
  const Eigen::MatrixXd reference = reference_of(dp, s, o);
  const double scale = reference.cwiseAbs().maxCoeff();
  std::printf("double pendulum, 5 s, dopri5 at rtol 1e-10; errors against rtol 1e-13, relative to the largest "
              "entry (%.1f)\n",
              scale);
  for (int r = 0; r < repeats; ++r) {
    auto start = Clock::now();
    const lagrangian::RunReport plain = lagrangian::simulate(dp, s, o.run);
    const double t_plain = since(start);
    lagrangian::SensitivityOptions phi_only = o;
    phi_only.parameters.clear();
    const lagrangian::SensitivityResult phi = lagrangian::sensitivities(dp, s, phi_only);
    const lagrangian::SensitivityResult all = lagrangian::sensitivities(dp, s, o);
    start = Clock::now();
    const Eigen::MatrixXd fd = by_differences(p, s, o.run);
    const double t_fd = since(start);
    const Eigen::MatrixXd& got = all.sensitivities.back();
    std::printf("  plain run %.2f ms (%llu steps); Phi (4 columns) %.2f ms = %.1fx (%llu steps), error %.1e; "
                "Phi and 5 parameters %.2f ms = %.1fx (%llu steps), error %.1e; central differences (18 runs) "
                "%.2f ms = %.1fx, error %.1e\n",
                1e3 * t_plain, static_cast<unsigned long long>(plain.steps), 1e3 * phi.seconds, phi.seconds / t_plain,
                static_cast<unsigned long long>(phi.steps),
                (phi.sensitivities.back() - reference.leftCols(4)).cwiseAbs().maxCoeff() / scale, 1e3 * all.seconds,
                all.seconds / t_plain, static_cast<unsigned long long>(all.steps),
                (got - reference).cwiseAbs().maxCoeff() / scale, 1e3 * t_fd, t_fd / t_plain,
                (fd - reference).cwiseAbs().maxCoeff() / scale);
  }

  // The records of tests/test_identification.cpp: each fit `fits` times by
  // each method, per fit and per run.
  const char* names[] = {"BOBYQA", "Gauss-Newton", "L-BFGS", "SLSQP"};
  const auto time_fits = [&](const char* label, int fits, const auto& fit) {
    for (int r = 0; r < repeats; ++r) {
      std::printf("%s, %d fits each:", label, fits);
      for (const lm::FitMethod m :
           {lm::FitMethod::bobyqa, lm::FitMethod::gauss_newton, lm::FitMethod::lbfgs, lm::FitMethod::slsqp}) {
        lm::Fit f;
        const auto start = Clock::now();
        for (int i = 0; i < fits; ++i) f = fit(lm::FitOptions{m, 0.0});
        const double per_fit = since(start) / fits;
        std::printf("  %s %.3f ms (%d runs, %.0f us each)", names[static_cast<int>(m)], 1e3 * per_fit, f.evaluations,
                    1e6 * per_fit / f.evaluations);
      }
      std::printf("\n");
    }
  };
  const lagrangian::testing::DragRecord record;
  const lm::Projectile<lm::Drag::linear> trial(0.145, 9.81, 0.0, 0.0);
  time_fits("fit_drag", 50, [&](const lm::FitOptions& options) {
    return lm::fit_drag(trial, record.x0, 0.02, record.xs, record.ys, 1.0, options);
  });
  const lagrangian::testing::BounceRecord bounces;
  const lm::BallAndPlane ball_trial(0.3, 0.05, 0.0, 9.81);
  time_fits("fit_restitution", 20, [&](const lm::FitOptions& options) {
    return lm::fit_restitution(ball_trial, bounces.x0, bounces.interval, bounces.heights, options);
  });

  // Across impacts.
  const lm::BallAndPlane ball(1.0, 0.1, 0.75, 9.81, {0.4, 0.0, 1.0}, 0.0);
  lagrangian::State<3> b;
  b.q << 0.3, 0.1, 1.2;
  b.qd << -0.5, 0.2, 0.4;
  lagrangian::SensitivityOptions bo;
  bo.run.t_end = 1.4;
  bo.run.rtol = 1e-10;
  bo.run.atol = 1e-12;
  const Eigen::MatrixXd bref = reference_of(ball, b, bo);
  const double bscale = bref.cwiseAbs().maxCoeff();
  std::printf("ball on a tilted plane, two bounces in 1.4 s, dopri5 at rtol 1e-10; errors against rtol 1e-13, "
              "relative to the largest entry (%.1f)\n",
              bscale);
  for (int r = 0; r < repeats; ++r) {
    const int runs = 200;
    auto start = Clock::now();
    lagrangian::RunReport plain;
    for (int i = 0; i < runs; ++i) plain = lagrangian::simulate(ball, b, bo.run);
    const double t_plain = since(start) / runs;
    start = Clock::now();
    lagrangian::SensitivityResult phi;
    for (int i = 0; i < runs; ++i) phi = lagrangian::sensitivities(ball, b, bo);
    const double t_phi = since(start) / runs;
    start = Clock::now();
    Eigen::MatrixXd fd;
    for (int i = 0; i < runs / 10; ++i) fd = state_by_differences(ball, b, bo.run, 1e-6);
    const double t_fd = since(start) / (runs / 10);
    std::printf("  plain run %.1f us (%llu steps, %zu events); Phi (6 columns, %d impacts) %.1f us = %.1fx (%llu "
                "steps), error %.1e; central differences (12 runs) %.1f us = %.1fx, error %.1e\n",
                1e6 * t_plain, static_cast<unsigned long long>(plain.steps), plain.events.size(), phi.impacts,
                1e6 * t_phi, t_phi / t_plain, static_cast<unsigned long long>(phi.steps),
                (phi.sensitivities.back() - bref).cwiseAbs().maxCoeff() / bscale, 1e6 * t_fd, t_fd / t_plain,
                (fd - bref).cwiseAbs().maxCoeff() / bscale);
  }
}
