#pragma once
// Internal: the state with k tangent vectors beside it, as one System for
// the driver (lyapunov.cpp, floquet.cpp).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/QR>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/integrate/method.hpp"
#include "lagrangian/integrate/system.hpp"

namespace lagrangian::detail {

/// ẋ = f(x, t) with k tangent vectors: the n(1 + k) coordinates
/// (q, δq_1, …, δq_k) and their rates (q̇, δq̇_1, …, δq̇_k), so that
/// d/dt δq_j = δq̇_j comes from the driver's layout and
///   d/dt δq̇_j = (∂q̈/∂q) δq_j + (∂q̈/∂q̇) δq̇_j.
/// With `benettin` (Lyapunov exponents) the tangent vectors start as the
/// first k canonical unit vectors and Benettin's renormalisation is the
/// system's one event: after an accepted step in which a tangent vector's
/// length changed by more than a factor e since the last one, or `longest`
/// seconds after it, the canonical tangent matrix Z = P W
/// (P = [[I, 0], ∂p/∂x]) is factored Z = QR, log R_jj is added to sum j and
/// W becomes P⁻¹ Q. The driver then restarts the stepper from the new
/// state, as after any event. MEGNO is summed over every accepted step.
/// Without it (the monodromy matrix) they start as the first k unit vectors
/// of the state (δq, δq̇) and are never touched: at the end they are the
/// first k columns of the flow's Jacobian ∂x(t)/∂x(t0).
class TangentSystem final : public System {
 public:
  TangentSystem(const TangentModel& model, int k, double longest, bool benettin)
      : model_(model), k_(k), longest_(longest), benettin_(benettin), qdd_(static_cast<std::size_t>(model.n)),
        jacobian_(static_cast<std::size_t>(2 * model.n * model.n)), w_(2 * model.n, k), qr_(2 * model.n, k),
        sums_(static_cast<std::size_t>(k), 0.0) {}

  int coordinate_count() const override { return model_.n * (1 + k_); }

  void rhs(const double* x, double* dxdt, double t) const override {
    const int n = model_.n, c = coordinate_count();
    ++evaluations_;
    std::copy(x + c, x + 2 * c, dxdt);
    if (k_ == 1 && model_.evaluate_direction != nullptr) {
      // One tangent vector: its rate along one direction, without J.
      std::copy(x + n, x + 2 * n, direction_.begin());
      std::copy(x + c + n, x + c + 2 * n, direction_.begin() + n);
      model_.evaluate_direction(model_.model, x, x + c, t, direction_.data(), dxdt + c, dxdt + c + n);
      return;
    }
    model_.evaluate(model_.model, x, x + c, t, qdd_.data(), jacobian_.data());
    std::copy(qdd_.begin(), qdd_.end(), dxdt + c);
    const Eigen::Map<const Eigen::MatrixXd> jq(jacobian_.data(), n, n), jqd(jacobian_.data() + n * n, n, n);
    for (int j = 1; j <= k_; ++j) {
      const Eigen::Map<const Eigen::VectorXd> dq(x + j * n, n), dqd(x + c + j * n, n);
      Eigen::Map<Eigen::VectorXd> out(dxdt + c + j * n, n);
      out.noalias() = jq * dq;
      out.noalias() += jqd * dqd;
    }
  }

  void start(double* x, double t0) override {
    last_ = t0_ = t0;
    if (benettin_) {
      canonical(x, t0);
      w_ = from_canonical(Eigen::MatrixXd::Identity(2 * model_.n, k_));
    } else {
      w_ = Eigen::MatrixXd::Identity(2 * model_.n, k_);
    }
    remember_lengths();
    store(x);
    ell_ = log_length(x);
  }
  void sample(double, const double*) override {}
  void finish(double, const double*, bool) override {}

