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

#include "lagrangian/detail/contact_rules.hpp"
#include "lagrangian/detail/roots.hpp"
#include "lagrangian/detail/model_system.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/impact.hpp"

namespace lagrangian::detail {

template <class M>
bool ModelSystem<M>::locate_events(double t_old, const double* x_old, double& t, double* x, const StepInterpolant& interp) {
  // Candidate: kind 0 release, 1 contact (at the step start), 2 contact, 3 watched.
  int best_kind = -1, best_index = -1;
  double best_t = std::numeric_limits<double>::infinity();
  auto consider = [&](double tc, int kind, int index) {
    if (tc < best_t) {
      best_t = tc;
      best_kind = kind;
      best_index = index;
    }
  };
  std::vector<double>& buf = event_buf_;
  if constexpr (unilateral_count_v<M> != 0) {
    const ActiveSet act = ctx_ ? ctx_->active : ActiveSet{0};
    const int contacts = ctx_ ? unilateral_count(model_) : 0, mh = holonomic_count(model_);
    // Lift-off: an active contact whose multiplier is negative at the step end.
    if ((act & unilateral_mask(model_)) != 0) {
      auto multipliers_at = [&](const double* xs, double ts) {
        Vec<double, n> q(size_), qd(size_), qdd(size_);
        split_state(xs, q, qd);
        constrained_accelerations(model_, ws_, cw_, q, qd, ts, qdd, 0.0, act);
        return cw_.multipliers;
      };
      const auto lam_end = multipliers_at(x, t);
      for (int j = 0; j < contacts; ++j) {
        const int row = mh + j;
        if (!((act >> j) & 1u) || !(lam_end[row] < 0)) continue;
        auto f = [&](double ts) {
          if (ts == t) return lam_end[row];
          interp(ts, buf.data());
          return multipliers_at(buf.data(), ts)[row];
        };
        consider(locate_lift_off(t_old, t, f(t_old), lam_end[row], time_function(f)), 0, j);
      }
    }
    // Closing contacts among the inactive ones.
    // (On the stack for a compile-time number of contacts, the run's own
    // vectors, sized once, for a run-time one.)
    [[maybe_unused]] Vec<double, u_> ga_local, ra_local, gb_local, rb_local;
    auto& ga = u_ == Dynamic ? gap_a_ : ga_local;
    auto& ra = u_ == Dynamic ? rate_a_ : ra_local;
    auto& gb = u_ == Dynamic ? gap_b_ : gb_local;
    auto& rb = u_ == Dynamic ? rate_b_ : rb_local;
    gaps_at(x_old, t_old, ga, ra);
    gaps_at(x, t, gb, rb);
    const double touch = contact_touch_tolerance(x);
    for (int j = 0; j < contacts; ++j) {
      if ((act >> j) & 1u) continue;
      // φ_j and φ̇_j at a time inside the step.
      auto on_step = [&](double ts) {
        interp(ts, buf.data());
        [[maybe_unused]] Vec<double, u_> g_local, r_local;
        auto& g = u_ == Dynamic ? gap_in_ : g_local;
        auto& r = u_ == Dynamic ? rate_in_ : r_local;
        gaps_at(buf.data(), ts, g, r);
        return GapRate{g[j], r[j]};
      };
      const Closing c = locate_closing(t_old, t, {ga[j], ra[j]}, {gb[j], rb[j]}, touch, opt_.contact_touch_speed,
                                       gap_function(on_step));
      if (c.kind == Closing::Kind::penetrated) throw_penetrated(contact_name(j), t_old, ga[j]);
      if (c.kind == Closing::Kind::inside) consider(c.t, 2, j);  // just before contact
      if (c.kind == Closing::Kind::at_start) consider(t_old, 1, j);
    }
  }
  if constexpr (event_count_v<M> > 0) {
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
      consider(locate_crossing(t_old, t, fa[k], fb[k], time_function(f)), 3, k);
    }
  }
  if (best_kind < 0) return false;
  progress_.check(best_t, t_old);  // an event that changes nothing, found again and again
  if (best_t < t) {
    interp(best_t, buf.data());
    std::copy(buf.begin(), buf.end(), x);
    t = best_t;
  }
  if (best_kind == 0) {
    if constexpr (unilateral_count_v<M> != 0) {
      ctx_->active &= ~(ActiveSet{1} << best_index);
      log_simple(EventKind::release, contact_name(best_index), t, x);
    }
  } else if (best_kind == 1 || best_kind == 2) {
    resolve_contacts(x, t, best_index);
  } else {
    const EventSpec& s = specs_[static_cast<std::size_t>(best_index)];
    log_simple(EventKind::watched, s.name, t, x);
    if (s.action == EventAction::stop) {
      log_simple(EventKind::stop, s.name, t, x);
      stopped_ = true;
      report_.stopped_at = t;
      report_.stopped_by = s.name;
    }
  }
  return true;
}

