#pragma once
// Internal: the contacts a tangent run holds shut where a plain run lets
// them rest (tangent_system.hpp), through TangentModel::rest.

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/QR>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/integrate/detail/contact_rules.hpp"
#include "lagrangian/integrate/detail/roots.hpp"
#include "lagrangian/integrate/system.hpp"
#include "tangent_messages.hpp"

namespace lagrangian::detail {

/// The contacts a tangent run holds shut, on the state x of the augmented
/// system (q at x, q̇ at x + c, c its coordinate count). A contact rests
/// (hold()) after the plastic impact that begins its rest, unless the
/// forces already pull it open; it lifts off at the first time its
/// multiplier λ_j is negative, the plain run's rule (lift_off());
///   M q̈ = M q̈_f + Cᵀλ,  C q̈ + γ = 0  ⇒  (C M⁻¹ Cᵀ) λ = −γ − C q̈_f,
/// C the resting contacts' G = ∂φ/∂q and γ (their impact maps'), q̈_f the
/// free motion's (the contacts opened for the moment): λ from the hooks
/// every model with contacts has. Its buffers are sized once.
class RestingContacts {
 public:
  RestingContacts(const TangentModel& model, int coordinates)
      : model_(model), c_(coordinates), resting_(static_cast<std::size_t>(model.contacts), 0),
        state_(static_cast<std::size_t>(2 * coordinates)), free_(static_cast<std::size_t>(model.n)),
        scratch_(free_), gradient_(free_), zero_(static_cast<std::size_t>(2 * model.n), 0.0),
        momentum_(static_cast<std::size_t>(2 * model.n * model.n)),
        jacobian_(static_cast<std::size_t>(model.n * (2 * model.n + 1))) {}

  bool resting(int j) const { return resting_[static_cast<std::size_t>(j)] != 0; }
  int count() const { return count_; }
  /// Contacts that came to rest, and resting contacts that lifted off.
  int rests() const { return rests_; }
  int releases() const { return releases_; }
  /// The contact that came to rest last.
  int last() const { return last_; }

  /// SimulationError unless contact j, coming to rest at t at approach
  /// speed `approach` (its Zeno rule, or else a plastic impact), can be
  /// held: the model has TangentModel::rest and, for a run with parameter
  /// columns, TangentModel::rest_holds_parameters (its seeded twins hold
  /// the contact too).
  void require_holdable(int j, double approach, bool zeno, bool parameter_columns, double t) const {
    const std::string why = zeno ? "an accumulation of impacts with the forces pressing it shut, where the plain "
                                   "run's Zeno rule lets it rest"
                                 : "a plastic impact, e = 0: the bodies stick, and a plain run holds the contact "
                                   "shut";
    if (model_.rest == nullptr)
      throw SimulationError("tangent flow: contact '" + contact_name(model_, j) + "' comes to rest (approach speed " +
                                short_number(approach) + ": " + why +
                                "): the tangent flow through a resting contact is not derived for " +
                                (model_.manifold > 0 ? "a model with holonomic or Pfaffian constraints" : "this model"),
                            t);
    if (parameter_columns && !model_.rest_holds_parameters)
      throw SimulationError("tangent flow: contact '" + contact_name(model_, j) + "' comes to rest (" + why +
                                "): a parameter's column through a resting contact is not derived for this model "
                                "(its seeded twins do not hold the contact)",
                            t);
  }

  /// Contact j holds shut from (q, q̇⁺, t), just after its plastic impact;
  /// false (and it stays open) when its multiplier there is already
  /// negative: a plain run lets it rest and lift off at one instant, so the
  /// motion after the impact is the free one.
  bool hold(const double* q, const double* qd_plus, double t, int j) {
    model_.rest(model_.model, j, true);
    resting_[static_cast<std::size_t>(j)] = 1;
    if (multiplier(q, qd_plus, t, j) < 0) {
      model_.rest(model_.model, j, false);
      resting_[static_cast<std::size_t>(j)] = 0;
      return false;
    }
    ++count_;
    ++rests_;
    last_ = j;
    return true;
  }

