// The monodromy matrix by the variational equations, run by the one driver,
// and periodic orbits found by Newton's method on it
// (lagrangian/analysis/floquet.hpp).

#include "lagrangian/analysis/floquet.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/QR>

#include "tangent_run.hpp"
#include "tangent_system.hpp"

namespace lagrangian::detail {
namespace {

void check_positive(const char* name, double value, const char* unit) {
  if (!std::isfinite(value) || !(value > 0)) {
    std::ostringstream os;
    os << "floquet: " << name << " = " << value << unit << " must be finite and > 0";
    throw OptionError(os.str());
  }
}

void check_tolerance(double tolerance) {
  if (!std::isfinite(tolerance) || !(tolerance >= 0)) {
    std::ostringstream os;
    os << "floquet: tolerance = " << tolerance << " must be finite and >= 0";
    throw OptionError(os.str());
  }
}

/// One period T from (q0, q̇0) with the 2n columns of Φ: the monodromy
/// matrix, the closure and the cost into `result`, the state at t0 + T into
/// x_end (2n values), the basis B0 the monodromy is taken in into `basis`
/// (manifold_basis(): the identity without constraints).
void monodromy(const TangentModel& model, const double* q0, const double* qd0, SimulationOptions run, double period,
               FloquetResult& result, Eigen::VectorXd& x_end, Eigen::MatrixXd& basis) {
  const int n = model.n;
  run.t_end = run.t0 + period;
  run.output_interval = -1;
  // On a constraint manifold: Φ on its tangent space, in the basis B0 of
  // the start's (orthonormal): C = B0ᵀ Φ B0 (d × d), the tangent vectors at
  // t0 + T projected back onto the start's tangent space, which they span
  // when the motion closes.
  basis = manifold_basis(model, q0, qd0, run.t0);
  if (basis.cols() == 0)
    throw AnalysisError(
        "floquet: the constraints leave no motion (the constraint manifold's tangent space has dimension 0)");
  TangentSystem system(model, static_cast<int>(basis.cols()), 0.0, false);
  const int c = system.coordinate_count();
  std::vector<double> x;
  RunReport report;
  integrate_tangents(system, n, q0, qd0, run, "floquet: the run stopped before t0 + period", x, report);
  result.monodromy = model.manifold > 0 ? Eigen::MatrixXd(basis.transpose() * system.tangents(x.data()))
                                        : system.tangents(x.data());
  x_end.resize(2 * n);
  result.closure = 0;
  for (int i = 0; i < n; ++i) {
    x_end[i] = x[static_cast<std::size_t>(i)];
    x_end[n + i] = x[static_cast<std::size_t>(c + i)];
    result.closure = std::max(result.closure, std::abs(x_end[i] - q0[i]));
    result.closure = std::max(result.closure, std::abs(x_end[n + i] - qd0[i]));
  }
  result.steps += report.steps;
  result.rhs_evaluations += system.evaluations();
  result.impacts = system.impacts();
}

/// The eigenvalues of result.monodromy, largest modulus first, and the
/// verdict.
void multipliers(FloquetResult& result, double tolerance) {
  const Eigen::EigenSolver<Eigen::MatrixXd> eigen(result.monodromy, false);
  if (eigen.info() != Eigen::Success)
    throw AnalysisError("floquet: the eigenvalues of the monodromy matrix did not converge");
  result.multipliers.clear();
  for (int i = 0; i < result.monodromy.rows(); ++i) result.multipliers.push_back(eigen.eigenvalues()[i]);
  std::sort(result.multipliers.begin(), result.multipliers.end(),
            [](const std::complex<double>& a, const std::complex<double>& b) { return std::abs(a) > std::abs(b); });
  result.largest_modulus = std::abs(result.multipliers.front());
  result.stable = result.largest_modulus <= 1 + tolerance;
}

/// ẋ = (q̇, q̈) at the state x (2n values) and time t.
Eigen::VectorXd rate(const TangentModel& model, const Eigen::VectorXd& x, double t) {
  const int n = model.n;
  Eigen::VectorXd f(2 * n), zero = Eigen::VectorXd::Zero(2 * n), unused(n);
  f.head(n) = x.tail(n);
  model.evaluate_direction(model.model, x.data(), x.data() + n, t, zero.data(), f.data() + n, unused.data());
  return f;
}

}  // namespace

/// ∇E at the state x (2n values) for E = p·q̇ − L, p = ∂L/∂q̇: with
/// C = ∂p/∂q and M = ∂p/∂q̇,
///   ∂E/∂q = Cᵀ q̇ − ∂L/∂q,   ∂E/∂q̇ = M q̇,
/// from L's derivatives alone (no equation of motion, so no constraint
/// force enters).
Eigen::VectorXd energy_gradient(const TangentModel& model, const Eigen::VectorXd& x, double t) {
  const int n = model.n;
  Eigen::MatrixXd dp(n, 2 * n);
  Eigen::VectorXd dl_dq(n);
  model.momentum(model.model, x.data(), x.data() + n, t, dp.data(), dl_dq.data());
  const Eigen::VectorXd qd = x.tail(n);
  Eigen::VectorXd g(2 * n);
  g.head(n) = dp.leftCols(n).transpose() * qd - dl_dq;
  g.tail(n) = dp.rightCols(n) * qd;
  return g;
}

FloquetResult floquet_multipliers(const TangentModel& model, const double* q0, const double* qd0,
                                  const FloquetOptions& options) {
  check_positive("period", options.period, " s");
  check_tolerance(options.tolerance);
  SimulationOptions run = options.run;
  run.t_end = run.t0 + options.period;
  run.output_interval = -1;
  check_tangent_run(run, "floquet");
  if (options.find_orbit) {
    check_positive("closure_tolerance", options.closure_tolerance, "");
    if (options.max_iterations < 1) {
      std::ostringstream os;
      os << "floquet: max_iterations = " << options.max_iterations << " must be >= 1";
      throw OptionError(os.str());
    }
  }
  const int n = model.n;
  const auto clock_start = std::chrono::steady_clock::now();

  FloquetResult f;
  Eigen::VectorXd x0(2 * n), x_end;
  Eigen::MatrixXd basis;  // B0 of the last monodromy (the identity without constraints)
  for (int i = 0; i < n; ++i) {
    x0[i] = q0[i];
    x0[n + i] = qd0[i];
  }
  double period = options.period;
  for (int iteration = 1;; ++iteration) {
    monodromy(model, x0.data(), x0.data() + n, run, period, f, x_end, basis);
    if (!options.find_orbit) break;
    f.iterations = iteration;
    if (f.closure <= options.closure_tolerance * (1 + x0.cwiseAbs().maxCoeff())) break;
    if (iteration == options.max_iterations) {
      std::ostringstream os;
      os.precision(6);
      os << "floquet: no periodic orbit found: after " << iteration << " Newton iterations the motion from the last "
         << "start misses it by " << f.closure << " after " << period << " s (closure_tolerance "
         << options.closure_tolerance << "); start closer to an orbit, or give a better period";
      throw AnalysisError(os.str());
    }
    // Newton on x(t0 + T; x0) − x0 = 0: 2n equations (d on a manifold) in δx0 and, with a
    // free period, δT, with the phase condition f(x0)·δx0 = 0 and, for a
    // conservative system, ∇E(x0)·δx0 = 0 (its orbits come in families,
    // one per energy, and the rest point is one of them: the energy row
    // keeps the start's). Least squares with the minimum-norm solution
    // (complete orthogonal decomposition). On a constraint manifold the
    // start moves in its tangent space, δx0 = B0 δ (B0 the orthonormal basis
    // of the monodromy matrix C = B0ᵀ Φ B0), the equations are those
    // projected on it, B0ᵀ (x(t0 + T) − x0) + (C − I) δ + B0ᵀ f(x_end) δT = 0,
    // and the new start is projected back onto the manifold. (The energy
    // row is ∇E from L itself, energy_gradient(): E is conserved under
    // holonomic rows g(q) and Pfaffian rows A(q) q̇ = 0, whose forces do no
    // work on the motion.)
    const int d = static_cast<int>(basis.cols());
    const int unknowns = options.fixed_period ? d : d + 1;
    const int rows = options.fixed_period ? d : d + (options.keep_energy ? 2 : 1);
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, unknowns);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(rows);
    a.topLeftCorner(d, d) = f.monodromy - Eigen::MatrixXd::Identity(d, d);
    b.head(d) = basis.transpose() * (x0 - x_end);
    if (!options.fixed_period) {
      a.block(0, d, d, 1) = basis.transpose() * rate(model, x_end, run.t0 + period);
      const Eigen::VectorXd f0 = rate(model, x0, run.t0);
      a.block(d, 0, 1, d) = (basis.transpose() * f0).transpose();
      if (options.keep_energy)
        a.block(d + 1, 0, 1, d) = (basis.transpose() * energy_gradient(model, x0, run.t0)).transpose();
    }
    const Eigen::VectorXd step = a.completeOrthogonalDecomposition().solve(b);
    if (!step.allFinite()) throw AnalysisError("floquet: the Newton step for the periodic orbit is not finite");
    x0 += basis * step.head(d);
    if (model.manifold > 0) {
      try {
        model.project(model.model, x0.data(), x0.data() + n, run.t0);
      } catch (const ConstraintError& e) {
        throw AnalysisError(std::string("floquet: no periodic orbit found: the Newton step's start could not be "
                                        "projected back onto the constraint manifold (") +
                            e.what() + "); start closer to an orbit, or give a better period");
      }
    }
    if (!options.fixed_period) period += step[d];
    // Every motion closes as T → 0: a period that leaves [T/2, 2T] of the
    // guess is Newton walking off to that, not an orbit near the guess.
    if (!(period >= 0.5 * options.period && period <= 2 * options.period)) {
      std::ostringstream os;
      os << "floquet: no periodic orbit found: the period's Newton iterate went to " << period
         << " s, outside [T/2, 2T] of the guess T = " << options.period << " s; give a better period or start";
      throw AnalysisError(os.str());
    }
  }
  multipliers(f, options.tolerance);
  f.q.assign(x0.data(), x0.data() + n);
  f.qd.assign(x0.data() + n, x0.data() + 2 * n);
  f.period = period;
  f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_start).count();
  return f;
}

}  // namespace lagrangian::detail
