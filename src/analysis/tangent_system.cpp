// The state with k tangent vectors beside it, as one System for the driver
// (tangent_system.hpp): compiled once, here, for the analyses that run it
// (lyapunov.cpp, floquet.cpp, sensitivity.cpp).

#include "tangent_system.hpp"

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

#include "lagrangian/analysis/saltation.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/integrate/detail/roots.hpp"

namespace lagrangian::detail {

TangentSystem::TangentSystem(const TangentModel& model, int k, double longest, bool benettin,
                             std::vector<int> parameters, bool record)
    : model_(model), k_(k), columns_(k + static_cast<int>(parameters.size())), parameters_(std::move(parameters)),
      record_(record), longest_(longest), benettin_(benettin), qdd_(static_cast<std::size_t>(model.n)),
      jacobian_(static_cast<std::size_t>(2 * model.n * model.n)), w_(2 * model.n, columns_), qr_(2 * model.n, k),
      sums_(static_cast<std::size_t>(k), 0.0) {
  if (benettin_ && columns_ != k_)
    throw std::logic_error("TangentSystem: Benettin's method takes no parameter columns");
  if (model_.contacts > 0 && columns_ != k_ && model_.parameter_impact == nullptr)
    throw std::logic_error(
        "TangentSystem: parameter columns of a model with contacts need its parameter_impact");
  jumped_.resize(2 * model_.n, columns_);
  lifting_.reserve(static_cast<std::size_t>(model_.contacts));
}

TangentSystem::~TangentSystem() = default;

void TangentSystem::rhs(const double* x, double* dxdt, double t) const {
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

void TangentSystem::start(double* x, double t0) {
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

void TangentSystem::sample(double t, const double* x) {
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

void TangentSystem::finish(double t, const double* x, bool sample_end) {
  if (sample_end) sample(t, x);
}

bool TangentSystem::handle_events(double t_old, const double* x_old, double& t, double* x,
                                  const StepInterpolant& interpolant) {
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

void TangentSystem::close(double* x, double t) {
  load(x);
  if (t > last_) renormalise(x, t);
}

const Eigen::MatrixXd& TangentSystem::tangents(const double* x) {
  load(x);
  return w_;
}

void TangentSystem::load_direction(const double* x, int j) const {
  const int n = model_.n, c = coordinate_count();
  std::copy(x + j * n, x + (j + 1) * n, direction_.begin());
  std::copy(x + c + j * n, x + c + (j + 1) * n, direction_.begin() + n);
}

void TangentSystem::load(const double* x) {
  const int n = model_.n, c = coordinate_count();
  w_.topRows(n) = Eigen::Map<const Eigen::MatrixXd>(x + n, n, columns_);
  w_.bottomRows(n) = Eigen::Map<const Eigen::MatrixXd>(x + c + n, n, columns_);
}

void TangentSystem::store(double* x) const {
  const int n = model_.n, c = coordinate_count();
  Eigen::Map<Eigen::MatrixXd>(x + n, n, columns_) = w_.topRows(n);
  Eigen::Map<Eigen::MatrixXd>(x + c + n, n, columns_) = w_.bottomRows(n);
}

void TangentSystem::canonical(const double* x, double t) {
  const int n = model_.n, c = coordinate_count();
  model_.momentum(model_.model, x, x + c, t, p_.data(), nullptr);
  const Eigen::Map<const Eigen::MatrixXd> dp = dp_dx();
  llt_.compute(dp.rightCols(n));
  if (llt_.info() != Eigen::Success)
    throw SimulationError("lyapunov: the mass matrix dp/dqd is not positive definite", t);
}

Eigen::MatrixXd TangentSystem::from_canonical(const Eigen::MatrixXd& z) const {
  const int n = model_.n;
  const Eigen::Map<const Eigen::MatrixXd> dp = dp_dx();
  Eigen::MatrixXd w(2 * n, z.cols());
  w.topRows(n) = z.topRows(n);
  w.bottomRows(n) = llt_.solve(z.bottomRows(n) - dp.leftCols(n) * z.topRows(n));
  return w;
}

double TangentSystem::log_length(const double* x) const {
  const int n = model_.n, c = coordinate_count();
  double s2 = 0;
  for (int i = 0; i < n; ++i) s2 += x[n + i] * x[n + i] + x[c + n + i] * x[c + n + i];
  return ell_offset_ + 0.5 * std::log(s2);
}

void TangentSystem::megno_step(double a, double b, const double* x, const StepInterpolant& interpolant) {
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

void TangentSystem::remember_lengths() {
  for (int j = 0; j < k_; ++j) lengths_[static_cast<std::size_t>(j)] = w_.col(j).norm();
}

void TangentSystem::renormalise(double* x, double t) {
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

void TangentSystem::live_canonical(const Eigen::Map<const Eigen::MatrixXd>& dp) {
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

bool TangentSystem::collapse(double t) {
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

bool TangentSystem::cross_impact(double t_old, const double* x_old, double& t, double* x,
                                 const StepInterpolant& interpolant) {
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
  double gamma = 0, v = 0;
  resting_.with_law_alone(first, [&] {
    v = model_.impact(model_.model, x, x + c, t, first, model_.restitution[static_cast<std::size_t>(first)],
                      qd_plus_.data(), impact_jacobian_.data(), gap_gradient_.data(), &gamma);
  });
  if (!(v < 0))
    throw SimulationError("tangent flow: contact '" + contact(first) + "' grazes (approach speed " +
                              number(v) + " >= 0): its saltation matrix is not defined",
                          t);
  lifting_.clear();
  if (resting_.count() > 0)
    resting_.lifted_by(first, x, qd_plus_.data(), v, t, run_.contact_touch_speed, gap_at_.data(), rate_at_.data(),
                       rate_old_.data(), lifting_);
  const double e = model_.restitution[static_cast<std::size_t>(first)];
  std::fill(zero_.begin(), zero_.end(), 0.0);
  model_.evaluate_direction(model_.model, x, x + c, t, zero_.data(), qdd_minus_.data(), scratch_.data());
  // Resting contacts the impulse sets separating lift off at the impact, as
  // in a plain run: f⁻ above is the held motion's, f⁺ below the motion's
  // without them.
  for (int j : lifting_) resting_.release(j);
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
    resting_.with_law_alone(first, [&] {
      model_.impact(model_.model, x, x + c, t, first, 0.0, qd_plus_.data(), impact_jacobian_.data(),
                    gap_gradient_.data(), &gamma);
    });
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
    double dgap = 0;
    resting_.with_law_alone(first, [&] {
      dgap = model_.parameter_impact(model_.model, x, x + c, t, first, parameters_[static_cast<std::size_t>(j - k_)],
                                     rest, scratch_.data());
    });
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

}  // namespace lagrangian::detail
