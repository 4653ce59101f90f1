#pragma once
// The rules every system with contacts follows, compiled once
// (src/integrate/contact_rules.cpp): when a contact is touching, where an
// open contact closes inside a step, where a resting contact lifts off, the
// Zeno rule, and the guard against events that make no progress. The
// adapter from a Model (integrate/detail/model_system.hpp) and the particle scenes'
// adapter (src/scene/particle_system.cpp) both decide with these functions.

#include <limits>
#include <string>

#include "lagrangian/integrate/detail/roots.hpp"
#include "lagrangian/integrate/report.hpp"

namespace lagrangian::detail {

/// |φ| at most this counts as touching: 1e-9 (1 + max_i |q_i|), in the
/// units of the gaps (m for Cartesian coordinates). q has n values.
double contact_touch_tolerance(const double* q, int n);

/// A contact's gap φ and its rate φ̇ at one time.
struct GapRate {
  double gap = 0, rate = 0;
};

/// φ, φ̇ of one contact at a time inside the step.
using GapFunction = FunctionRef<GapRate(double)>;

template <class F>
GapFunction gap_function(const F& f) {
  return function_ref<GapRate(double)>(f);
}

/// What locate_closing found for one open contact.
struct Closing {
  enum class Kind {
    none,        ///< stays open (or a slow touch within the touch tolerance)
    at_start,    ///< touching at the step's start and approaching, or pressing in
    inside,      ///< closes at `t` inside the step
    penetrated,  ///< φ(t0) < −touch: a closing was missed before this step
  };
  Kind kind = Kind::none;
  double t = 0;  ///< the closing time (s): the last time with φ ≥ 0
};

/// Whether and where an open contact closes in the step [t0, t1], from φ and
/// φ̇ at both ends (`start`, `end`) and on the step (`on_step`): a crossing
/// (φ(t0) > 0 > φ(t1)), a dip below zero and back inside the step, or
/// leaving a touch and coming back, located to event_time_tolerance. A slow
/// touch (approach speed ≤ touch_speed, φ(t1) ≥ −touch) is not an impact.
Closing locate_closing(double t0, double t1, GapRate start, GapRate end, double touch, double touch_speed,
                       GapFunction on_step);

/// Where φ̇ changes sign inside [t0, t1] (start.rate and end.rate of
/// opposite signs): the middle of the located bracket — the gap's minimum
/// or maximum inside the step.
double stationary_time(double t0, double t1, GapRate start, GapRate end, GapFunction on_step);

/// Stops the run: contact `name` was found penetrated (gap < −touch) at the
/// start t of a step, so an earlier closing was missed.
[[noreturn]] void throw_penetrated(const std::string& name, double t, double gap);

/// Where a watched function crosses zero in [t0, t1] given its values f0,
/// f1 of opposite signs at the ends: the upper end of the located bracket,
/// the first time from which f has the sign of f1.
double locate_crossing(double t0, double t1, double f0, double f1, TimeFunction f);

/// Where a resting contact lifts off in [t0, t1]: the first time from which
/// its multiplier λ (N, or N·m for an angular gap) is negative, given λ at
/// both ends (lambda1 < 0) and on the step.
double locate_lift_off(double t0, double t1, double lambda0, double lambda1, TimeFunction lambda);

/// A contact's impacts so far, for the Zeno rule.
struct ContactHistory {
  double approach_max = 0;  ///< fastest approach speed so far (units of φ̇)
  double last_impact = -std::numeric_limits<double>::infinity();  ///< time of the last impact (s)
  void record(double approach, double t);
};

/// A yes/no question asked only when needed.
using Predicate = FunctionRef<bool()>;

template <class F>
Predicate predicate(const F& f) {
  return function_ref<bool()>(f);
}

/// The Zeno rule, the one for every system. An impact at time t with
/// approach speed `approach` ends an accumulation of impacts — it is
/// resolved plastically (e = 0) and the contact rests — when
///   approach ≤ zeno_speed_ratio · (the fastest approach of the contact so
///   far), or t − (its last impact) ≤ zeno_min_interval · max(1 s, |t|),
/// and the forces press the contact shut (`pressed`: d²φ/dt² < 0 in the
/// motion without it; asked only when the first test holds). Free bodies
/// that graze never rest.
bool zeno_accumulation(const ContactHistory& history, double approach, double t, const SimulationOptions& options,
                       Predicate pressed);

/// The Zeno rule's cut-off at an impact that it ends: an estimate of the
/// time the bounces left would have taken, had each flight shrunk by the
/// contact's restitution e as under a constant pressing force (a ball on a
/// floor): (t − its last impact) e / (1 − e) (s). The rest's time is known
/// to about that much. NaN when there was no earlier impact or e = 1.
double zeno_cutoff(const ContactHistory& history, double t, double e);

/// Stops a run whose events make no progress: more than 100 events at the
/// same instant, each found at the start of the step.
class EventProgress {
 public:
  /// Called with the time of each event handled and the step's start.
  void check(double t_event, double t_step_start);

 private:
  double last_ = std::numeric_limits<double>::quiet_NaN();
  int repeats_ = 0;
};

}  // namespace lagrangian::detail
