#pragma once
// What the energy charts (the animation page, energy.png) plot, the same for
// both.

#include <cmath>

namespace lagrangian::detail {

/// The charts plot the relative change (E − E0)/|E0| on an axis at least
/// ±kEnergyChartFloor wide: a change below it is round-off or tolerance,
/// drawn as the flat line it is, and the chart's title says how constant the
/// energy was.
inline constexpr double kEnergyChartFloor = 1e-10;

/// What the charts divide E − E0 by (J): |E0|, or `scale` (the run's energy
/// scale) where E0 is 0 or not finite.
inline double energy_chart_reference(double e0, double scale) {
  return std::isfinite(e0) && e0 != 0 ? std::abs(e0) : scale;
}

}  // namespace lagrangian::detail
