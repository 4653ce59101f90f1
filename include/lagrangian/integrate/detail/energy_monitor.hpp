#pragma once
// The energy monitor of a run, the same for every adapter (ModelSystem, the
// particle scenes' system): the drift of h and of E = T + V against their
// values at the start, moved by what impacts take, relative to the run's
// energy scale. The per-sample part is inline (it runs at every sample);
// the rest is compiled once (src/integrate/energy_monitor.cpp).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "lagrangian/integrate/report.hpp"

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

/// Watches h = p·q̇ − L (J) and, for a system that has them, E = T + V (J).
/// Their drifts, max |h − h₀| and max |E − E₀| over the samples, are written
/// to the RunReport divided by the energy scale (RunReport::energy_drift_max,
/// total_energy_drift_max, energy_scale). An impact at time t_i moves h₀ and
/// E₀ by what it took from t_i on, so that the monitor measures integration
/// error only; samples interpolated before t_i, from the step cut there,
/// still compare with the old references.
class EnergyMonitor {
 public:
  /// A run starting with h₀ (J); E = T + V not watched.
  void start(RunReport& report, double h0);
  /// A run starting with h₀, T₀ and V₀ (J); E = T + V watched too.
  void start(RunReport& report, double h0, double kinetic0, double potential0);
  /// An impact at t changed h by dh and E by dE (J; an impulse leaves V as
  /// it is, so dE = ΔT).
  void shift(double t, double dh, double dE);
  /// A sample at t with energy h (J).
  void sample(RunReport& report, double t, double h) {
    if (!pending_.empty()) apply_shifts(t);
    h_last_ = h;
    h_drift_ = std::max(h_drift_, std::abs(h - h0_));
    scale_.meet(h);
    rescale(report);
  }
  /// A sample at t with energy h, T and V (J).
  void sample(RunReport& report, double t, double h, double kinetic, double potential) {
    if (!pending_.empty()) apply_shifts(t);
    h_last_ = h;
    h_drift_ = std::max(h_drift_, std::abs(h - h0_));
    scale_.meet(h);
    e_last_ = kinetic + potential;
    e_drift_ = std::max(e_drift_, std::abs(e_last_ - e0_));
    scale_.meet(kinetic, potential);
    h_differs_ = std::max(h_differs_, std::abs(e_last_ - h));
    rescale(report);
  }
  /// A sample at t of a run whose h is E = T + V (particles in fixed
  /// surroundings; started with h₀ = T₀ + V₀ and shifted with dh = dE): T
  /// and V (J). The two drifts are one, computed once; the scale meets
  /// |T| + |V| alone, never less than |h|.
  void sample_h_is_total(RunReport& report, double t, double kinetic, double potential) {
    if (!pending_.empty()) apply_shifts(t);
    h_last_ = e_last_ = kinetic + potential;
    h_drift_ = e_drift_ = std::max(h_drift_, std::abs(h_last_ - h0_));
    scale_.meet(kinetic, potential);
    rescale(report);
  }
  /// The run ended at t: the final drifts, the final energies, and whether
  /// E equalled h at every sample (to 1e-9 of the scale).
  void finish(RunReport& report, double t);

 private:
  /// Moves h₀ and E₀ by the shifts of the impacts at or before t.
  void apply_shifts(double t);
  void rescale(RunReport& report) const {
    report.energy_scale = scale_.value();
    report.energy_drift_max = h_drift_ / report.energy_scale;
    if (total_) report.total_energy_drift_max = e_drift_ / report.energy_scale;
  }

  struct Shift {
    double t, dh, dE;
  };
  std::vector<Shift> pending_;
  bool total_ = false;
  double h0_ = 0, e0_ = 0, h_last_ = 0, e_last_ = 0;
  double h_drift_ = 0, e_drift_ = 0, h_differs_ = 0;  // J
  EnergyScale scale_;
};

}  // namespace lagrangian::detail
