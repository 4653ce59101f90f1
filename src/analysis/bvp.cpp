// Boundary-value problems by stationary discrete action (bvp.hpp) on the
// ActionModel interface, compiled once: Newton's method on the discrete
// Euler–Lagrange equations with a sparse LDLᵀ of the block-tridiagonal
// Hessian of S_d, its inertia and spectrum, and the NLopt minimisation of
// the same action for comparison.

#include "lagrangian/analysis/bvp.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <nlopt.h>

#include "lagrangian/errors.hpp"

namespace lagrangian::detail {

namespace {

/// The end points, the time span, the number of steps and the guess, each
/// with an OptionError naming it.
void check_bvp_input(int n, const Eigen::VectorXd& a, const Eigen::VectorXd& b, double t0, double t1,
                     const BvpOptions& options) {
  const int K = options.steps;
  if (!a.allFinite()) throw OptionError("stationary action: from: not finite");
  if (!b.allFinite()) throw OptionError("stationary action: to: not finite");
  if (!std::isfinite(t0) || !std::isfinite(t1) || !(t1 > t0))
    throw OptionError("stationary action: time: need finite t0 < t1, got t0 = " + std::to_string(t0) +
                      " s, t1 = " + std::to_string(t1) + " s");
  if (K < 2) throw OptionError("stationary action: steps: need at least 2, got " + std::to_string(K));
  if (options.guess.size() != 0 && (options.guess.rows() != K + 1 || options.guess.cols() != n))
    throw OptionError("stationary action: guess: must be (steps + 1) x n");
}

/// The Morse index (negative eigenvalues of the Hessian of S_d, from its
/// LDLᵀ by Sylvester's law of inertia), and for small problems the lowest
/// and the smallest-magnitude eigenvalue against those of a free particle
/// on the same grid; an AnalysisError naming the conjugate point when the
/// Hessian is singular.
void judge_spectrum(const ActionModel& model, const Eigen::VectorXd& a, double t0, double t1,
                    const Eigen::SparseMatrix<double>& H, Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& ldlt,
                    const BvpOptions& options, BvpResult& out) {
  const int K = options.steps;
  const int N = static_cast<int>(H.rows());
  const double h = (t1 - t0) / K;
  // Morse index from the LDLᵀ factorisation of the Hessian at the solution
  // (Sylvester's law of inertia: the permutation is symmetric).
  ldlt.compute(H);
  if (ldlt.info() == Eigen::Success) {
    const Eigen::VectorXd D = ldlt.vectorD();
    out.negative_eigenvalues = static_cast<int>((D.array() < 0).count());
  }
  Eigen::MatrixXd Ma;
  Eigen::VectorXd p0;
  model.at_rest(a.data(), t0, Ma, p0);
  Eigen::VectorXd ev;
  symmetric_eigenvalues(Ma, ev);
  const double pi = 3.141592653589793;
  out.free_reference = ev[0] * (4.0 / h) * std::pow(std::sin(pi / (2.0 * K)), 2);
  if (N <= options.max_dense_eigen && Eigen::Map<const Eigen::VectorXd>(H.valuePtr(), H.nonZeros()).allFinite() &&
      symmetric_eigenvalues(Eigen::MatrixXd(H), ev)) {
    out.eigenvalues_computed = true;
    out.lowest_eigenvalue = ev[0];
    out.smallest_magnitude = ev.cwiseAbs().minCoeff();
    out.negative_eigenvalues = static_cast<int>((ev.array() < 0).count());
  }
  std::ostringstream why;
  why.precision(6);
  const bool singular = out.eigenvalues_computed
                            ? out.smallest_magnitude < options.singular_fraction * out.free_reference
                            : ldlt.info() != Eigen::Success;
  if (singular) {
    why << "stationary action: the boundary-value problem is singular over t1 - t0 = " << (t1 - t0)
        << " s (a conjugate point: the Hessian of the discrete action has an eigenvalue " << out.smallest_magnitude
        << " in magnitude, below " << options.singular_fraction << " x " << out.free_reference
        << ", the lowest eigenvalue of a free particle on the same grid); the path between the two end points is "
           "not unique or does not exist — change the time span or the end points";
    throw AnalysisError(why.str());
  }
}

/// The path of Q (one node per column), its momenta p_k = ∂S_d/∂q_k at the
/// nodes, the velocities M⁻¹(p − p₀) and the energy there, and the action.
void recover_path(const ActionModel& model, const Eigen::MatrixXd& Q, const std::vector<SegmentDerivatives>& seg,
                  double t0, double t1, BvpResult& out) {
  const int n = static_cast<int>(Q.rows());
  const int K = static_cast<int>(Q.cols()) - 1;
  const double h = (t1 - t0) / K;
  Eigen::VectorXd p0;
  // Path, momenta, velocities, energy.
  out.t.resize(static_cast<std::size_t>(K + 1));
  out.q = Q.transpose();
  out.p.resize(K + 1, n);
  out.qd.resize(K + 1, n);
  out.energy.resize(static_cast<std::size_t>(K + 1));
  out.action = 0;
  for (int k = 0; k < K; ++k) out.action += seg[static_cast<std::size_t>(k)].value;
  Eigen::MatrixXd Mk;
  for (int k = 0; k <= K; ++k) {
    out.t[static_cast<std::size_t>(k)] = k == K ? t1 : t0 + k * h;
    const Eigen::VectorXd pk = k == 0 ? Eigen::VectorXd(-seg[0].d1) : seg[static_cast<std::size_t>(k - 1)].d2;
    out.p.row(k) = pk.transpose();
    const double tk = out.t[static_cast<std::size_t>(k)];
    model.at_rest(Q.col(k).data(), tk, Mk, p0);
    const Eigen::LLT<Eigen::MatrixXd> llt(Mk);
    const Eigen::VectorXd v = llt.solve(pk - p0);
    if (llt.info() != Eigen::Success || !v.allFinite()) {
      std::ostringstream os;
      os.precision(17);
      os << "stationary action: the path was found, but the mass matrix is singular at node " << k << " ("
         << describe_state<Eigen::Dynamic>(Q.col(k), Eigen::VectorXd::Zero(n), tk)
         << "), so the velocities there cannot be recovered from the momenta";
      throw AnalysisError(os.str());
    }
    out.qd.row(k) = v.transpose();
    out.energy[static_cast<std::size_t>(k)] = model.energy(Q.col(k).data(), v.data(), tk);
  }
}

}  // namespace

BvpResult bvp_of(const ActionModel& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b, double t0, double t1,
                 const BvpOptions& options) {
  const int n = model.coordinate_count();
  const int K = options.steps;
  check_bvp_input(n, a, b, t0, t1, options);
  const double h = (t1 - t0) / K;
  const int N = (K - 1) * n;
  // The path, one node q_k per column (contiguous, as the ActionModel reads it).
  Eigen::MatrixXd Q(n, K + 1);
  for (int k = 0; k <= K; ++k) {
    if (options.guess.size() != 0 && k > 0 && k < K) {
      Q.col(k) = options.guess.row(k).transpose();
    } else {
      const double s = static_cast<double>(k) / K;
      Q.col(k) = (1 - s) * a + s * b;
    }
  }
  std::vector<SegmentDerivatives> seg(static_cast<std::size_t>(K));
  Eigen::VectorXd R(N);
  Eigen::SparseMatrix<double> H(N, N);
  std::vector<Eigen::Triplet<double>> trip;
  auto assemble = [&](bool jacobian) {
    for (int k = 0; k < K; ++k)
      model.segment(Q.col(k).data(), Q.col(k + 1).data(), t0 + k * h, h, options.rule, seg[static_cast<std::size_t>(k)]);
    trip.clear();
    if (jacobian) trip.reserve(static_cast<std::size_t>(3 * n * n * (K - 1)));
    for (int k = 1; k < K; ++k) {
      const auto& prev = seg[static_cast<std::size_t>(k - 1)];
      const auto& next = seg[static_cast<std::size_t>(k)];
      const int r = (k - 1) * n;
      R.segment(r, n) = prev.d2 + next.d1;
      if (!jacobian) continue;
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          trip.emplace_back(r + i, r + j, prev.d22(i, j) + next.d11(i, j));
          if (k > 1) trip.emplace_back(r + i, r - n + j, prev.d12(j, i));
          if (k < K - 1) trip.emplace_back(r + i, r + n + j, next.d12(i, j));
        }
    }
    if (jacobian) H.setFromTriplets(trip.begin(), trip.end());
  };
  BvpResult out;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt;
  bool converged = false;
  assemble(true);
  Eigen::MatrixXd Q0;
  for (int it = 0; it < options.max_iterations; ++it) {
    if (!R.allFinite()) break;
    ldlt.compute(H);
    if (ldlt.info() != Eigen::Success) break;
    const Eigen::VectorXd dx = ldlt.solve(-R);
    if (!dx.allFinite()) break;
    // Backtracking on ‖R‖ when a full step makes it grow by more than 10×
    // (Newton is otherwise left free: near a saddle ‖R‖ need not fall monotonically).
    Q0 = Q;
    const double r0 = R.norm();
    double alpha = 1.0;
    for (int bt = 0; bt < 30; ++bt) {
      for (int k = 1; k < K; ++k) Q.col(k) = Q0.col(k) + alpha * dx.segment((k - 1) * n, n);
      assemble(false);
      if (R.allFinite() && (R.norm() <= 10 * r0 || r0 == 0)) break;
      alpha *= 0.5;
    }
    assemble(true);
    ++out.iterations;
    if ((alpha * dx).lpNorm<Eigen::Infinity>() <= options.tolerance * (1.0 + Q.lpNorm<Eigen::Infinity>())) {
      converged = true;
      break;
    }
  }
  out.residual = R.lpNorm<Eigen::Infinity>();
  judge_spectrum(model, a, t0, t1, H, ldlt, options, out);
  if (!converged || !Q.allFinite()) {
    std::ostringstream why;
    why.precision(6);
    why << "stationary action: Newton's method did not converge in " << out.iterations
        << " iterations (residual of the discrete Euler-Lagrange equations " << out.residual
        << "); try more steps or a different time span";
    throw AnalysisError(why.str());
  }
  recover_path(model, Q, seg, t0, t1, out);
  return out;
}

