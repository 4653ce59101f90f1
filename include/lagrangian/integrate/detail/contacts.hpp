#pragma once
// Impacts at contacts, resolved once for every system (compiled once:
// src/integrate/contacts.cpp). An adapter — a Model's (run_events.hpp) or a
// particle scene's (src/scene/particle_system.cpp) — numbers its contacts
// 0, 1, … and answers for each through ContactSystem; the order of the
// impacts, the Zeno rule, cycles replaced by their limit, which contacts
// rest and which lift off, and the event log are decided here.

#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "lagrangian/integrate/detail/contact_rules.hpp"
#include "lagrangian/integrate/detail/impact_cycle.hpp"
#include "lagrangian/integrate/report.hpp"

namespace lagrangian::detail {

/// What Newton's law of restitution did at one contact.
struct LawResult {
  double impulse = 0;         ///< Λ along +∇φ (N·s for a distance gap)
  double approach = 0;        ///< −φ̇ before (m/s for a distance gap)
  double separation = 0;      ///< φ̇ after
  double kinetic_before = 0;  ///< T before (J)
  double kinetic_after = 0;   ///< T after (J)
};

/// A system's contacts as the contact rules see them. x = [q; q̇] is the
/// state (2n values); a contact j has a gap φ_j(q, t) ≥ 0 and its rate φ̇_j.
class ContactSystem {
 public:
  virtual ~ContactSystem() = default;
  /// n, the number of coordinates.
  virtual int coordinates() const = 0;
  /// The contact's name in the event log.
  virtual std::string contact_name(int j) const = 0;
  /// φ and φ̇ of the contacts `which` at (x, t), into out[0 …].
  virtual void gap_rates(const double* x, double t, const std::vector<int>& which, GapRate* out) = 0;
  /// The contacts that may take part in an impact at x, in the order to
  /// prefer among equally fast ones: at least every open one within `touch`
  /// of closing, and `trigger` (when ≥ 0).
  virtual void near(const double* x, double t, double touch, int trigger, std::vector<int>& out) = 0;
  /// The contact's impacts so far, for the Zeno rule.
  virtual ContactHistory& history(int j) = 0;
  /// Its coefficient of restitution e; NaN when the system declares none.
  virtual double restitution(int j) const = 0;
  /// Whether the forces press contact j shut at (x, t): d²φ_j/dt² < 0 with
  /// the contact itself free.
  virtual bool pressed(int j, const double* x, double t) = 0;
  /// Newton's law at contact j with coefficient e on the velocities of x,
  /// the constraint rows kept (the resting contacts are not rows here),
  /// whatever the sign of φ̇ (so the law is linear in q̇). `record`: a real
  /// impact, whose change of energy the adapter's monitors account for; else
  /// a trial inside a cycle's limit.
  virtual LawResult apply_law(int j, double e, double* x, double t, bool record) = 0;
  /// The velocities of x jump to v (n values), the limit of impacts that
  /// cycle; the adapter's monitors account for the change of energy.
  /// Returns T before and after (J).
  virtual std::pair<double, double> jump_velocities(double* x, const double* v, double t) = 0;
  /// The impulse (N·s) each contact of `which` gave in the jump from the
  /// velocities of x to v (n values): least squares over their normals.
  virtual void impulse_shares(const double* x, const double* v, double t, const std::vector<int>& which,
                              double* out) = 0;
  /// T at x (J), for the log of events without an impulse.
  virtual double kinetic(const double* x, double t) = 0;
  /// Resting contacts are held shut as constraint rows.
  virtual bool resting(int j) const = 0;
  virtual void resting_contacts(std::vector<int>& out) const = 0;
  /// Contact j becomes a resting one.
  virtual void rest(int j) = 0;
  /// Resting contact j lifts off.
  virtual void release(int j) = 0;

  // Location inside a step (ContactEvents).

