#pragma once
// Simultaneous impacts that cycle: the limit of the sequential rule, by
// extrapolation instead of one pairwise impact at a time (compiled once:
// src/integrate/impact_cycle.cpp). Both adapters with contacts use it.

#include <vector>

#include "lagrangian/integrate/detail/roots.hpp"

namespace lagrangian::detail {

/// The contacts resolved, in order, while one simultaneous impact is
/// resolved by the sequential rule, watched for a cycle: the same contacts
/// with the same e, in the same order, again and again. That happens when a
/// light body is pinned between heavy ones (a sphere of mass m between a
/// wall and a sphere of mass M): each round of pairwise impacts changes the
/// velocities by the same linear map, whose part along the approach decays
/// by about 1 − 2 m/M a round, so the rule needs ~ M/m impacts to settle.
class ImpactCycle {
 public:
  struct Impact {
    int contact;  ///< the adapter's index of the contact
    double e;     ///< the restitution the impact used
  };
  /// Records an impact.
  void record(int contact, double e) { impacts_.push_back({contact, e}); }
  /// The impacts of one round when the last three rounds were the same
  /// (a period of at most max_period impacts); otherwise, once 2 · window
  /// impacts are recorded, the last `window` (a cycle whose pattern varies,
  /// as when a light body is pinned in a corner, taken as repeating its
  /// latest stretch); empty when neither.
  std::vector<Impact> round(int max_period, int window) const;
  /// The round to try to replace by its limit after the latest impact, or
  /// empty: a try once 12 impacts are recorded, and again each time the
  /// record has doubled after a round that did not settle; the repeating
  /// round (or the latest window) at first, and after a limit that left
  /// another contact approaching, every impact since (the contacts that
  /// cycle together). `contacts` is how many contacts may take part.
  std::vector<Impact> due_round(int contacts);
  /// The round from due_round() was replaced by its limit: starts over.
  void settled();
  /// Forgets every impact, for the next resolution (keeps the storage).
  void restart() {
    impacts_.clear();
    next_try_ = 12;
    settles_ = 0;
  }
  /// Every impact recorded, in order.
  const std::vector<Impact>& all() const { return impacts_; }
  /// Impacts recorded.
  std::size_t size() const { return impacts_.size(); }

 private:
  std::vector<Impact> impacts_;
  std::size_t next_try_ = 12;
  int settles_ = 0;
};

/// The velocities a round maps v to: out = F(v), n values each.
using RoundMap = FunctionRef<void(const double*, double*)>;

template <class F>
RoundMap round_map(const F& f) {
  return function_ref<void(const double*, double*)>(f);
}

/// The limit lim_k F^k(v) of the map F (n velocities) that one round of
/// impacts applies. F is linear for contacts whose gaps do not move on their
/// own (F(0) = 0; otherwise no limit is taken); its matrix C is read off F
/// and the limit is P v, P the projection onto ker(C − I) along
/// range(C − I): what the round leaves unchanged is kept, what it damps
/// dropped (a decay per round of 1 − 2m/M down to m/M ≈ 1e-11 is told from
/// rounding). Velocities the round does not touch are copied. Writes the
/// limit into `out` and returns true; returns false (out untouched) when
/// some part keeps its size and flips or turns (a reflection) or grows, or
/// λ = 1 lacks a full set of eigenvectors: nothing settles, and the caller
/// goes on impact by impact.
bool round_limit(int n, const double* v, RoundMap round, double* out);

/// After a round's limit v (n velocities, changed in place): the contacts
/// 0 … count − 1 of the round still approaching by rounding (rate(k, v) <
/// −1e-13 speed) are closed plastically, all together — the limit of
/// plastic impacts on them in turn, `plastic(k, v)` applying one (linear in
/// v); a contact closed stays closed while others join. The limit is exact
/// only to rounding amplified by the slowest decay (about ε M/(2m)); closed
/// one at a time, a light body in a corner cycles again. Returns false when
/// one approaches by more than 1e-6 of `speed` (the rounds had not settled
/// into one pattern) or a limit fails.
bool close_together(int n, double* v, int count, double speed, FunctionRef<double(int, const double*)> rate,
                    FunctionRef<void(int, double*)> plastic);

}  // namespace lagrangian::detail
