#include "lagrangian/integrate/detail/contact_rules.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/impact.hpp"

namespace lagrangian::detail {

namespace {

std::pair<double, double> root(TimeFunction f, double a, double b, double fa, double fb) {
  return bracket_root(f, a, b, fa, fb, event_time_tolerance);
}

}  // namespace

double contact_touch_tolerance(const double* q, int n) {
  double qmax = 0;
  for (int i = 0; i < n; ++i) qmax = std::max(qmax, std::abs(q[i]));
  return 1e-9 * (1.0 + qmax);
}

Closing locate_closing(double t0, double t1, GapRate start, GapRate end, double touch, double touch_speed,
                       GapFunction on_step) {
  if (start.gap < -touch) return {Closing::Kind::penetrated, t0};
  auto at = [&](double t) {
    if (t == t0) return start;
    if (t == t1) return end;
    return on_step(t);
  };
  auto gap = [&](double t) { return at(t).gap; };
  auto rate_root = [&] { return stationary_time(t0, t1, start, end, on_step); };
  // The bracket [lo, hi] of a closing: φ(lo) > 0 > φ(hi).
  double lo = t0, hi = t1;
  bool crossing = start.gap > 0 && end.gap < 0;
  if (!crossing && start.gap >= 0 && end.gap >= 0 && start.rate < 0 && end.rate > 0) {
    hi = rate_root();  // a dip inside the step: below zero at the gap's minimum?
    crossing = gap(hi) < 0;
  } else if (!crossing && start.gap <= 0 && start.rate > 0 && end.gap < 0 && end.rate < 0) {
    lo = rate_root();  // leaves the contact and comes back within the step
    crossing = gap(lo) > 0;
  }
  if (crossing) {
    double tc = root(time_function(gap), lo, hi, gap(lo), gap(hi)).first;
    GapRate c = at(tc);
    if (lo == t0 && start.gap <= touch && start.rate > 0 && !(c.rate < 0) && end.rate < 0) {
      // The root found is the touch the contact left (φ(t0) a rounding
      // above zero, as after an impact), not its return: the closing is
      // after the gap's maximum.
      lo = rate_root();
      if (!(gap(lo) > 0)) return {};
      tc = root(time_function(gap), lo, hi, gap(lo), gap(hi)).first;
      c = at(tc);
    }
    if (-c.rate <= touch_speed && end.gap >= -touch) return {};  // a slow touch
    return {Closing::Kind::inside, tc};
  }
  if ((start.gap <= touch && start.rate < -touch_speed) || (start.gap < 0 && end.gap < -touch && end.gap < start.gap))
    return {Closing::Kind::at_start, t0};
  return {};
}

double stationary_time(double t0, double t1, GapRate start, GapRate end, GapFunction on_step) {
  auto rate = [&](double t) {
    if (t == t0) return start.rate;
    if (t == t1) return end.rate;
    return on_step(t).rate;
  };
  const auto r = root(time_function(rate), t0, t1, start.rate, end.rate);
  return 0.5 * (r.first + r.second);
}

void throw_penetrated(const std::string& name, double t, double gap) {
  std::ostringstream os;
  os.precision(17);
  os << "contact " << name << " is penetrated at t = " << t << " (gap " << gap
     << ") without a located closing; the run was stopped";
  throw SimulationError(os.str(), t);
}

double locate_crossing(double t0, double t1, double f0, double f1, TimeFunction f) {
  return root(f, t0, t1, f0, f1).second;
}

double locate_lift_off(double t0, double t1, double lambda0, double lambda1, TimeFunction lambda) {
  if (!(lambda0 > 0)) return t0;
  return locate_crossing(t0, t1, lambda0, lambda1, lambda);  // λ < 0 from there on
}

void ContactHistory::record(double approach, double t) {
  approach_max = std::max(approach_max, approach);
  last_impact = t;
}

bool zeno_accumulation(const ContactHistory& history, double approach, double t, const SimulationOptions& options,
                       Predicate pressed) {
  const bool accumulating = approach <= options.zeno_speed_ratio * history.approach_max ||
                            t - history.last_impact <= options.zeno_min_interval * std::max(1.0, std::abs(t));
  return accumulating && pressed();
}

double zeno_cutoff(const ContactHistory& history, double t, double e) {
  if (!std::isfinite(history.last_impact) || !(e < 1)) return std::numeric_limits<double>::quiet_NaN();
  return (t - history.last_impact) * e / (1 - e);
}

void EventProgress::check(double t_event, double t_step_start) {
  if (t_event == last_ && t_event == t_step_start) {
    if (++repeats_ > 100) {
      std::ostringstream os;
      os.precision(17);
      os << "event handling made no progress at t = " << t_event << " (more than 100 events at this instant)";
      throw SimulationError(os.str(), t_event);
    }
  } else {
    repeats_ = 0;
  }
  last_ = t_event;
}

}  // namespace lagrangian::detail
