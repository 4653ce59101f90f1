#pragma once
// Internal: the state with k tangent vectors beside it, as one System for
// the driver (lyapunov.cpp, floquet.cpp).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/QR>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/saltation.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/integrate/detail/contact_rules.hpp"
#include "lagrangian/integrate/detail/roots.hpp"
#include "lagrangian/integrate/system.hpp"
#include "manifold.hpp"

namespace lagrangian::detail {

/// ẋ = f(x, t) with k tangent vectors: the n(1 + k) coordinates
/// (q, δq_1, …, δq_k) and their rates (q̇, δq̇_1, …, δq̇_k), so that
/// d/dt δq_j = δq̇_j comes from the driver's layout and
///   d/dt δq̇_j = (∂q̈/∂q) δq_j + (∂q̈/∂q̇) δq̇_j.
/// With `benettin` (Lyapunov exponents) the tangent vectors start as the
/// first k canonical unit vectors (for a model with holonomic or Pfaffian
/// constraints: the first k vectors of a basis of the constraint manifold's
/// tangent space orthonormal in the reduced canonical coordinates
/// (Uᵀ δq, Uᵀ δp), U a basis of ker ∂g/∂q, in which it is factored; a
/// renormalisation projects the state onto the manifold and the vectors
/// onto its tangent space first) and Benettin's renormalisation is the
/// system's one event: after an accepted step in which a tangent vector's
/// length changed by more than a factor e since the last one, or `longest`
/// seconds after it, the canonical tangent matrix Z = P W
/// (P = [[I, 0], ∂p/∂x]) is factored Z = QR, log R_jj is added to sum j and
/// W becomes P⁻¹ Q. The driver then restarts the stepper from the new
/// state, as after any event. MEGNO is summed over every accepted step.
/// Without it (the monodromy matrix, sensitivities) they start as the first
/// k unit vectors of the state (δq, δq̇) and are never touched: at the end
/// they are the first k columns of the flow's Jacobian ∂x(t)/∂x(t0) (for a
/// model with holonomic or Pfaffian constraints they start as the basis B0
/// of manifold_basis(), k its d columns, and end as Φ B0; a recorded sample
/// holds Φ B0 B0ᵀ). After them come the columns s_j = ∂x/∂p_j of the
/// model's parameters `parameters` (sensitivity.hpp), from 0, with
///   d/dt δq̇ = (∂q̈/∂q) δq + (∂q̈/∂q̇) δq̇ + ∂q̈/∂p_j.
/// With `record`, every sample keeps its time, state and columns.
/// A model's contacts are located at the end of every accepted step by the
/// plain run's rules (contact_rules.hpp, on the step's interpolant); at the
/// earliest impact the step end moves there, q̇ becomes q̇⁺ and every column
/// w becomes S w (saltation.hpp), a parameter's column S w + R_p + a ∂φ/∂p / v
/// (sensitivity.hpp); MEGNO's ℓ jumps with the first vector's
/// length. Where the plain run lets a contact rest (its Zeno rule, a
/// plastic impact) a model with TangentModel::rest holds it shut: the
/// impact with e = 0 into the motion with φ_j = 0 held is crossed by its
/// saltation matrix, whose kernel, δφ_j and δφ̇_j, every column loses
/// (Benettin's vectors are renormalised at once, and those that vanished
/// are left out from then on: their exponents are −∞); it lifts off at the
/// first time its multiplier λ_j is negative (the plain run's rule), where
/// the columns cross unchanged (both motions' rates agree at λ_j = 0).
/// Refused with SimulationError: a rest on a model without
/// TangentModel::rest or with parameter columns, a touch not faster than
/// contact_touch_speed, an impact while another contact rests, a grazing
/// contact, two contacts closing or touching at one instant, a resting
/// contact whose gap drifts beyond 1e-6 (1 + ‖q‖∞).
class TangentSystem final : public System {
 public:
  TangentSystem(const TangentModel& model, int k, double longest, bool benettin, std::vector<int> parameters = {},
                bool record = false)
      : model_(model), k_(k), columns_(k + static_cast<int>(parameters.size())), parameters_(std::move(parameters)),
        record_(record), longest_(longest), benettin_(benettin), qdd_(static_cast<std::size_t>(model.n)),
        jacobian_(static_cast<std::size_t>(2 * model.n * model.n)), w_(2 * model.n, columns_), qr_(2 * model.n, k),
        sums_(static_cast<std::size_t>(k), 0.0) {
    if (benettin_ && columns_ != k_) throw std::logic_error("TangentSystem: Benettin's method takes no parameter columns");
    if (model_.contacts > 0 && columns_ != k_ && model_.parameter_impact == nullptr)
      throw std::logic_error(
          "TangentSystem: parameter columns of a model with contacts need its parameter_impact");
    jumped_.resize(2 * model_.n, columns_);
  }

  int coordinate_count() const override { return model_.n * (1 + columns_); }