/// Resolves every contact that is touching (|φ| within the touch
/// tolerance) and approaching faster than contact_touch_speed at (x, t),
/// one pair at a time: the one approaching fastest first, by Newton's law
/// of restitution (apply_impact), until none approaches (the sequential
/// rule for simultaneous impacts; each step conserves momentum, and kinetic
/// energy when e = 1). Zeno accumulations are resolved plastically (see
/// SimulationOptions::zeno_speed_ratio). Afterwards a contact that took
/// part (or `trigger`) and does not separate rests (becomes active) when
/// its last impact was plastic (e = 0: the bodies stick) or the forces
/// press it shut, and active contacts that separate are released.
template <class M>
void ModelSystem<M>::resolve_contacts(double* x, double t, int trigger) {
  if constexpr (unilateral_count_v<M> != 0) {
    const int u = unilateral_count(model_);
    Vec<double, n> q(size_), qd(size_);
    split_state(x, q, qd);
    const double touch = contact_touch_tolerance(x);
    [[maybe_unused]] Vec<double, u_> g_local, r_local;
    auto& g = u_ == Dynamic ? gap_in_ : g_local;
    auto& r = u_ == Dynamic ? rate_in_ : r_local;
    PerContact<char> involved{}, rested{}, plastic{};  // plastic: its last impact here had e = 0: the bodies stick
    if constexpr (u_ == Dynamic) {
      involved.assign(static_cast<std::size_t>(u), 0);
      rested = plastic = involved;
    }
    involved[static_cast<std::size_t>(trigger)] = true;
    const int max_impacts = 1000 * u;
    int count = 0;
    ImpactCycle cycle;  // the impacts since the last cycle replaced by its limit
    for (;; ++count) {
      contact_gaps(model_, q, qd, t, g, r);
      int j = -1;
      for (int i = 0; i < u; ++i)
        if ((i == trigger || g[i] <= touch) && r[i] < -opt_.contact_touch_speed && (j < 0 || r[i] < r[j])) j = i;
      if (j < 0) break;
      if (count >= max_impacts) {
        std::ostringstream os;
        os.precision(17);
        os << "simultaneous impacts at t = " << t << " did not settle after " << max_impacts
           << " pairwise impacts (contact " << contact_name(j) << " still approaching at " << -r[j] << ")";
        throw SimulationError(os.str(), t);
      }
      const std::size_t js = static_cast<std::size_t>(j);
      if constexpr (!has_restitution_v<M>) {
        std::ostringstream os;
        os.precision(17);
        os << "contact " << contact_name(j) << " closed at t = " << t << " with approach speed " << -r[j]
           << "; the model declares no restitution(), so the impact cannot be resolved";
        throw SimulationError(os.str(), t);
      }
      const double approach = -r[j];
      // An accumulation needs the forces to press the contact shut
      // (d²φ/dt² < 0 in free motion); free bodies that graze never rest.
      const auto pressed = [&] { return gap_acceleration(q, qd, t, j) < 0; };
      const bool zeno = zeno_accumulation(history_[js], approach, t, opt_, predicate(pressed));
      const double e = zeno ? 0.0 : restitution_[js];
      const double h_before = energy_function(model_, q, qd, t);
      ImpactResult<n> res;
      try {
        res = apply_impact(model_, ws_, q, qd, t, j, e);
      } catch (const DynamicsError& err) {
        throw SimulationError(std::string("impact failed: ") + err.what(), t);
      }
      const double cutoff = zeno ? zeno_cutoff(history_[js], t, restitution_[js]) : std::nan("");
      history_[js].record(approach, t);
      involved[js] = true;
      rested[js] = zeno;
      plastic[js] = e == 0.0;
      EventRecord rec;
      rec.t = t;
      rec.kind = zeno ? EventKind::rest : EventKind::impact;
      rec.name = contact_name(j);
      rec.impulse = res.impulse;
      rec.approach_speed = res.approach_speed;
      rec.separation_speed = res.separation_speed;
      rec.kinetic_energy_before = res.kinetic_energy_before;
      rec.kinetic_energy_after = res.kinetic_energy_after;
      rec.zeno_cutoff = cutoff;
      report_.events.push_back(rec);
      if (!zeno) ++report_.impacts;
      report_.impact_energy_loss += res.kinetic_energy_before - res.kinetic_energy_after;
      shift_reference_energy(q, qd, t, h_before, res.kinetic_energy_after - res.kinetic_energy_before);
      cycle.record(j, e);
      const std::vector<ImpactCycle::Impact> round = cycle.due_round(u);
      if (!round.empty() && settle_cycle(q, qd, t, round)) {
        for (const ImpactCycle::Impact& imp : round) involved[static_cast<std::size_t>(imp.contact)] = true;
        cycle.settled();
      }
    }
    contact_gaps(model_, q, qd, t, g, r);
    ActiveSet& active = ctx_->active;
    for (int j = 0; j < u; ++j) {
      const std::size_t js = static_cast<std::size_t>(j);
      const ActiveSet bit = ActiveSet{1} << j;
      const bool resting = (j == trigger || g[j] <= touch) && r[j] <= opt_.contact_touch_speed;
      if ((active & bit) && !resting) {
        active &= ~bit;
        log_simple(EventKind::release, contact_name(j), t, x);
      } else if (!(active & bit) && involved[js] && resting && (plastic[js] || gap_acceleration(q, qd, t, j) < 0)) {
        active |= bit;
        if (!rested[js]) log_simple(EventKind::rest, contact_name(j), t, x);
      }
    }
    for (int i = 0; i < size_; ++i) x[size_ + i] = qd[i];
  } else {
    (void)x, (void)t, (void)trigger;
  }
}

