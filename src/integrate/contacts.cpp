#include "lagrangian/integrate/detail/contacts.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "lagrangian/integrate/detail/impact_cycle.hpp"
#include "lagrangian/errors.hpp"

namespace lagrangian::detail {

namespace {

bool contains(const std::vector<int>& v, int j) { return std::find(v.begin(), v.end(), j) != v.end(); }

void add_once(std::vector<int>& v, int j) {
  if (!contains(v, j)) v.push_back(j);
}

/// A rest or lift-off of contact j at (x, t) into the log: no impulse, T at x.
void log_change(ContactSystem& s, EventKind kind, int j, const double* x, double t, RunReport& report) {
  EventRecord rec;
  rec.t = t;
  rec.kind = kind;
  rec.name = s.contact_name(j);
  rec.kinetic_energy_before = rec.kinetic_energy_after = s.kinetic(x, t);
  report.events.push_back(std::move(rec));
}

/// One resolution at (x, t): the state it works on and what it has seen.
class Resolution {
 public:
  Resolution(ContactSystem& system, double* x, double t, int trigger, const SimulationOptions& options,
             RunReport& report, ResolutionBuffers& buffers)
      : s_(system), x_(x), t_(t), trigger_(trigger), n_(system.coordinates()), opt_(options), rep_(report),
        near_(buffers.near), involved_(buffers.involved), resting_before_(buffers.resting_before),
        resting_now_(buffers.resting_now), woken_(buffers.woken), rested_(buffers.rested), plastic_(buffers.plastic),
        seen_(buffers.seen), rates_(buffers.rates), cycle_(buffers.cycle) {
    for (std::vector<int>* v : {&involved_, &woken_, &rested_, &plastic_}) v->clear();
    touch_ = contact_touch_tolerance(x, n_);
    s_.resting_contacts(resting_before_);
    s_.near(x, t, touch_, trigger, near_);
    if (trigger >= 0) {
      add_once(near_, trigger);
      involved_.push_back(trigger);
    } else {
      involved_ = near_;
    }
  }

  void impacts() {
    wake();
    cycle_.restart();
    for (int count = 0;; ++count) {
      double approach = opt_.contact_touch_speed;
      const int k = fastest(approach);
      if (k < 0) break;
      const int j = near_[static_cast<std::size_t>(k)];
      const int max_impacts = 1000 * static_cast<int>(near_.size() + 1);
      if (count >= max_impacts) {
        std::ostringstream os;
        os.precision(17);
        os << "simultaneous impacts at t = " << t_ << " did not settle after " << max_impacts
           << " pairwise impacts (contact " << s_.contact_name(j) << " still approaching at " << approach << ")";
        throw SimulationError(os.str(), t_);
      }
      const double e = impact(j, approach);
      wake();
      cycle_.record(k, e);
      const std::vector<ImpactCycle::Impact> round = cycle_.due_round(static_cast<int>(near_.size()));
      if (!round.empty() && settle_cycle(round)) {
        for (const ImpactCycle::Impact& imp : round) involved_.push_back(near_[static_cast<std::size_t>(imp.contact)]);
        cycle_.settled();
        wake();
      }
    }
  }

  /// Contacts that took part and do not separate rest when their last
  /// impact was plastic or the forces press them shut; resting contacts
  /// that separate lift off.
  void rests_and_releases(bool log_changes) {
    // (Resting and releasing move nothing: the gaps and rates are those of x throughout.)
    std::vector<int>& seen = seen_;
    seen.clear();
    for (int j : involved_) add_once(seen, j);
    rates_.resize(seen.size());
    s_.gap_rates(x_, t_, seen, rates_.data());
    for (std::size_t k = 0; k < seen.size(); ++k) {
      const int j = seen[k];
      const GapRate& g = rates_[k];
      if (!s_.resting(j) && (j == trigger_ || g.gap <= touch_) && g.rate <= opt_.contact_touch_speed &&
          (contains(plastic_, j) || s_.pressed(j, x_, t_)))
        s_.rest(j);
    }
    std::vector<int>& resting = resting_now_;
    s_.resting_contacts(resting);
    rates_.resize(resting.size());
    s_.gap_rates(x_, t_, resting, rates_.data());
    for (std::size_t k = resting.size(); k-- > 0;)
      if (rates_[k].rate > opt_.contact_touch_speed) s_.release(resting[k]);
    if (!log_changes) return;
    for (int j : seen)
      if (s_.resting(j) && !contains(resting_before_, j) && !contains(rested_, j)) log_change(s_, EventKind::rest, j, x_, t_, rep_);
    for (int j : resting_before_)
      if (!s_.resting(j)) log_change(s_, EventKind::release, j, x_, t_, rep_);
  }