namespace {

struct ActionProblem {
  const ActionModel* model;
  Eigen::VectorXd a, b;
  double t0, h;
  int K;
  DiscreteRule rule;
  int evaluations = 0;
  SegmentDerivatives d;
};

/// S_d(q_1 … q_{K−1}) and its gradient, the DEL residuals D2 L_d + D1 L_d.
double action_objective(unsigned, const double* x, double* grad, void* data) {
  auto& p = *static_cast<ActionProblem*>(data);
  const int n = p.model->coordinate_count();
  ++p.evaluations;
  auto node = [&](int k) -> const double* {
    if (k == 0) return p.a.data();
    if (k == p.K) return p.b.data();
    return x + (k - 1) * n;
  };
  double s = 0;
  if (grad) std::fill(grad, grad + (p.K - 1) * n, 0.0);
  for (int k = 0; k < p.K; ++k) {
    p.model->segment(node(k), node(k + 1), p.t0 + k * p.h, p.h, p.rule, p.d);
    s += p.d.value;
    if (!grad) continue;
    for (int i = 0; i < n; ++i) {
      if (k > 0) grad[(k - 1) * n + i] += p.d.d1[i];
      if (k + 1 < p.K) grad[k * n + i] += p.d.d2[i];
    }
  }
  return s;
}

}  // namespace