  void rhs(const double* x, double* dxdt, double t) const override {
    const int n = model_.n, c = coordinate_count();
    ++evaluations_;
    std::copy(x + c, x + 2 * c, dxdt);
    if (k_ == 1 && model_.evaluate_direction != nullptr) {
      // One tangent vector: its rate along one direction, without J.
      load_direction(x, 1);
      model_.evaluate_direction(model_.model, x, x + c, t, direction_.data(), dxdt + c, dxdt + c + n);
    } else if (k_ > 0) {
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
    // Each parameter's column along its own direction, ∂q̈/∂p_j included.
    for (int j = k_ + 1; j <= columns_; ++j) {
      load_direction(x, j);
      model_.evaluate_parameter(model_.model, x, x + c, t, direction_.data(),
                                parameters_[static_cast<std::size_t>(j - k_ - 1)], qdd_.data(), dxdt + c + j * n);
      if (k_ == 0 && j == 1) std::copy(qdd_.begin(), qdd_.end(), dxdt + c);
    }
  }

  void start(double* x, double t0) override {
    last_ = t0_ = t0;
    if (model_.contacts > 0) {
      model_.gaps(model_.model, x, x + coordinate_count(), t0, gap_new_.data(), rate_new_.data());
      const double touch = contact_touch_tolerance(x, model_.n);
      for (int j = 0; j < model_.contacts; ++j)
        if (gap_new_[static_cast<std::size_t>(j)] < -touch)
          throw SimulationError("tangent flow: contact '" + contact(j) + "' is penetrated at the start (gap " +
                                    number(gap_new_[static_cast<std::size_t>(j)]) + " < 0)",
                                t0);
    }
    if (model_.manifold > 0) {
      check_on_manifold(x, t0);
      // B0, the tangent space's basis (H at the start, from check_on_manifold()).
      start_basis_ = tangent_basis(manifold_jacobian(), 2 * model_.n);
    }
    if (benettin_ && model_.manifold > 0) {
      // The first k vectors of B0, orthonormal in reduced canonical coordinates.
      canonical(x, t0);
      reduce_ = configuration_basis();
      qr_.compute(reduced_canonical(start_basis_));
      w_ = divided_by_r(start_basis_, qr_.matrixQR()).leftCols(k_);
    } else if (benettin_) {
      canonical(x, t0);
      w_ = from_canonical(Eigen::MatrixXd::Identity(2 * model_.n, k_));
    } else {
      // The monodromy matrix and the sensitivities: the first k unit vectors
      // (on a manifold B0), then the parameters' columns from 0.
      if (model_.manifold > 0 && k_ > 0 && start_basis_.cols() != k_)
        throw std::logic_error("TangentSystem: k differs from the dimension of the constraint manifold");
      w_.setZero();
      if (model_.manifold > 0)
        w_.leftCols(k_) = start_basis_.leftCols(k_);
      else
        w_.leftCols(k_) = Eigen::MatrixXd::Identity(2 * model_.n, k_);
    }
    remember_lengths();
    store(x);
    ell_ = log_length(x);
  }
  void sample(double t, const double* x) override {
    if (!record_) return;
    using V = Eigen::Map<const Eigen::VectorXd>;
    Eigen::VectorXd state(2 * model_.n);
    state << V(x, model_.n), V(x + coordinate_count(), model_.n);  // (q, q̇)
    load(x);
    times_.push_back(t);
    states_.push_back(std::move(state));
    // On a manifold the d columns W = Φ B0 are recorded as Φ P0 = W B0ᵀ,
    // the parameters' columns after them as they are.
    if (model_.manifold == 0 || benettin_ || k_ == 0) {
      columns_taken_.push_back(w_);
      return;
    }
    const int m = 2 * model_.n, p = columns_ - k_;
    Eigen::MatrixXd taken(m, m + p);
    taken.leftCols(m) = w_.leftCols(k_) * start_basis_.transpose();
    taken.rightCols(p) = w_.rightCols(p);
    columns_taken_.push_back(std::move(taken));
  }
  void finish(double t, const double* x, bool sample_end) override {
    if (sample_end) sample(t, x);
  }

  bool has_events() const override { return benettin_ || model_.contacts > 0; }
  bool handle_events(double t_old, const double* x_old, double& t, double* x,
                     const StepInterpolant& interpolant) override {
    // A lift-off ends the step first: an impact before it (cross_impact())
    // is one under a resting contact, which is refused.
    const int lifted = resting_count_ > 0 ? lift_off(t_old, x_old, t, x, interpolant) : -1;
    const bool impact = model_.contacts > 0 && cross_impact(t_old, x_old, t, x, interpolant);
    if (lifted >= 0) release(lifted);
    if (resting_count_ > 0) check_resting_gaps(x, t);
    const bool event = impact || lifted >= 0;
    if (!benettin_) return event;
    if (!impact) megno_step(t_old, t, x, interpolant);
    load(x);
    bool due = rest_due_ || t - last_ >= longest_;
    for (int j = 0; j < k_ && !due; ++j)
      due = !dead_[static_cast<std::size_t>(j)] &&
            std::abs(std::log(w_.col(j).norm() / lengths_[static_cast<std::size_t>(j)])) > 1.0;
    if (due) renormalise(x, t);
    return event || due;
  }

  /// Impacts crossed so far (a rest by the Zeno rule is not one).
  int impacts() const { return impacts_; }
  /// Contacts that came to rest, and resting contacts that lifted off.
  int rests() const { return rests_; }
  int releases() const { return releases_; }
  /// The run's options: its contact_touch_speed (a contact touching slower
  /// is not an impact) and Zeno rule (zeno_speed_ratio, zeno_min_interval:
  /// where a plain run lets a contact rest), contact_rules.hpp.
  void set_run(const SimulationOptions& run) { run_ = run; }

  /// The last renormalisation, at the end of the run at t.
  void close(double* x, double t) {
    load(x);
    if (t > last_) renormalise(x, t);
  }

  /// With `record`: the samples' times, states (q, q̇) and columns (above).
  const std::vector<double>& times() const { return times_; }
  const std::vector<Eigen::VectorXd>& states() const { return states_; }
  const std::vector<Eigen::MatrixXd>& recorded_columns() const { return columns_taken_; }

  /// The tangent matrix W = [δx_1 … δx_k] (2n × k, and the parameters'
  /// columns after them) held in x.
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
  /// Column j ≥ 1 of x (δq_j, δq̇_j) into direction_.
  void load_direction(const double* x, int j) const {
    const int n = model_.n, c = coordinate_count();
    std::copy(x + j * n, x + (j + 1) * n, direction_.begin());
    std::copy(x + c + j * n, x + c + (j + 1) * n, direction_.begin() + n);
  }
  /// The columns W (2n × columns) from x (their δq after q, their δq̇ after
  /// q̇, each n × columns column-major) and back.
  void load(const double* x) {
    const int n = model_.n, c = coordinate_count();
    w_.topRows(n) = Eigen::Map<const Eigen::MatrixXd>(x + n, n, columns_);
    w_.bottomRows(n) = Eigen::Map<const Eigen::MatrixXd>(x + c + n, n, columns_);
  }
  void store(double* x) const {
    const int n = model_.n, c = coordinate_count();
    Eigen::Map<Eigen::MatrixXd>(x + n, n, columns_) = w_.topRows(n);
    Eigen::Map<Eigen::MatrixXd>(x + c + n, n, columns_) = w_.bottomRows(n);
  }
  /// P at the state of x, in p_ (its lower n rows ∂p/∂(q, q̇)) and the
  /// Cholesky factor of M = ∂p/∂q̇.
  void canonical(const double* x, double t) {
    const int n = model_.n, c = coordinate_count();
    model_.momentum(model_.model, x, x + c, t, p_.data(), nullptr);
    const Eigen::Map<const Eigen::MatrixXd> dp(p_.data(), n, 2 * n);
    llt_.compute(dp.rightCols(n));
    if (llt_.info() != Eigen::Success)
      throw SimulationError("lyapunov: the mass matrix dp/dqd is not positive definite", t);
  }
  /// W = P⁻¹ Z: δq = Z_q, δq̇ = M⁻¹ (Z_p − (∂p/∂q) Z_q).
  Eigen::MatrixXd from_canonical(const Eigen::MatrixXd& z) const {
    const int n = model_.n;
    const Eigen::Map<const Eigen::MatrixXd> dp(p_.data(), n, 2 * n);
    Eigen::MatrixXd w(2 * n, z.cols());
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
    if (model_.manifold > 0) to_manifold(x, t);
    canonical(x, t);
    const Eigen::Map<const Eigen::MatrixXd> dp(p_.data(), n, 2 * n);
    if (model_.manifold > 0) {  // (no contacts: no vector leaves)
      live_.resize(static_cast<std::size_t>(k_));
      for (int j = 0; j < k_; ++j) live_[static_cast<std::size_t>(j)] = j;
      qr_.compute(reduced_canonical(w_));
    } else {
      live_canonical(dp);
      if (rest_due_ && collapse(t)) live_canonical(dp);
    }
    rest_due_ = false;
    const Eigen::MatrixXd& r = qr_.matrixQR();
    for (int i = 0; i < static_cast<int>(live_.size()); ++i) {
      const int j = live_[static_cast<std::size_t>(i)];
      const double grow = std::log(std::abs(r(i, i)));
      if (!std::isfinite(grow))
        throw SimulationError("lyapunov: tangent vector " + std::to_string(j + 1) +
                                  " became dependent on the others or non-finite (|R_jj| = " +
                                  std::to_string(std::abs(r(i, i))) + ")",
                              t);
      sums_[static_cast<std::size_t>(j)] += grow;
    }
    ell_offset_ += std::log(r(0, 0) < 0 ? -r(0, 0) : r(0, 0));
    if (model_.manifold > 0) {
      w_ = divided_by_r(w_, r);
    } else {
      // Q with the signs that make R's diagonal positive: each tangent
      // vector keeps its direction; those a rest removed stay 0.
      const auto live = static_cast<int>(live_.size());
      Eigen::MatrixXd q = qr_.householderQ() * Eigen::MatrixXd::Identity(2 * n, live);
      for (int i = 0; i < live; ++i)
        if (r(i, i) < 0) q.col(i) = -q.col(i);
      const Eigen::MatrixXd w = from_canonical(q);
      w_.leftCols(k_).setZero();
      for (int i = 0; i < live; ++i) w_.col(live_[static_cast<std::size_t>(i)]) = w.col(i);
    }
    remember_lengths();
    store(x);
    // The projection moved the first vector a little: MEGNO's ℓ starts the
    // next step from its length now.
    if (model_.manifold > 0) ell_ = log_length(x);
    ++renormalisations_;
    shortest_ = std::min(shortest_, t - last_);
    longest_taken_ = std::max(longest_taken_, t - last_);
    last_ = t;
  }

  /// The live tangent vectors (live_: those no rest removed) in canonical
  /// coordinates (δq, δp = (∂p/∂q) δq + M δq̇), factored into qr_.
  void live_canonical(const Eigen::Map<const Eigen::MatrixXd>& dp) {
    const int n = model_.n;
    live_.clear();
    for (int j = 0; j < k_; ++j)
      if (!dead_[static_cast<std::size_t>(j)]) live_.push_back(j);
    Eigen::MatrixXd z(2 * n, static_cast<Eigen::Index>(live_.size()));
    for (int i = 0; i < static_cast<int>(live_.size()); ++i) {
      const auto w = w_.col(live_[static_cast<std::size_t>(i)]);
      z.col(i).head(n) = w.head(n);
      z.col(i).tail(n).noalias() = dp * w;
    }
    qr_.compute(z);
  }
  /// Just after a rest's saltation matrix (renormalise()): the vectors whose
  /// image lies, to rounding, in the span of those before them — S removed
  /// their part outside it (|R_jj| ≤ 1e-7 of the largest column; the
  /// columns were orthonormal at the last renormalisation and e = 0's S
  /// has entries of order 1, so a vector it keeps has |R_jj| far above
  /// that). They leave (dead_), at most two per rest; with fewer than 2n
  /// vectors, or the first one, SimulationError: the rest removed a vector
  /// that Benettin's method needs. Returns whether one left.
  bool collapse(double t) {
    const Eigen::MatrixXd& r = qr_.matrixQR();
    double largest = 0;
    for (int i = 0; i < static_cast<int>(live_.size()); ++i) largest = std::max(largest, r.col(i).head(i + 1).norm());
    int gone = 0;
    for (int i = 0; i < static_cast<int>(live_.size()); ++i) {
      if (!(std::abs(r(i, i)) <= 1e-7 * largest)) continue;
      const int j = live_[static_cast<std::size_t>(i)];
      if (k_ < 2 * model_.n || j == 0)
        throw SimulationError("lyapunov: the rest of contact '" + contact(last_rest_) +
                                  "' removes the direction of tangent vector " + std::to_string(j + 1) +
                                  " (its exponent becomes -inf, while the exponents asked for are the largest " +
                                  std::to_string(k_) + " of " + std::to_string(2 * model_.n) +
                                  "): ask for all of them (exponents = 0)",
                              t);
      dead_[static_cast<std::size_t>(j)] = 1;
      sums_[static_cast<std::size_t>(j)] = -std::numeric_limits<double>::infinity();
      w_.col(j).setZero();
      ++gone;
    }
    if (gone > 2)
      throw SimulationError("lyapunov: the rest of contact '" + contact(last_rest_) + "' removed " +
                                std::to_string(gone) + " tangent vectors; one rest removes at most 2",
                            t);
    return gone > 0;
  }

  /// The earliest lift-off in (t_old, t] of a resting contact, the first
  /// time from which its multiplier λ_j < 0 (locate_lift_off(), the plain
  /// run's rule): (t, x) move there and the contact is returned; −1 when
  /// none.
  int lift_off(double t_old, const double* x_old, double& t, double* x, const StepInterpolant& interpolant) {
    const int c = coordinate_count();
    int which = -1;
    double at = t;
    for (int j = 0; j < model_.contacts; ++j) {
      if (!resting_[static_cast<std::size_t>(j)]) continue;
      const double end = multiplier(x, x + c, t, j);
      if (!(end < 0)) continue;
      const auto lambda = [&](double s) {
        interpolant(s, mid_.data());
        return multiplier(mid_.data(), mid_.data() + c, s, j);
      };
      const double start = multiplier(x_old, x_old + c, t_old, j);
      const double found = locate_lift_off(t_old, t, start, end, time_function(lambda));
      if (which < 0 || found < at) {
        which = j;
        at = found;
      }
    }
    if (which >= 0 && at < t) {
      interpolant(at, x);
      t = at;
    }
    return which;
  }
  /// λ_j (N for a distance gap; > 0 presses the bodies apart) of resting
  /// contact j at (q, q̇, t): with C the resting contacts' G = ∂φ/∂q and γ
  /// (their impact maps') and q̈_f the free motion's (the contacts opened
  /// for the moment),
  ///   M q̈ = M q̈_f + Cᵀλ,  C q̈ + γ = 0  ⇒  (C M⁻¹ Cᵀ) λ = −γ − C q̈_f.
  double multiplier(const double* q, const double* qd, double t, int wanted) {
    const int n = model_.n;
    held_.clear();
    for (int j = 0; j < model_.contacts; ++j)
      if (resting_[static_cast<std::size_t>(j)]) held_.push_back(j);
    for (int j : held_) model_.rest(model_.model, j, false);
    std::fill(zero_.begin(), zero_.end(), 0.0);
    model_.evaluate_direction(model_.model, q, qd, t, zero_.data(), held_free_.data(), held_scratch_.data());
    for (int j : held_) model_.rest(model_.model, j, true);
    model_.momentum(model_.model, q, qd, t, held_momentum_.data(), nullptr);
    const auto rows = static_cast<Eigen::Index>(held_.size());
    Eigen::MatrixXd g(rows, n);
    Eigen::VectorXd b(rows);
    Eigen::Index which = -1;
    for (Eigen::Index i = 0; i < rows; ++i) {
      const int j = held_[static_cast<std::size_t>(i)];
      double gamma = 0;
      model_.impact(model_.model, q, qd, t, j, 0.0, held_scratch_.data(), held_jacobian_.data(),
                    held_gradient_.data(), &gamma);
      const Eigen::Map<const Eigen::VectorXd> gradient(held_gradient_.data(), n), free(held_free_.data(), n);
      g.row(i) = gradient.transpose();
      b[i] = -gamma - gradient.dot(free);
      if (j == wanted) which = i;
    }
    if (which < 0) throw std::logic_error("TangentSystem::multiplier: contact " + contact(wanted) + " is not resting");
    const Eigen::LLT<Eigen::MatrixXd> mass(Eigen::Map<const Eigen::MatrixXd>(held_momentum_.data(), n, 2 * n).rightCols(n));
    const Eigen::MatrixXd minv_gt = mass.solve(g.transpose());
    const Eigen::VectorXd lambda = (g * minv_gt).completeOrthogonalDecomposition().solve(b);
    return lambda[which];
  }
  void release(int j) {
    model_.rest(model_.model, j, false);
    resting_[static_cast<std::size_t>(j)] = 0;
    --resting_count_;
    ++releases_;
  }
  /// SimulationError when a resting contact's gap has left 0 by more than
  /// 1e-6 (1 + ‖q‖∞): the motion along it drifted (the tangent run holds
  /// φ̈ = 0 without stabilisation).
  void check_resting_gaps(const double* x, double t) {
    const int n = model_.n, c = coordinate_count();
    model_.gaps(model_.model, x, x + c, t, gap_at_.data(), rate_at_.data());
    const double tolerance = 1000 * contact_touch_tolerance(x, n);
    for (int j = 0; j < model_.contacts; ++j)
      if (resting_[static_cast<std::size_t>(j)] && !(std::abs(gap_at_[static_cast<std::size_t>(j)]) <= tolerance))
        throw SimulationError("tangent flow: resting contact '" + contact(j) + "' drifted to a gap of " +
                                  number(gap_at_[static_cast<std::size_t>(j)]) + " (tolerance " + number(tolerance) +
                                  ")",
                              t);
  }

  /// ConstraintError naming the first row h_i of the constraint manifold
  /// (g, ġ or φ) off zero at the start by more than 1e-9 (1 + ‖q‖∞) or
  /// 1e-9 (1 + ‖q̇‖∞), the plain run's test.
  void check_on_manifold(const double* x, double t) {
    const int n = model_.n, c = coordinate_count(), mh = model_.manifold_holonomic;
    model_.manifold_rows(model_.model, x, x + c, t, residual_.data(), manifold_jacobian_.data());
    const Eigen::Map<const Eigen::VectorXd> q(x, n), qd(x + c, n);
    const double qs = 1.0 + q.lpNorm<Eigen::Infinity>(), vs = 1.0 + qd.lpNorm<Eigen::Infinity>();
    for (int i = 0; i < model_.manifold; ++i) {
      const double h = residual_[static_cast<std::size_t>(i)];
      if (!(std::abs(h) <= 1e-9 * (i < mh ? qs : vs)))
        throw ConstraintError("tangent flow: the initial state violates constraint " +
                              model_.manifold_names[static_cast<std::size_t>(i)] + " (" + number(h) +
                              "); use consistent_initial_state() to find the nearest consistent state");
    }
  }
  /// The state of x projected onto the constraint manifold (the model's
  /// projection) and the tangent vectors onto its tangent space,
  /// W ← W − H⁺ (H W) with H = ∂h/∂(q, q̇): a renormalisation takes off
  /// the drift the integration left (the exact flow keeps both on it).
  void to_manifold(double* x, double t) {
    const int c = coordinate_count();
    try {
      model_.project(model_.model, x, x + c, t);
    } catch (const ConstraintError& e) {
      throw SimulationError(std::string("tangent flow: projection onto the constraint manifold failed: ") + e.what(),
                            t);
    }
    model_.manifold_rows(model_.model, x, x + c, t, residual_.data(), manifold_jacobian_.data());
    const Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(manifold_jacobian());
    w_ -= cod.solve(manifold_jacobian() * w_);
    reduce_ = configuration_basis();
    store(x);
  }
  /// U: an orthonormal basis (n × f) of the configuration's tangent space
  /// ker G, G = ∂g/∂q of the holonomic rows (from the last manifold_rows()
  /// evaluation; the identity without holonomic rows).
  Eigen::MatrixXd configuration_basis() const {
    const int n = model_.n, mh = model_.manifold_holonomic;
    if (mh == 0) return Eigen::MatrixXd::Identity(n, n);
    return tangent_basis(manifold_jacobian().topLeftCorner(mh, n), n);
  }
  /// H = ∂h/∂(q, q̇) of the last manifold_rows() evaluation.
  Eigen::Map<const Eigen::MatrixXd> manifold_jacobian() const {
    return Eigen::Map<const Eigen::MatrixXd>(manifold_jacobian_.data(), model_.manifold, 2 * model_.n);
  }
  /// The reduced canonical coordinates (Uᵀ δq, Uᵀ δp) of tangent vectors
  /// (the columns of w) of the manifold, δp = (∂p/∂q) δq + M δq̇ (p_ at
  /// the state): on the manifold of a holonomic system they are Darboux
  /// coordinates of the symplectic form Σ δq_i ∧ δp_i restricted to it
  /// (δq = U a, Uᵀ δp = b: ω = a₁·b₂ − a₂·b₁), so volumes in them are
  /// phase-space volumes and a Hamiltonian spectrum sums to zero at every
  /// time, as in (q, p) without constraints; they determine a tangent
  /// vector of the manifold (Pfaffian rows too: the map is injective).
  Eigen::MatrixXd reduced_canonical(const Eigen::MatrixXd& w) const {
    const int n = model_.n, f = static_cast<int>(reduce_.cols());
    const Eigen::Map<const Eigen::MatrixXd> dp(p_.data(), n, 2 * n);
    Eigen::MatrixXd z(2 * f, w.cols());
    z.topRows(f) = reduce_.transpose() * w.topRows(n);
    z.bottomRows(f) = reduce_.transpose() * (dp * w);
    return z;
  }
  /// x with 6 significant digits, for messages.
  static std::string number(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", x);
    return buf;
  }
  std::string contact(int j) const {
    return j < static_cast<int>(model_.contact_names.size()) ? model_.contact_names[static_cast<std::size_t>(j)]
                                                              : std::to_string(j);
  }
  /// The earliest contact closing in the step (t_old, t], located by the
  /// plain run's rules (locate_closing: crossings, dips of the gap, a
  /// contact leaving and coming back within the step): false when none;
  /// otherwise the step end moves to the impact (t, x), MEGNO is taken to
  /// it, the impact law applied to q̇ and the saltation matrix to every
  /// column; where a plain run lets the contact rest (the Zeno rule, a
  /// plastic impact) the impact is plastic and the contact rests from then
  /// on (TangentModel::rest). SimulationError for a rest the model cannot
  /// hold (above), a touch slower than contact_touch_speed, an impact while
  /// another contact rests, two contacts closing or touching at one instant,
  /// a grazing contact and one found penetrated.
  bool cross_impact(double t_old, const double* x_old, double& t, double* x, const StepInterpolant& interpolant) {
    const int n = model_.n, c = coordinate_count();
    model_.gaps(model_.model, x_old, x_old + c, t_old, gap_old_.data(), rate_old_.data());
    model_.gaps(model_.model, x, x + c, t, gap_new_.data(), rate_new_.data());
    const double touch = contact_touch_tolerance(x, n);
    int first = -1, slow = -1;
    double at = t;
    for (int j = 0; j < model_.contacts; ++j) {
      const auto jj = static_cast<std::size_t>(j);
      if (resting_[jj]) continue;  // held shut
      const GapRate a{gap_old_[jj], rate_old_[jj]}, b{gap_new_[jj], rate_new_[jj]};
      if (a.gap > touch && b.gap > touch && !(a.rate < 0 && b.rate > 0)) continue;  // open throughout
      const auto on_step = [&](double s) {
        interpolant(s, mid_.data());
        model_.gaps(model_.model, mid_.data(), mid_.data() + c, s, gap_at_.data(), rate_at_.data());
        return GapRate{gap_at_[jj], rate_at_[jj]};
      };
      const Closing found = locate_closing(t_old, t, a, b, touch, run_.contact_touch_speed, gap_function(on_step));
      if (found.kind == Closing::Kind::penetrated) throw_penetrated(contact(j), t_old, a.gap);
      if (found.kind == Closing::Kind::none) {
        if (b.gap < 0 && slow < 0) slow = j;  // a touch too slow to be an impact, ending shut
        continue;
      }
      if (first >= 0 && std::abs(found.t - at) <= 2 * event_time_tolerance * std::max(1.0, std::abs(at)))
        throw SimulationError("tangent flow: contacts '" + contact(first) + "' and '" + contact(j) +
                                  "' close at one instant: the saltation matrix of simultaneous impacts is not "
                                  "derived",
                              found.t);
      if (first < 0 || found.t < at) {
        first = j;
        at = found.t;
      }
    }
    if (first < 0 && slow >= 0)
      throw SimulationError("tangent flow: contact '" + contact(slow) +
                                "' touches slower than contact_touch_speed and stays shut (a plain run lets it rest "
                                "or slide along): the tangent flow through a closed contact is not derived",
                            t_old);
    if (first < 0) return false;
    for (int j = 0; j < model_.contacts; ++j)
      if (resting_[static_cast<std::size_t>(j)])
        throw SimulationError("tangent flow: contact '" + contact(first) + "' closes while contact '" + contact(j) +
                                  "' rests: the saltation matrix of an impact under a resting contact is not derived",
                              at);
    progress_.check(at, t_old);
    if (at < t) interpolant(at, x);
    if (benettin_) megno_step(t_old, at, x, interpolant);
    t = at;
    // Another contact touching at the impact (a ball in a corner, a row of
    // touching spheres): impacts in sequence at one instant.
    model_.gaps(model_.model, x, x + c, t, gap_at_.data(), rate_at_.data());
    for (int j = 0; j < model_.contacts; ++j)
      if (j != first && std::abs(gap_at_[static_cast<std::size_t>(j)]) <= contact_touch_tolerance(x, n))
        throw SimulationError("tangent flow: contacts '" + contact(first) + "' and '" + contact(j) +
                                  "' touch at one instant: the saltation matrix of simultaneous impacts is not "
                                  "derived",
                              t);
    const double ell_before = log_length(x);
    double gamma = 0;
    const double v = model_.impact(model_.model, x, x + c, t, first, model_.restitution[static_cast<std::size_t>(first)],
                                   qd_plus_.data(), impact_jacobian_.data(), gap_gradient_.data(), &gamma);
    if (!(v < 0))
      throw SimulationError("tangent flow: contact '" + contact(first) + "' grazes (approach speed " +
                                number(v) + " >= 0): its saltation matrix is not defined",
                            t);
    const double e = model_.restitution[static_cast<std::size_t>(first)];
    std::fill(zero_.begin(), zero_.end(), 0.0);
    model_.evaluate_direction(model_.model, x, x + c, t, zero_.data(), qdd_minus_.data(), scratch_.data());
    // Where a plain run lets the contact rest (a plastic impact; the Zeno
    // rule: an accumulation of impacts while the forces press the contact
    // shut, d²φ/dt² = G q̈ + γ < 0) the model holds it shut after an impact
    // with e = 0; a touch slower than the touch speed stops the run.
    ContactHistory& history = history_[static_cast<std::size_t>(first)];
    const auto pressed = [&] {
      double accel = gamma;
      for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) accel += gap_gradient_[k] * qdd_minus_[k];
      return accel < 0;
    };
    if (-v <= run_.contact_touch_speed)
      throw SimulationError("tangent flow: contact '" + contact(first) + "' comes to rest (approach speed " +
                                number(-v) +
                                ", not above contact_touch_speed): the tangent flow through a touch without an "
                                "impact is not derived",
                            t);
    const bool zeno = zeno_accumulation(history, -v, t, run_, predicate(pressed));
    const bool rest = zeno || e == 0;
    if (rest) {
      const std::string why = zeno ? "an accumulation of impacts with the forces pressing it shut, where the plain "
                                     "run's Zeno rule lets it rest"
                                   : "a plastic impact, e = 0: the bodies stick, and a plain run holds the contact "
                                     "shut";
      if (model_.rest == nullptr)
        throw SimulationError("tangent flow: contact '" + contact(first) + "' comes to rest (approach speed " +
                                  number(-v) + ": " + why +
                                  "): the tangent flow through a resting contact is not derived for this model",
                              t);
      if (columns_ > k_)
        throw SimulationError("tangent flow: contact '" + contact(first) + "' comes to rest (" + why +
                                  "): a parameter's column through a resting contact is not derived",
                              t);
      // The last impact is plastic (the plain run's law at a rest).
      model_.impact(model_.model, x, x + c, t, first, 0.0, qd_plus_.data(), impact_jacobian_.data(),
                    gap_gradient_.data(), &gamma);
      model_.rest(model_.model, first, true);
      resting_[static_cast<std::size_t>(first)] = 1;
      if (multiplier(x, qd_plus_.data(), t, first) < 0) {
        // The forces pull the bodies apart at once (a plain run lets the
        // contact rest and lift off at the same instant): a plastic impact
        // into the free motion.
        model_.rest(model_.model, first, false);
        resting_[static_cast<std::size_t>(first)] = 0;
      } else {
        ++resting_count_;
        ++rests_;
        last_rest_ = first;
        rest_due_ = benettin_;
      }
    }
    history.record(-v, t);
    // f⁺: the motion after the impact (with the contact held shut after a rest).
    model_.evaluate_direction(model_.model, x, qd_plus_.data(), t, zero_.data(), qdd_plus_.data(), scratch_.data());
    saltation_from(n, x + c, qdd_minus_.data(), qd_plus_.data(), qdd_plus_.data(), impact_jacobian_.data(),
                   gap_gradient_.data(), v, salt_scratch_.data(), saltation_.data());
    load(x);
    const Eigen::Map<const Eigen::MatrixXd> s(saltation_.data(), 2 * n, 2 * n);
    jumped_.noalias() = s * w_;
    w_ = jumped_;
    // A parameter's column s becomes S s + R_p + a ∂φ/∂p / v, with
    // R_p = (0, ∂q̇⁺/∂p) at the state before the impact and
    // a = f⁺ − R_x f⁻ − R_t (saltation_from()'s scratch): the impact map
    // and the gap move with the parameter too.
    const Eigen::Map<const Eigen::VectorXd> a(salt_scratch_.data(), 2 * n);
    for (int j = k_; j < columns_; ++j) {
      const double dgap = model_.parameter_impact(model_.model, x, x + c, t, first,
                                                  parameters_[static_cast<std::size_t>(j - k_)], scratch_.data());
      w_.col(j) += a * (dgap / v);
      w_.col(j).tail(n) += Eigen::Map<const Eigen::VectorXd>(scratch_.data(), n);
    }
    std::copy(qd_plus_.begin(), qd_plus_.end(), x + c);
    store(x);
    if (benettin_) {
      // ℓ jumps at the impact: ∫ s dℓ gains s (ℓ⁺ − ℓ⁻).
      ell_ = log_length(x);
      megno_i_ += (t - t0_) * (ell_ - ell_before);
      if (t > t0_) megno_ = 2 * megno_i_ / (t - t0_);
    }
    if (!(zeno && resting_[static_cast<std::size_t>(first)])) ++impacts_;
    return true;
  }