  bool has_events() const override { return benettin_; }
  bool handle_events(double t_old, const double*, double& t, double* x, const StepInterpolant& interpolant) override {
    megno_step(t_old, t, x, interpolant);
    load(x);
    bool due = t - last_ >= longest_;
    for (int j = 0; j < k_ && !due; ++j)
      due = std::abs(std::log(w_.col(j).norm() / lengths_[static_cast<std::size_t>(j)])) > 1.0;
    if (!due) return false;
    renormalise(x, t);
    return true;
  }

  /// The last renormalisation, at the end of the run at t.
  void close(double* x, double t) {
    load(x);
    if (t > last_) renormalise(x, t);
  }

  /// The tangent matrix W = [δx_1 … δx_k] (2n × k) held in x.
  const Eigen::MatrixXd& tangents(const double* x) {
    load(x);
    return w_;
  }

  std::uint64_t evaluations() const { return evaluations_; }
  double megno() const { return megno_; }
  double megno_mean(double t) const { return t > t0_ ? megno_integral_ / (t - t0_) : 0.0; }
  const std::vector<double>& sums() const { return sums_; }
  int renormalisations() const { return renormalisations_; }
  double shortest() const { return shortest_; }
  double longest() const { return longest_taken_; }

 private:
  void load(const double* x) {
    const int n = model_.n, c = coordinate_count();
    for (int j = 0; j < k_; ++j)
      for (int i = 0; i < n; ++i) {
        w_(i, j) = x[(j + 1) * n + i];
        w_(n + i, j) = x[c + (j + 1) * n + i];
      }
  }
  void store(double* x) const {
    const int n = model_.n, c = coordinate_count();
    for (int j = 0; j < k_; ++j)
      for (int i = 0; i < n; ++i) {
        x[(j + 1) * n + i] = w_(i, j);
        x[c + (j + 1) * n + i] = w_(n + i, j);
      }
  }
  /// P at the state of x, in p_ (its lower n rows ∂p/∂(q, q̇)) and the
  /// Cholesky factor of M = ∂p/∂q̇.
  void canonical(const double* x, double t) {
    const int n = model_.n, c = coordinate_count();
    model_.momentum(model_.model, x, x + c, t, p_.data());
    const Eigen::Map<const Eigen::MatrixXd> dp(p_.data(), n, 2 * n);
    llt_.compute(dp.rightCols(n));
    if (llt_.info() != Eigen::Success)
      throw SimulationError("lyapunov: the mass matrix dp/dqd is not positive definite", t);
  }
  /// W = P⁻¹ Z: δq = Z_q, δq̇ = M⁻¹ (Z_p − (∂p/∂q) Z_q).
  Eigen::MatrixXd from_canonical(const Eigen::MatrixXd& z) const {
    const int n = model_.n;
    const Eigen::Map<const Eigen::MatrixXd> dp(p_.data(), n, 2 * n);
    Eigen::MatrixXd w(2 * n, k_);
    w.topRows(n) = z.topRows(n);
    w.bottomRows(n) = llt_.solve(z.bottomRows(n) - dp.leftCols(n) * z.topRows(n));
    return w;
  }
  /// ℓ = ln |δx_1| of the first tangent vector as if never renormalised:
  /// its length in (q, q̇) plus the logs of the factors R_11 it was divided
  /// by (a renormalisation only scales it).
  double log_length(const double* x) const {
    const int n = model_.n, c = coordinate_count();
    double s2 = 0;
    for (int i = 0; i < n; ++i) s2 += x[n + i] * x[n + i] + x[c + n + i] * x[c + n + i];
    return ell_offset_ + 0.5 * std::log(s2);
  }
  /// MEGNO over the step [a, b] (s = t − t0): with I = ∫ s dℓ,
  ///   I(b) − I(a) = s_b ℓ_b − s_a ℓ_a − ∫ ℓ ds   (Simpson, ℓ at the
  ///   interpolated midpoint),  Y = 2 I / s,  ∫ Y ds by the trapezoid rule.
  void megno_step(double a, double b, const double* x, const StepInterpolant& interpolant) {
    if (!(b > a)) return;
    interpolant(0.5 * (a + b), mid_.data());
    const double lm = log_length(mid_.data()), lb = log_length(x);
    const double sa = a - t0_, sb = b - t0_;
    megno_i_ += sb * lb - sa * ell_ - (b - a) / 6 * (ell_ + 4 * lm + lb);
    const double y = 2 * megno_i_ / sb;
    megno_integral_ += 0.5 * (b - a) * (megno_ + y);
    megno_ = y;
    ell_ = lb;
  }
  /// The tangent vectors' lengths in (q, q̇) just after a renormalisation
  /// (unit length in (q, p)): the next one is due when one of them has
  /// grown or shrunk by a factor e from there.
  void remember_lengths() {
    for (int j = 0; j < k_; ++j) lengths_[static_cast<std::size_t>(j)] = w_.col(j).norm();
  }
  void renormalise(double* x, double t) {
    const int n = model_.n;
    canonical(x, t);
    const Eigen::Map<const Eigen::MatrixXd> dp(p_.data(), n, 2 * n);
    Eigen::MatrixXd z(2 * n, k_);
    z.topRows(n) = w_.topRows(n);
    z.bottomRows(n) = dp * w_;
    qr_.compute(z);
    const Eigen::MatrixXd& r = qr_.matrixQR();
    for (int j = 0; j < k_; ++j) {
      const double grow = std::log(std::abs(r(j, j)));
      if (!std::isfinite(grow))
        throw SimulationError("lyapunov: tangent vector " + std::to_string(j + 1) +
                                  " became dependent on the others or non-finite (|R_jj| = " +
                                  std::to_string(std::abs(r(j, j))) + ")",
                              t);
      sums_[static_cast<std::size_t>(j)] += grow;
    }
    ell_offset_ += std::log(r(0, 0) < 0 ? -r(0, 0) : r(0, 0));
    // Q with the signs that make R's diagonal positive: each tangent vector
    // keeps its direction.
    Eigen::MatrixXd q = qr_.householderQ() * Eigen::MatrixXd::Identity(2 * n, k_);
    for (int j = 0; j < k_; ++j)
      if (r(j, j) < 0) q.col(j) = -q.col(j);
    w_ = from_canonical(q);
    remember_lengths();
    store(x);
    ++renormalisations_;
    shortest_ = std::min(shortest_, t - last_);
    longest_taken_ = std::max(longest_taken_, t - last_);
    last_ = t;
  }

