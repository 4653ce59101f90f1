#pragma once
// ModelSystem's members for events: location of contacts closing, lift-offs
// and watched events inside a step, and the sequential resolution of
// impacts with the Zeno rule. Included by model_system.hpp.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "lagrangian/integrate/detail/contact_rules.hpp"
#include "lagrangian/integrate/detail/contacts.hpp"
#include "lagrangian/integrate/detail/roots.hpp"
#include "lagrangian/integrate/detail/model_system.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/impact.hpp"

namespace lagrangian::detail {

template <class M>
bool ModelSystem<M>::locate_events(double t_old, const double* x_old, double& t, double* x, const StepInterpolant& interp) {
  ContactEvent contact;
  if constexpr (unilateral_count_v<M> != 0) {
    if (contacts_) contact = contact_events_.first(*contacts_, t_old, x_old, t, x, interp, opt_.contact_touch_speed);
  }
  // Watched events: a sign change between the step's ends in their direction.
  int watched = -1;
  double best_t = contact.t;
  if constexpr (event_count_v<M> > 0) {
    std::vector<double>& buf = event_buf_;
    Vec<double, event_count_v<M>> fa = watched_at(x_old, t_old), fb = watched_at(x, t);
    for (int k = 0; k < event_count_v<M>; ++k) {
      const Direction d = specs_[static_cast<std::size_t>(k)].direction;
      const bool falls = fa[k] > 0 && fb[k] <= 0, rises = fa[k] < 0 && fb[k] >= 0;
      if (!((falls && d != Direction::rising) || (rises && d != Direction::falling))) continue;
      auto f = [&](double ts) {
        if (ts == t) return fb[k];
        interp(ts, buf.data());
        return watched_at(buf.data(), ts)[k];
      };
      const double tc = locate_crossing(t_old, t, fa[k], fb[k], time_function(f));
      if (tc < best_t) {
        best_t = tc;
        watched = k;
      }
    }
  }
  if (contact.kind == ContactEvent::Kind::none && watched < 0) return false;
  contact_events_.move_to(best_t, t_old, interp, t, x, size_);
  if (watched < 0) {
    if constexpr (unilateral_count_v<M> != 0) contact_events_.apply(*contacts_, contact, x, t, opt_, report_);
    return true;
  }
  const EventSpec& s = specs_[static_cast<std::size_t>(watched)];
  log_simple(EventKind::watched, s.name, t, x);
  if (s.action == EventAction::stop) {
    log_simple(EventKind::stop, s.name, t, x);
    stopped_ = true;
    report_.stopped_at = t;
    report_.stopped_by = s.name;
  }
  return true;
}

/// A model's contacts for detail::resolve_contacts: contact j is its
/// unilateral constraint j, resting when it is in the active set.
template <class M>
class ModelSystem<M>::Contacts final : public ContactSystem {
 public:
  explicit Contacts(ModelSystem& s) : s_(s), q_(s.size_), qd_(s.size_) {}