  /// The open contacts that may close in the step from (t0, x0) to
  /// (t1, x1): at least every one whose gap could reach zero in it. Asked
  /// once per step, before the other questions about the step.
  virtual void step_candidates(double t0, const double* x0, double t1, const double* x1,
                               std::vector<int>& out) = 0;
  /// The multipliers λ (N, or N·m for an angular gap) of the resting
  /// contacts `which` at (x, t), into out[0 …]: > 0 pushes the bodies apart.
  virtual void resting_multipliers(const double* x, double t, const std::vector<int>& which, double* out) = 0;
  /// φ, φ̇ of contact j at time ts inside the step, on a path that
  /// reproduces the step's interpolant `interp` to rounding (it sorts out
  /// contacts that cannot close; those that may are located on `interp`).
  virtual GapRate gap_on_path(int j, double ts, const Interpolator& interp) = 0;
};

/// The lists one resolution of impacts works with, kept from one to the
/// next so that resolving allocates nothing once they have grown.
struct ResolutionBuffers {
  std::vector<int> near, involved, resting_before, resting_now, woken, rested, plastic, seen;
  std::vector<GapRate> rates;
  ImpactCycle cycle;  // the impacts since the last cycle replaced by its limit
};

/// Resolves every contact that is touching (|φ| ≤ the touch tolerance, or
/// `trigger`, the one located closing) and approaching faster than
/// contact_touch_speed at (x, t), one at a time, the one approaching
/// fastest first, by Newton's law of restitution, until none approaches
/// (the sequential rule for simultaneous impacts; each impact conserves
/// momentum, and kinetic energy when e = 1). The Zeno rule
/// (zeno_accumulation) decides which impact ends an accumulation: it is
/// plastic and the contact rests. Impacts that cycle are replaced by their
/// limit (integrate/detail/impact_cycle.hpp). A resting contact that an impact sets
/// approaching takes part as an open one. Afterwards a contact that took
/// part (`trigger`, or with trigger < 0 every one near) and does not
/// separate rests when its last impact was plastic (e = 0: the bodies
/// stick) or the forces press it shut, and resting contacts that separate
/// lift off. Impacts go into the report's log; rests and lift-offs too when
/// `log_changes`. SimulationError when the impacts do not settle after
/// 1000 per contact, when the system declares no restitution, or when an
/// impact gives non-finite values.
void resolve_contacts(ContactSystem& system, double* x, double t, int trigger, bool log_changes,
                      const SimulationOptions& options, RunReport& report, ResolutionBuffers& buffers);

/// The first contact event inside a step.
struct ContactEvent {
  enum class Kind {
    none,
    lift_off,  ///< a resting contact whose multiplier turns negative
    closing,   ///< an open contact closing (or touching and approaching at the step's start)
  };
  Kind kind = Kind::none;
  int contact = -1;
  double t = std::numeric_limits<double>::infinity();  ///< its time (s)
};

/// Where contacts close or lift off inside a step, and what that does: the
/// location for every system with contacts. One per run: it keeps the
/// buffers it reuses step after step and the guard against events that
/// make no progress.
class ContactEvents {
 public:
  /// The first contact event in the step from (t0, x0) to (t1, x1), both
  /// ends exact and `interp` between them: a resting contact lifting off
  /// (its multiplier turning negative, locate_lift_off) or an open one
  /// closing (locate_closing; a dip of the gap that stays above the touch
  /// tolerance is sorted out on the system's path, and crossings are
  /// located in the order of their chord estimate, each skipped when it is
  /// still open at the earliest time found so far). A lift-off wins a tie.
  /// SimulationError when a contact is found penetrated at t0.
  ContactEvent first(ContactSystem& system, double t0, const double* x0, double t1, const double* x1,
                     const Interpolator& interp, double touch_speed);
  /// The step's end (t, x, 2n values) moves back to an event at t_event
  /// found in the step that began at t_step_start (on `interp`), after the
  /// check that events make progress (EventProgress).
  void move_to(double t_event, double t_step_start, const Interpolator& interp, double& t, double* x, int n);
  /// Applies a contact event at (x, t): a lift-off goes into the log, a
  /// closing is resolved (resolve_contacts, the event's contact the trigger).
  void apply(ContactSystem& system, const ContactEvent& event, double* x, double t, const SimulationOptions& options,
             RunReport& report);
  /// resolve_contacts() with this run's buffers.
  void resolve(ContactSystem& system, double* x, double t, int trigger, bool log_changes,
               const SimulationOptions& options, RunReport& report) {
    resolve_contacts(system, x, t, trigger, log_changes, options, report, resolution_);
  }
  /// Contacts located on a step's interpolant so far (root searches).
  std::uint64_t locations() const { return locations_; }

 private:
  struct Candidate {
    double key;  // the chord estimate of a crossing; the step's start for the others
    std::size_t place;  // among the system's candidates
    bool crossing;
    int contact;
    GapRate a, b;  // at the step's ends
  };
  std::vector<double> buf_, lambda_;
  std::vector<int> candidates_, resting_, one_ = std::vector<int>(1);
  std::vector<GapRate> a_, b_;
  std::vector<Candidate> order_;
  EventProgress progress_;
  std::uint64_t locations_ = 0;
  ResolutionBuffers resolution_;
};

}  // namespace lagrangian::detail