  TangentModel model_;
  int k_, columns_;
  std::vector<int> parameters_;
  bool record_;
  std::vector<double> times_;
  std::vector<Eigen::VectorXd> states_;
  std::vector<Eigen::MatrixXd> columns_taken_;
  double longest_;
  bool benettin_;
  mutable std::vector<double> qdd_, jacobian_;
  mutable std::vector<double> direction_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n));
  mutable std::uint64_t evaluations_ = 0;
  Eigen::MatrixXd w_, start_basis_;  // start_basis_: B0 on a manifold
  std::vector<double> p_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n * model_.n));
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr_;
  std::vector<double> sums_, lengths_ = std::vector<double>(static_cast<std::size_t>(k_), 1.0);
  double last_ = 0, t0_ = 0;
  // MEGNO: ℓ at the last step end, its offset, I, Y and ∫ Y ds.
  double ell_ = 0, ell_offset_ = 0, megno_i_ = 0, megno_ = 0, megno_integral_ = 0;
  std::vector<double> mid_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n * (1 + columns_)));
  // Contacts: gaps at the step's ends and inside it, the impact map, the
  // accelerations either side, S and the columns after it.
  std::vector<double> gap_old_ = std::vector<double>(static_cast<std::size_t>(model_.contacts)),
                      gap_new_ = gap_old_, gap_at_ = gap_old_, rate_old_ = gap_old_, rate_new_ = gap_old_,
                      rate_at_ = gap_old_;
  SimulationOptions run_;
  std::vector<ContactHistory> history_ = std::vector<ContactHistory>(static_cast<std::size_t>(model_.contacts));
  EventProgress progress_;
  std::vector<double> qd_plus_ = std::vector<double>(static_cast<std::size_t>(model_.n)),
                      impact_jacobian_ = std::vector<double>(static_cast<std::size_t>(model_.n * (2 * model_.n + 1))),
                      gap_gradient_ = qd_plus_, qdd_minus_ = qd_plus_, qdd_plus_ = qd_plus_, scratch_ = qd_plus_,
                      zero_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n)),
                      saltation_ = std::vector<double>(static_cast<std::size_t>(4 * model_.n * model_.n)),
                      salt_scratch_ = zero_;
  Eigen::MatrixXd jumped_;
  // The constraint manifold: its rows and their Jacobian, U (configuration_basis()).
  Eigen::MatrixXd reduce_;
  std::vector<double> residual_ = std::vector<double>(static_cast<std::size_t>(model_.manifold)),
                      manifold_jacobian_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n * model_.manifold));
  int impacts_ = 0;
  // Resting contacts (TangentModel::rest): which rest, how many rested and
  // lifted off, the last to rest; Benettin's vectors a rest removed, the
  // others (live_), and a renormalisation due after a rest.
  std::vector<char> resting_ = std::vector<char>(static_cast<std::size_t>(model_.contacts), 0);
  int resting_count_ = 0, rests_ = 0, releases_ = 0, last_rest_ = 0;
  std::vector<char> dead_ = std::vector<char>(static_cast<std::size_t>(k_), 0);
  std::vector<int> live_;
  bool rest_due_ = false;
  // multiplier()'s: the resting contacts, q̈_f, ∂p/∂(q, q̇), an impact map.
  std::vector<int> held_;
  std::vector<double> held_free_ = std::vector<double>(static_cast<std::size_t>(model_.n)),
                      held_scratch_ = held_free_, held_gradient_ = held_free_,
                      held_momentum_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n * model_.n)),
                      held_jacobian_ = std::vector<double>(static_cast<std::size_t>(model_.n * (2 * model_.n + 1)));
  int renormalisations_ = 0;
  double shortest_ = std::numeric_limits<double>::infinity();
  double longest_taken_ = 0;
};

}  // namespace lagrangian::detail