  int coordinates() const override { return s_.size_; }
  std::string contact_name(int j) const override { return s_.contact_name(j); }
  void gap_rates(const double* x, double t, const std::vector<int>& which, GapRate* out) override {
    [[maybe_unused]] Vec<double, u_> g_local, r_local;
    auto& g = u_ == Dynamic ? s_.gap_in_ : g_local;
    auto& r = u_ == Dynamic ? s_.rate_in_ : r_local;
    split_state(x, q_, qd_);
    contact_gaps(s_.model_, q_, qd_, t, g, r);
    for (std::size_t k = 0; k < which.size(); ++k) out[k] = {g[which[k]], r[which[k]]};
  }
  void near(const double*, double, double, int, std::vector<int>& out) override {
    out.resize(static_cast<std::size_t>(unilateral_count(s_.model_)));
    for (std::size_t j = 0; j < out.size(); ++j) out[j] = static_cast<int>(j);
  }
  ContactHistory& history(int j) override { return s_.history_[static_cast<std::size_t>(j)]; }
  double restitution(int j) const override {
    if constexpr (has_restitution_v<M>) {
      return s_.restitution_[static_cast<std::size_t>(j)];
    } else {
      (void)j;
      return std::numeric_limits<double>::quiet_NaN();
    }
  }
  bool pressed(int j, const double* x, double t) override {
    split_state(x, q_, qd_);
    return s_.gap_acceleration(q_, qd_, t, j) < 0;
  }
  LawResult apply_law(int j, double e, double* x, double t, bool record) override {
    split_state(x, q_, qd_);
    const double h_before = record ? energy_function(s_.model_, q_, qd_, t) : 0.0;
    ImpactResult<n> r;
    try {
      r = restitution_impact(s_.model_, s_.ws_, q_, qd_, t, j, e, record, s_.cw_.schur_solver);
    } catch (const DynamicsError& err) {
      throw SimulationError(std::string("impact failed: ") + err.what(), t);
    }
    set_velocities(x);
    if (record) s_.shift_reference_energy(q_, qd_, t, h_before, r.kinetic_energy_after - r.kinetic_energy_before);
    return {r.impulse, r.approach_speed, r.separation_speed, r.kinetic_energy_before, r.kinetic_energy_after};
  }
  std::pair<double, double> jump_velocities(double* x, const double* v, double t) override {
    split_state(x, q_, qd_);
    const double T_before = kinetic_for_log(s_.model_, s_.ws_, q_, qd_, t);
    const double h_before = energy_function(s_.model_, q_, qd_, t);
    for (int i = 0; i < s_.size_; ++i) qd_[i] = v[i];
    if constexpr (!has_kinetic_potential_v<M>) evaluate(s_.model_, s_.ws_, q_, qd_, t);
    const double T_after = kinetic_for_log(s_.model_, s_.ws_, q_, qd_, t);
    set_velocities(x);
    s_.shift_reference_energy(q_, qd_, t, h_before, T_after - T_before);
    return {T_before, T_after};
  }
  /// Gᵀ Λ = M (v − q̇), G the rows of the contacts `which`: least squares.
  void impulse_shares(const double* x, const double* v, double t, const std::vector<int>& which,
                      double* out) override {
    split_state(x, q_, qd_);
    evaluate(s_.model_, s_.ws_, q_, qd_, t);
    Vec<double, n> dv(s_.size_);
    for (int i = 0; i < s_.size_; ++i) dv[i] = v[i] - qd_[i];
    const Vec<double, n> dp = s_.ws_.mass * dv;
    const auto cs = constraint_state(s_.model_, q_, qd_, t);
    const int count = static_cast<int>(which.size()), size = s_.size_;
    std::vector<double> Gt(static_cast<std::size_t>(size * count));
    for (int k = 0; k < count; ++k)
      for (int i = 0; i < size; ++i)
        Gt[static_cast<std::size_t>(k * size + i)] =
            cs.jacobian(holonomic_count(s_.model_) + which[static_cast<std::size_t>(k)], i);
    MinNormSolver solver(size, count);
    solver.factorize(Gt.data());
    solver.solve(dp.data(), out);
  }
  double kinetic(const double* x, double t) override {
    split_state(x, q_, qd_);
    if constexpr (!has_kinetic_potential_v<M>) evaluate(s_.model_, s_.ws_, q_, qd_, t);  // M for ½ q̇ᵀMq̇
    return kinetic_for_log(s_.model_, s_.ws_, q_, qd_, t);
  }
  bool resting(int j) const override { return s_.ctx_->active.contains(j); }
  void resting_contacts(std::vector<int>& out) const override {
    out.clear();
    for (int j = 0; j < unilateral_count(s_.model_); ++j)
      if (resting(j)) out.push_back(j);
  }
  void rest(int j) override { s_.ctx_->active.insert(j); }
  void release(int j) override { s_.ctx_->active.erase(j); }
  /// Every open contact: a model's contacts are few, and each is looked at.
  void step_candidates(double, const double*, double, const double*, std::vector<int>& out) override {
    out.clear();
    for (int j = 0; j < unilateral_count(s_.model_); ++j)
      if (!resting(j)) out.push_back(j);
  }
  void resting_multipliers(const double* x, double t, const std::vector<int>& which, double* out) override {
    Vec<double, n> qdd(s_.size_);
    split_state(x, q_, qd_);
    constrained_accelerations(s_.model_, s_.ws_, s_.cw_, q_, qd_, t, qdd, 0.0, s_.ctx_->active);
    const int mh = holonomic_count(s_.model_);
    for (std::size_t k = 0; k < which.size(); ++k) out[k] = s_.cw_.multipliers[mh + which[k]];
  }
  /// On the interpolant itself.
  GapRate gap_on_path(int j, double ts, const StepInterpolant& interp) override {
    s_.event_buf_.resize(static_cast<std::size_t>(2 * s_.size_));
    interp(ts, s_.event_buf_.data());
    GapRate g;
    one_[0] = j;
    gap_rates(s_.event_buf_.data(), ts, one_, &g);
    return g;
  }

 private:
  void set_velocities(double* x) const {
    for (int i = 0; i < s_.size_; ++i) x[s_.size_ + i] = qd_[i];
  }
  ModelSystem& s_;
  Vec<double, n> q_, qd_;
  std::vector<int> one_ = std::vector<int>(1);
};

template <class M>
void ModelSystem<M>::resolve_contacts(double* x, double t, int trigger) {
  if constexpr (unilateral_count_v<M> != 0) {
    contact_events_.resolve(*contacts_, x, t, trigger, true, opt_, report_);
  } else {
    (void)x, (void)t, (void)trigger;
  }
}

/// d²φ_j/dt² = G_j q̈ + γ_j with q̈ from the current active set (contact j
/// itself inactive): negative when the forces press the contact shut.
template <class M>
double ModelSystem<M>::gap_acceleration(const Vec<double, n>& q, const Vec<double, n>& qd, double t, int j) {
  if constexpr (unilateral_count_v<M> != 0) {
    Vec<double, n> qdd(size_);
    constrained_accelerations(model_, ws_, cw_, q, qd, t, qdd, 0.0, ctx_->active.without(j));
    const auto cs = constraint_state(model_, q, qd, t);
    const int row = holonomic_count(model_) + j;
    return cs.jacobian.row(row).dot(qdd) + cs.gamma[row];
  } else {
    (void)q, (void)qd, (void)t, (void)j;
    return 0.0;
  }
}

}  // namespace lagrangian::detail
