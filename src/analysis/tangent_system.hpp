#pragma once
// Internal: the state with k tangent vectors beside it, as one System for
// the driver (lyapunov.cpp, floquet.cpp).

#include <algorithm>
#include <cmath>
#include <cstdint>
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
#include "resting_contacts.hpp"

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
/// plastic impact) the impact with e = 0 is crossed into the motion that
/// holds it shut (resting_contacts.hpp), whose saltation matrix removes
/// δφ_j and δφ̇_j: Benettin's vectors are renormalised at once and those
/// that vanished left out (exponents −∞); at its lift-off (λ_j = 0, the
/// rates agree) the columns cross unchanged. Refused with SimulationError:
/// a rest on a model without TangentModel::rest, or with parameter columns
/// that it does not hold (TangentModel::rest_holds_parameters),
/// a touch not faster than contact_touch_speed, an impact while a contact
/// rests that resting_contacts.hpp does not allow, a grazing contact, two
/// contacts closing or touching at once.
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
      manifold_.check(x, t0);
      // B0, the tangent space's basis (H at the start, from check()).
      start_basis_ = tangent_basis(manifold_.jacobian(), 2 * model_.n);
    }
    if (benettin_ && model_.manifold > 0) {
      // The first k vectors of B0, orthonormal in reduced canonical coordinates.
      canonical(x, t0);
      qr_.compute(manifold_.reduced_canonical(start_basis_, dp_dx()));
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
    const int lifted = resting_.count() > 0 ? resting_.lift_off(t_old, x_old, t, x, interpolant) : -1;
    const bool impact = model_.contacts > 0 && cross_impact(t_old, x_old, t, x, interpolant);
    if (lifted >= 0) resting_.release(lifted);
    if (resting_.count() > 0) resting_.check_gaps(x, t, gap_at_.data(), rate_at_.data());
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
  int rests() const { return resting_.rests(); }
  int releases() const { return resting_.releases(); }
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
    const Eigen::Map<const Eigen::MatrixXd> dp = dp_dx();
    llt_.compute(dp.rightCols(n));
    if (llt_.info() != Eigen::Success)
      throw SimulationError("lyapunov: the mass matrix dp/dqd is not positive definite", t);
  }
  /// ∂p/∂(q, q̇) (n × 2n) of the last canonical().
  Eigen::Map<const Eigen::MatrixXd> dp_dx() const {
    return Eigen::Map<const Eigen::MatrixXd>(p_.data(), model_.n, 2 * model_.n);
  }
  /// W = P⁻¹ Z: δq = Z_q, δq̇ = M⁻¹ (Z_p − (∂p/∂q) Z_q).
  Eigen::MatrixXd from_canonical(const Eigen::MatrixXd& z) const {
    const int n = model_.n;
    const Eigen::Map<const Eigen::MatrixXd> dp = dp_dx();
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
    if (model_.manifold > 0) {
      manifold_.project(x, t, w_);
      store(x);
    }
    canonical(x, t);
    const Eigen::Map<const Eigen::MatrixXd> dp = dp_dx();
    if (model_.manifold > 0) {  // (no contacts: no vector leaves)
      live_.resize(static_cast<std::size_t>(k_));
      for (int j = 0; j < k_; ++j) live_[static_cast<std::size_t>(j)] = j;
      qr_.compute(manifold_.reduced_canonical(w_, dp));
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
        throw SimulationError("lyapunov: the rest of contact '" + contact(resting_.last()) +
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
      throw SimulationError("lyapunov: the rest of contact '" + contact(resting_.last()) + "' removed " +
                                std::to_string(gone) + " tangent vectors; one rest removes at most 2",
                            t);
    return gone > 0;
  }

  /// x with 6 significant digits, for messages.
  static std::string number(double x) { return short_number(x); }
  std::string contact(int j) const { return contact_name(model_, j); }
  /// The earliest contact closing in the step (t_old, t], located by the
  /// plain run's rules (locate_closing: crossings, dips of the gap, a
  /// contact leaving and coming back within the step): false when none;
  /// otherwise the step end moves to the impact (t, x), MEGNO is taken to
  /// it, the impact law applied to q̇ and the saltation matrix to every
  /// column; where a plain run lets the contact rest (the Zeno rule, a
  /// plastic impact) the impact is plastic and the contact rests from then
  /// on (TangentModel::rest). SimulationError for a rest the model cannot
  /// hold (above), a touch slower than contact_touch_speed, an impact while
  /// another contact rests (refuse_impact(), require_unmoved()), two
  /// contacts closing or touching at one instant,
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
      if (resting_.resting(j)) continue;  // held shut
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
    resting_.refuse_impact(first, at);
    progress_.check(at, t_old);
    if (at < t) interpolant(at, x);
    if (benettin_) megno_step(t_old, at, x, interpolant);
    t = at;
    // Another open contact touching at the impact (a ball in a corner, a
    // row of touching spheres): impacts in sequence at one instant.
    model_.gaps(model_.model, x, x + c, t, gap_at_.data(), rate_at_.data());
    for (int j = 0; j < model_.contacts; ++j)
      if (j != first && !resting_.resting(j) &&
          std::abs(gap_at_[static_cast<std::size_t>(j)]) <= contact_touch_tolerance(x, n))
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
    if (resting_.count() > 0)
      resting_.require_unmoved(first, x, qd_plus_.data(), v, t, gap_at_.data(), rate_at_.data(), rate_old_.data());
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
      resting_.require_holdable(first, -v, zeno, columns_ > k_, t);
      // The last impact is plastic (the plain run's law at a rest).
      model_.impact(model_.model, x, x + c, t, first, 0.0, qd_plus_.data(), impact_jacobian_.data(),
                    gap_gradient_.data(), &gamma);
      // (Unless the forces pull the bodies apart at once: then a plastic
      // impact into the free motion.)
      if (resting_.hold(x, qd_plus_.data(), t, first)) rest_due_ = benettin_;
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
                                                  parameters_[static_cast<std::size_t>(j - k_)], rest, scratch_.data());
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
    if (!(zeno && resting_.resting(first))) ++impacts_;
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
  TangentManifold manifold_{model_, model_.n * (1 + columns_)};  // (models with holonomic or Pfaffian rows)
  int impacts_ = 0;
  // Resting contacts (TangentModel::rest); Benettin's vectors a rest
  // removed, the others (live_), and a renormalisation due after a rest.
  RestingContacts resting_{model_, model_.n * (1 + columns_)};
  std::vector<char> dead_ = std::vector<char>(static_cast<std::size_t>(k_), 0);
  std::vector<int> live_;
  bool rest_due_ = false;
  int renormalisations_ = 0;
  double shortest_ = std::numeric_limits<double>::infinity();
  double longest_taken_ = 0;
};

}  // namespace lagrangian::detail