 private:
  /// The index in near_ of the open contact approaching fastest, faster
  /// than `approach` (updated to its speed); −1 when none.
  int fastest(double& approach) {
    rates_.resize(near_.size());
    s_.gap_rates(x_, t_, near_, rates_.data());
    int best = -1;
    for (std::size_t k = 0; k < near_.size(); ++k) {
      const int j = near_[k];
      if (s_.resting(j)) continue;
      const GapRate& g = rates_[k];
      if (!(j == trigger_ || g.gap <= touch_ || contains(woken_, j))) continue;
      if (-g.rate > approach) {
        approach = -g.rate;
        best = static_cast<int>(k);
      }
    }
    return best;
  }

  /// One impact at contact j approaching at `approach`; returns the e used.
  double impact(int j, double approach) {
    const double e_declared = s_.restitution(j);
    if (std::isnan(e_declared)) {
      std::ostringstream os;
      os.precision(17);
      os << "contact " << s_.contact_name(j) << " closed at t = " << t_ << " with approach speed " << approach
         << "; the model declares no restitution(), so the impact cannot be resolved";
      throw SimulationError(os.str(), t_);
    }
    ContactHistory& history = s_.history(j);
    const auto pressed = [&] { return s_.pressed(j, x_, t_); };
    const bool zeno = zeno_accumulation(history, approach, t_, opt_, predicate(pressed));
    const double e = zeno ? 0.0 : e_declared;
    const LawResult r = s_.apply_law(j, e, x_, t_, true);
    const double cutoff = zeno ? zeno_cutoff(history, t_, e_declared) : std::nan("");
    history.record(approach, t_);
    log(zeno ? EventKind::rest : EventKind::impact, j, r);
    rep_.events.back().zeno_cutoff = cutoff;
    rep_.impact_energy_loss += r.kinetic_before - r.kinetic_after;
    involved_.push_back(j);
    plastic_.erase(std::remove(plastic_.begin(), plastic_.end(), j), plastic_.end());
    rested_.erase(std::remove(rested_.begin(), rested_.end(), j), rested_.end());
    if (e == 0.0) plastic_.push_back(j);
    if (zeno) {
      rested_.push_back(j);
      s_.rest(j);
    }
    return e;
  }

  /// Resting contacts that an impulse has set approaching leave the
  /// constraint rows and take part as open contacts.
  void wake() {
    s_.resting_contacts(resting_now_);
    if (resting_now_.empty()) return;
    rates_.resize(resting_now_.size());
    s_.gap_rates(x_, t_, resting_now_, rates_.data());
    for (std::size_t k = resting_now_.size(); k-- > 0;) {
      if (!(rates_[k].rate < -opt_.contact_touch_speed)) continue;
      const int j = resting_now_[k];
      s_.release(j);
      add_once(woken_, j);
      add_once(near_, j);
    }
  }