/// The limit of impacts that cycle (detail/impact_cycle.hpp): q̇ jumps to
/// it when the rounds converge and no contact of the round approaches there;
/// each contact of the round gets one impact in the log, with its share of
/// the total impulse M (q̇∞ − q̇) (least squares over the round's normals)
/// and the kinetic energies before and after the whole accumulation.
template <class M>
bool ModelSystem<M>::settle_cycle(const Vec<double, n>& q, Vec<double, n>& qd, double t,
                                  const std::vector<ImpactCycle::Impact>& round) {
  if constexpr (unilateral_count_v<M> != 0) {
    constexpr int u = unilateral_count_v<M>;
    const int count = unilateral_count(model_);
    Vec<double, n> w(size_), limit(size_);
    auto apply_round = [&](const double* in, double* out) {
      for (int i = 0; i < size_; ++i) w[i] = in[i];
      for (const ImpactCycle::Impact& imp : round) restitution_impact(model_, ws_, q, w, t, imp.contact, imp.e, false);
      for (int i = 0; i < size_; ++i) out[i] = w[i];
    };
    if (!round_limit(size_, qd.data(), round_map(apply_round), limit.data())) return false;
    std::vector<int> contacts;
    for (const ImpactCycle::Impact& imp : round)
      if (std::find(contacts.begin(), contacts.end(), imp.contact) == contacts.end()) contacts.push_back(imp.contact);
    // Contacts of the round left approaching by rounding: closed together.
    Vec<double, u> g(count), r_before(count), r_after(count);
    contact_gaps(model_, q, qd, t, g, r_before);
    auto rate = [&](int k, const double* v) {
      for (int i = 0; i < size_; ++i) w[i] = v[i];
      contact_gaps(model_, q, w, t, g, r_after);
      return r_after[contacts[static_cast<std::size_t>(k)]];
    };
    auto plastic = [&](int k, double* v) {
      for (int i = 0; i < size_; ++i) w[i] = v[i];
      restitution_impact(model_, ws_, q, w, t, contacts[static_cast<std::size_t>(k)], 0.0, false);
      for (int i = 0; i < size_; ++i) v[i] = w[i];
    };
    if (!close_together(size_, limit.data(), static_cast<int>(contacts.size()), qd.template lpNorm<Eigen::Infinity>(),
                        function_ref<double(int, const double*)>(rate), function_ref<void(int, double*)>(plastic)))
      return false;
    contact_gaps(model_, q, limit, t, g, r_after);
    // The impulse each contact gave: Gᵀ Λ = M (q̇∞ − q̇), G the round's rows.
    evaluate(model_, ws_, q, qd, t);
    const Vec<double, n> dp = ws_.mass * (limit - qd);
    const auto cs = constraint_state(model_, q, qd, t);
    const int k_count = static_cast<int>(contacts.size());
    std::vector<double> Gt(static_cast<std::size_t>(size_ * k_count)), impulses(contacts.size());
    for (int k = 0; k < k_count; ++k)
      for (int i = 0; i < size_; ++i)
        Gt[static_cast<std::size_t>(k * size_ + i)] =
            cs.jacobian(holonomic_count(model_) + contacts[static_cast<std::size_t>(k)], i);
    MinNormSolver solver(size_, k_count);
    solver.factorize(Gt.data());
    solver.solve(dp.data(), impulses.data());
    const double T_before = kinetic_for_log(model_, ws_, q, qd, t);
    const double h_before = energy_function(model_, q, qd, t);
    qd = limit;
    if constexpr (!has_kinetic_potential_v<M>) evaluate(model_, ws_, q, qd, t);
    const double T_after = kinetic_for_log(model_, ws_, q, qd, t);
    for (std::size_t k = 0; k < contacts.size(); ++k) {
      EventRecord rec;
      rec.t = t;
      rec.kind = EventKind::impact;
      rec.name = contact_name(contacts[k]);
      rec.impulse = impulses[k];
      rec.approach_speed = -r_before[contacts[k]];
      rec.separation_speed = r_after[contacts[k]];
      rec.kinetic_energy_before = T_before;
      rec.kinetic_energy_after = T_after;
      report_.events.push_back(rec);
      ++report_.impacts;
    }
    report_.impact_energy_loss += T_before - T_after;
    shift_reference_energy(q, qd, t, h_before, T_after - T_before);
    return true;
  } else {
    (void)q, (void)qd, (void)t, (void)round;
    return false;
  }
}

/// d²φ_j/dt² = G_j q̈ + γ_j with q̈ from the current active set (contact j
/// itself inactive): negative when the forces press the contact shut.
template <class M>
double ModelSystem<M>::gap_acceleration(const Vec<double, n>& q, const Vec<double, n>& qd, double t, int j) {
  if constexpr (unilateral_count_v<M> != 0) {
    Vec<double, n> qdd(size_);
    constrained_accelerations(model_, ws_, cw_, q, qd, t, qdd, 0.0, ctx_->active & ~(ActiveSet{1} << j));
    const auto cs = constraint_state(model_, q, qd, t);
    const int row = holonomic_count(model_) + j;
    return cs.jacobian.row(row).dot(qdd) + cs.gamma[row];
  } else {
    (void)q, (void)qd, (void)t, (void)j;
    return 0.0;
  }
}

}  // namespace lagrangian::detail