ActionMinimum action_minimum_of(const ActionModel& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                double t0, double t1, const BvpOptions& options) {
  const int n = model.coordinate_count();
  const int K = options.steps;
  if (!a.allFinite() || !b.allFinite()) throw OptionError("minimise action: end points are not finite");
  if (!std::isfinite(t0) || !std::isfinite(t1) || !(t1 > t0))
    throw OptionError("minimise action: time: need finite t0 < t1");
  if (K < 2) throw OptionError("minimise action: steps: need at least 2, got " + std::to_string(K));
  ActionProblem problem{&model, a, b, t0, (t1 - t0) / K, K, options.rule, 0, {}};
  const int N = (K - 1) * n;
  std::vector<double> x(static_cast<std::size_t>(N));
  for (int k = 1; k < K; ++k)
    for (int i = 0; i < n; ++i) {
      const double s = static_cast<double>(k) / K;
      x[static_cast<std::size_t>((k - 1) * n + i)] = (1 - s) * a[i] + s * b[i];
    }
  std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(nlopt_create(NLOPT_LD_LBFGS, static_cast<unsigned>(N)),
                                                             &nlopt_destroy);
  nlopt_set_min_objective(opt.get(), &action_objective, &problem);
  nlopt_set_xtol_rel(opt.get(), 1e-14);
  nlopt_set_ftol_rel(opt.get(), 0.0);
  nlopt_set_maxeval(opt.get(), 20000);
  double f = 0;
  ActionMinimum out;
  out.nlopt_result = static_cast<int>(nlopt_optimize(opt.get(), x.data(), &f));
  out.evaluations = problem.evaluations;
  out.q.resize(K + 1, n);
  out.q.row(0) = a.transpose();
  out.q.row(K) = b.transpose();
  for (int k = 1; k < K; ++k)
    for (int i = 0; i < n; ++i) out.q(k, i) = x[static_cast<std::size_t>((k - 1) * n + i)];
  std::vector<double> g(static_cast<std::size_t>(N));
  out.action = action_objective(static_cast<unsigned>(N), x.data(), g.data(), &problem);
  double gmax = 0;
  for (double v : g) gmax = std::max(gmax, std::abs(v));
  // The momentum scale of the residual test: |D1 L_d| on the first segment.
  model.segment(a.data(), x.data(), t0, (t1 - t0) / K, options.rule, problem.d);
  const double pmax = problem.d.d1.lpNorm<Eigen::Infinity>();
  out.residual = gmax;
  out.converged = out.nlopt_result > 0 && std::isfinite(out.action) && std::isfinite(gmax) &&
                  gmax <= 1e-8 * (1.0 + pmax);
  return out;
}

}  // namespace lagrangian::detail