  /// The limit of impacts that cycle among the contacts near_[k] of `round`
  /// (integrate/detail/impact_cycle.hpp): the velocities jump to it when the rounds
  /// converge, the contacts left approaching by rounding are closed
  /// together (close_together), and each contact of the round gets one
  /// impact in the log with its share of the total impulse and the kinetic
  /// energies before and after the whole accumulation. Returns false (x
  /// unchanged) when the rounds do not settle.
  bool settle_cycle(const std::vector<ImpactCycle::Impact>& round) {
    const auto n = static_cast<std::size_t>(n_);
    std::vector<double> trial(x_, x_ + 2 * n), limit(n);
    auto set_velocities = [&](const double* v) { std::copy(v, v + n, trial.begin() + n_); };
    auto apply_round = [&](const double* in, double* out) {
      set_velocities(in);
      for (const ImpactCycle::Impact& imp : round)
        s_.apply_law(near_[static_cast<std::size_t>(imp.contact)], imp.e, trial.data(), t_, false);
      std::copy(trial.begin() + n_, trial.end(), out);
    };
    if (!round_limit(n_, x_ + n_, round_map(apply_round), limit.data())) return false;
    std::vector<int> contacts;
    for (const ImpactCycle::Impact& imp : round) add_once(contacts, near_[static_cast<std::size_t>(imp.contact)]);
    double speed = 0;
    for (int i = 0; i < n_; ++i) speed = std::max(speed, std::abs(x_[n_ + i]));
    // Contacts of the round left approaching by rounding: closed together.
    GapRate g;
    std::vector<int> which(1);
    auto rate = [&](int k, const double* v) {
      set_velocities(v);
      which[0] = contacts[static_cast<std::size_t>(k)];
      s_.gap_rates(trial.data(), t_, which, &g);
      return g.rate;
    };
    auto plastic = [&](int k, double* v) {
      set_velocities(v);
      s_.apply_law(contacts[static_cast<std::size_t>(k)], 0.0, trial.data(), t_, false);
      std::copy(trial.begin() + n_, trial.end(), v);
    };
    if (!close_together(n_, limit.data(), static_cast<int>(contacts.size()), speed,
                        function_ref<double(int, const double*)>(rate), function_ref<void(int, double*)>(plastic)))
      return false;
    std::vector<double> shares(contacts.size());
    s_.impulse_shares(x_, limit.data(), t_, contacts, shares.data());
    std::vector<GapRate> before(contacts.size()), after(contacts.size());
    s_.gap_rates(x_, t_, contacts, before.data());
    const auto [T_before, T_after] = s_.jump_velocities(x_, limit.data(), t_);
    s_.gap_rates(x_, t_, contacts, after.data());
    for (std::size_t k = 0; k < contacts.size(); ++k)
      log(EventKind::impact, contacts[k], {shares[k], -before[k].rate, after[k].rate, T_before, T_after});
    rep_.impact_energy_loss += T_before - T_after;
    return true;
  }

  /// An impact (or a rest that the Zeno rule began) into the log.
  void log(EventKind kind, int j, const LawResult& r) {
    if (!std::isfinite(r.impulse) || !std::isfinite(r.kinetic_before) || !std::isfinite(r.kinetic_after)) {
      std::ostringstream os;
      os.precision(17);
      os << "impact " << s_.contact_name(j) << " at t = " << t_ << " gave a non-finite impulse or energy (J = "
         << r.impulse << " N s, kinetic energy " << r.kinetic_before << " -> " << r.kinetic_after
         << " J): its values overflow double precision, so the run was stopped";
      throw SimulationError(os.str(), t_);
    }
    EventRecord rec;
    rec.t = t_;
    rec.kind = kind;
    rec.name = s_.contact_name(j);
    rec.impulse = r.impulse;
    rec.approach_speed = r.approach;
    rec.separation_speed = r.separation;
    rec.kinetic_energy_before = r.kinetic_before;
    rec.kinetic_energy_after = r.kinetic_after;
    rep_.events.push_back(std::move(rec));
    if (kind == EventKind::impact) ++rep_.impacts;
  }

  ContactSystem& s_;
  double* x_;
  double t_;
  int trigger_;
  int n_;
  const SimulationOptions& opt_;
  RunReport& rep_;
  double touch_ = 0;
  std::vector<int>&near_, &involved_, &resting_before_, &resting_now_, &woken_;
  std::vector<int>& rested_;   // their last impact here began a rest by the Zeno rule (logged as such)
  std::vector<int>& plastic_;  // their last impact here had e = 0: the bodies stick
  std::vector<int>& seen_;
  std::vector<GapRate>& rates_;
  ImpactCycle& cycle_;  // the impacts since the last cycle replaced by its limit
};

}  // namespace

void resolve_contacts(ContactSystem& system, double* x, double t, int trigger, bool log_changes,
                      const SimulationOptions& options, RunReport& report, ResolutionBuffers& buffers) {
  Resolution r(system, x, t, trigger, options, report, buffers);
  r.impacts();
  r.rests_and_releases(log_changes);
}

}  // namespace lagrangian::detail

