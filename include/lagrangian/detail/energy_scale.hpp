#pragma once
// The energy scale of a run (RunReport::energy_scale), kept the same way by
// both adapters (ModelSystem, the particle scenes' system).

#include <algorithm>
#include <cmath>

namespace lagrangian::detail {

/// The largest |h| (or |E|) and |T| + |V| met so far (J): the energy the
/// motion moves around, so that a start at E = 0 (a pendulum let go from the
/// horizontal, a parabolic orbit) does not make rounding look like drift.
/// Non-finite values are not met. 1 J until a positive value is met.
class EnergyScale {
 public:
  void meet(double energy) {
    if (std::isfinite(energy)) largest_ = std::max(largest_, std::abs(energy));
  }
  void meet(double kinetic, double potential) { meet(std::abs(kinetic) + std::abs(potential)); }
  double value() const { return largest_ > 0 ? largest_ : 1.0; }

 private:
  double largest_ = 0;
};

}  // namespace lagrangian::detail