  TangentModel model_;
  int k_;
  double longest_;
  bool benettin_;
  mutable std::vector<double> qdd_, jacobian_;
  mutable std::vector<double> direction_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n));
  mutable std::uint64_t evaluations_ = 0;
  Eigen::MatrixXd w_;
  std::vector<double> p_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n * model_.n));
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr_;
  std::vector<double> sums_, lengths_ = std::vector<double>(static_cast<std::size_t>(k_), 1.0);
  double last_ = 0, t0_ = 0;
  // MEGNO: ℓ at the last step end, its offset, I, Y and ∫ Y ds.
  double ell_ = 0, ell_offset_ = 0, megno_i_ = 0, megno_ = 0, megno_integral_ = 0;
  std::vector<double> mid_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n * (1 + k_)));
  int renormalisations_ = 0;
  double shortest_ = std::numeric_limits<double>::infinity();
  double longest_taken_ = 0;
};

/// OptionError for an invalid run or a method that cannot carry tangent
/// vectors (the symplectic and variational ones integrate a model's own
/// structure); `command` names the caller in the message.
inline void check_tangent_run(const SimulationOptions& run, const std::string& command) {
  run.validate();
  const MethodInfo& method = method_info(run.method);
  if (method.family != MethodFamily::explicit_runge_kutta && method.family != MethodFamily::gauss_radau &&
      method.family != MethodFamily::rosenbrock)
    throw OptionError(command + ": method '" + std::string(method.name) +
                      "' integrates a model's own structure, not the tangent vectors beside it; take an explicit "
                      "Runge-Kutta method (dopri5, fehlberg78, ...), gauss_radau15 or rosenbrock4");
}

}  // namespace lagrangian::detail