namespace lagrangian::detail {

ContactEvent ContactEvents::first(ContactSystem& s, double t0, const double* x0, double t1, const double* x1,
                                  const Interpolator& interp, double touch_speed) {
  const int n = s.coordinates();
  buf_.resize(static_cast<std::size_t>(2 * n));
  s.step_candidates(t0, x0, t1, x1, candidates_);
  ContactEvent best;
  // Lift-off: a resting contact whose multiplier pulls at the step's end.
  s.resting_contacts(resting_);
  if (!resting_.empty()) {
    lambda_.resize(resting_.size());
    s.resting_multipliers(x1, t1, resting_, lambda_.data());
    for (std::size_t k = 0; k < resting_.size(); ++k) {
      if (!(lambda_[k] < 0)) continue;
      const int j = resting_[k];
      auto lambda = [&](double ts) {
        if (ts == t1) return lambda_[k];
        interp(ts, buf_.data());
        one_[0] = j;
        double l = 0;
        s.resting_multipliers(buf_.data(), ts, one_, &l);
        return l;
      };
      const double tl = locate_lift_off(t0, t1, lambda(t0), lambda_[k], time_function(lambda));
      if (tl < best.t) best = {ContactEvent::Kind::lift_off, j, tl};
    }
  }
  // Closing: only the earliest event of the step matters, so the contacts
  // that cross zero (open at the step's start, closed at its end) are
  // located in the order of their chord estimate, and one still open on
  // the path at the earliest time found so far closes after it and is not
  // located. (A step of free flight can hold thousands of crossings: a gas
  // against its walls.)
  const double touch = contact_touch_tolerance(x1, n);
  a_.resize(candidates_.size());
  b_.resize(candidates_.size());
  s.gap_rates(x0, t0, candidates_, a_.data());
  s.gap_rates(x1, t1, candidates_, b_.data());
  order_.clear();
  for (std::size_t k = 0; k < candidates_.size(); ++k) {
    const int j = candidates_[k];
    const GapRate a = a_[k], b = b_[k];
    if (a.gap > touch && b.gap > touch) {
      if (!(a.rate < 0 && b.rate > 0)) continue;  // open throughout: no crossing
      // A dip of the gap: it passes by when its minimum, where φ̇ = 0, stays above the touch tolerance.
      auto on_path = [&](double ts) { return s.gap_on_path(j, ts, interp); };
      if (on_path(stationary_time(t0, t1, a, b, gap_function(on_path))).gap > touch) continue;
    }
    const bool crossing = a.gap > touch && b.gap < 0;
    order_.push_back({crossing ? t0 + (t1 - t0) * (a.gap / (a.gap - b.gap)) : t0, k, crossing, j, a, b});
  }
  // Earliest first; equal keys in the order the system gave them (stable
  // without std::stable_sort's scratch buffer).
  std::sort(order_.begin(), order_.end(), [](const Candidate& p, const Candidate& q) {
    return p.key < q.key || (p.key == q.key && p.place < q.place);
  });
  for (const Candidate& c : order_) {
    if (c.crossing && best.t < t1 && s.gap_on_path(c.contact, best.t, interp).gap > touch) continue;
    auto on_step = [&](double ts) {
      interp(ts, buf_.data());
      one_[0] = c.contact;
      GapRate g;
      s.gap_rates(buf_.data(), ts, one_, &g);
      return g;
    };
    ++locations_;
    const Closing found = locate_closing(t0, t1, c.a, c.b, touch, touch_speed, gap_function(on_step));
    if (found.kind == Closing::Kind::penetrated) throw_penetrated(s.contact_name(c.contact), t0, c.a.gap);
    if (found.kind != Closing::Kind::none && found.t < best.t) best = {ContactEvent::Kind::closing, c.contact, found.t};
  }
  return best;
}

void ContactEvents::move_to(double t_event, double t_step_start, const Interpolator& interp, double& t, double* x,
                            int n) {
  progress_.check(t_event, t_step_start);  // an event that changes nothing, found again and again
  if (t_event < t) {
    buf_.resize(static_cast<std::size_t>(2 * n));
    interp(t_event, buf_.data());
    std::copy(buf_.begin(), buf_.end(), x);
    t = t_event;
  }
}

void ContactEvents::apply(ContactSystem& s, const ContactEvent& event, double* x, double t,
                          const SimulationOptions& options, RunReport& report) {
  if (event.kind == ContactEvent::Kind::closing) {
    resolve(s, x, t, event.contact, true, options, report);
  } else if (event.kind == ContactEvent::Kind::lift_off) {
    s.release(event.contact);
    log_change(s, EventKind::release, event.contact, x, t, report);
  }
}

}  // namespace lagrangian::detail