  /// The earliest lift-off in (t_old, t] of a resting contact
  /// (locate_lift_off() on λ_j along the step): (t, x) move there and the
  /// contact is returned; −1 when none.
  int lift_off(double t_old, const double* x_old, double& t, double* x, const StepInterpolant& interpolant) {
    int which = -1;
    double at = t;
    for (int j = 0; j < model_.contacts; ++j) {
      if (!resting(j)) continue;
      const double end = multiplier(x, x + c_, t, j);
      if (!(end < 0)) continue;
      const auto lambda = [&](double s) {
        interpolant(s, state_.data());
        return multiplier(state_.data(), state_.data() + c_, s, j);
      };
      const double found =
          locate_lift_off(t_old, t, multiplier(x_old, x_old + c_, t_old, j), end, time_function(lambda));
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

  /// Contact j opens (it lifted off).
  void release(int j) {
    model_.rest(model_.model, j, false);
    resting_[static_cast<std::size_t>(j)] = 0;
    --count_;
    ++releases_;
  }

  /// SimulationError when a resting contact's gap has left 0 by more than
  /// 1e-6 (1 + ‖q‖∞): the motion along it drifted (the tangent run holds
  /// φ̈ = 0 without stabilisation). `gap` and `rate` take the contacts'
  /// values.
  void check_gaps(const double* x, double t, double* gap, double* rate) const {
    model_.gaps(model_.model, x, x + c_, t, gap, rate);
    const double tolerance = 1000 * contact_touch_tolerance(x, model_.n);
    for (int j = 0; j < model_.contacts; ++j)
      if (resting(j) && !(std::abs(gap[j]) <= tolerance))
        throw SimulationError("tangent flow: resting contact '" + contact_name(model_, j) + "' drifted to a gap of " +
                                  short_number(gap[j]) + " (tolerance " + short_number(tolerance) + ")",
                              t);
  }

  /// Calls `law()`, which evaluates an impact law of contact `closing`
  /// through the model's hooks, with the law a plain run applies: Newton's
  /// law of the closing contact alone, the other resting contacts no rows
  /// of it. A model whose impact hooks give that law whatever it holds
  /// (TangentModel::impact_alone_while_resting) is called as it is; one
  /// whose held contacts are rows of its passes and so of its law (a text
  /// model's, FixedSizeModel::hold()) has the other resting contacts opened
  /// for the call and held again after it. (An exception
  /// from `law` ends the tangent run; they are not held again then.)
  template <class Law>
  void with_law_alone(int closing, Law&& law) {
    if (model_.impact_alone_while_resting || count_ == 0) {
      law();
      return;
    }
    opened_.clear();
    for (int j = 0; j < model_.contacts; ++j)
      if (resting(j) && j != closing) opened_.push_back(j);
    for (int j : opened_) model_.rest(model_.model, j, false);
    law();
    for (int j : opened_) model_.rest(model_.model, j, true);
  }

  /// The resting contacts that the impulse of contact `closing` (q̇⁺ in
  /// `qd_plus`, approach speed −v, at (q, t) of x) sets separating faster
  /// than `touch_speed` (m/s), into `lifting`: a plain run releases them at
  /// the impact, and so does the tangent run (release(), after f⁻), with
  /// f⁺ of the motion without them; a neighbouring start rests as well and
  /// lifts off at its own impact. An impulse orthogonal in M⁻¹ to the
  /// resting contacts' (a wall's while a floor holds) leaves them held, and
  /// the saltation matrix carries the held motion's tangent vectors across.
  /// SimulationError when a resting contact's rate changes by more than
  /// 1e-9 |v| otherwise: set approaching (a plain run resolves it as another
  /// impact at the same instant) or separating no faster than the touch
  /// speed (a plain run keeps it resting). `gap`, `before`, `after`:
  /// buffers of one value per contact.
  void lifted_by(int closing, const double* x, const double* qd_plus, double v, double t, double touch_speed,
                 double* gap, double* before, double* after, std::vector<int>& lifting) const {
    lifting.clear();
    model_.gaps(model_.model, x, x + c_, t, gap, before);
    model_.gaps(model_.model, x, qd_plus, t, gap, after);
    for (int j = 0; j < model_.contacts; ++j) {
      const double change = after[j] - before[j];
      if (!resting(j) || std::abs(change) <= 1e-9 * std::abs(v)) continue;
      if (after[j] > touch_speed) {
        lifting.push_back(j);
        continue;
      }
      throw SimulationError("tangent flow: the impulse of contact '" + contact_name(model_, closing) +
                                "' sets resting contact '" + contact_name(model_, j) + "' moving (its rate changes by " +
                                short_number(change) +
                                (after[j] < 0 ? "; a plain run resolves it as another impact at the same instant): "
                                                "impacts in sequence at one instant are not derived"
                                              : ", separating no faster than contact_touch_speed: a plain run keeps "
                                                "it resting): not derived"),
                            t);
    }
  }

 private:
  /// λ_j (N for a distance gap; > 0 presses the bodies apart) of resting
  /// contact j at (q, q̇, t) (the class comment).
  double multiplier(const double* q, const double* qd, double t, int wanted) {
    const int n = model_.n;
    held_.clear();
    for (int j = 0; j < model_.contacts; ++j)
      if (resting(j)) held_.push_back(j);
    for (int j : held_) model_.rest(model_.model, j, false);
    model_.evaluate_direction(model_.model, q, qd, t, zero_.data(), free_.data(), scratch_.data());
    for (int j : held_) model_.rest(model_.model, j, true);
    model_.momentum(model_.model, q, qd, t, momentum_.data(), nullptr);
    const auto rows = static_cast<Eigen::Index>(held_.size());
    Eigen::MatrixXd g(rows, n);
    Eigen::VectorXd b(rows);
    Eigen::Index which = -1;
    for (Eigen::Index i = 0; i < rows; ++i) {
      const int j = held_[static_cast<std::size_t>(i)];
      double gamma = 0;
      model_.impact(model_.model, q, qd, t, j, 0.0, scratch_.data(), jacobian_.data(), gradient_.data(), &gamma);
      const Eigen::Map<const Eigen::VectorXd> gradient(gradient_.data(), n), free(free_.data(), n);
      g.row(i) = gradient.transpose();
      b[i] = -gamma - gradient.dot(free);
      if (j == wanted) which = i;
    }
    if (which < 0)
      throw std::logic_error("RestingContacts::multiplier: contact " + contact_name(model_, wanted) + " is not resting");
    const Eigen::LLT<Eigen::MatrixXd> mass(Eigen::Map<const Eigen::MatrixXd>(momentum_.data(), n, 2 * n).rightCols(n));
    const Eigen::MatrixXd minv_gt = mass.solve(g.transpose());
    const Eigen::VectorXd lambda = (g * minv_gt).completeOrthogonalDecomposition().solve(b);
    return lambda[which];
  }

  TangentModel model_;
  int c_;
  std::vector<char> resting_;
  int count_ = 0, rests_ = 0, releases_ = 0, last_ = 0;
  // The resting contacts, those opened for an impact law, a state on the
  // step, q̈_f, ∂p/∂(q, q̇), an impact map.
  std::vector<int> held_, opened_;
  std::vector<double> state_, free_, scratch_, gradient_, zero_, momentum_, jacobian_;
};

}  // namespace lagrangian::detail
