#pragma once
// The momentum monitor of a system of point masses, one for every engine
// (models with particles() or mass_points(), particle scenes, the
// hard-sphere engine). The per-sample part is inline; the rest is compiled
// once (src/integrate/point_momenta_monitor.cpp).

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

#include "lagrangian/integrate/report.hpp"

namespace lagrangian::detail {

/// P = Σ m v (kg·m/s) and L = Σ m (r − r₀) × v (kg·m²/s) at one sample,
/// summed point by point, and what they say over the run: the first
/// sample's P and L are the initial ones, and each later sample updates the
/// drift of the components the report calls conserved; the first nonzero
/// Σ m |v| and Σ m |r − r₀| |v| are the scales the sanity monitor
/// (check_drift) measures the drifts by.
class PointMomenta {
 public:
  /// r₀: the point angular momentum is taken about (m).
  explicit PointMomenta(const std::array<double, 3>& r0) : r0_(r0) {}
  /// Starts the sum of one sample.
  void clear() {
    P_ = L_ = {};
    p_scale_ = l_scale_ = 0;
  }
  /// Adds a point of mass m (kg) at r (m) moving at v (m/s), 3 values each.
  void add(double mass, const double* r, const double* v) {
    // Read once into locals: the stores to P_ and L_ may not alias r or v.
    const double d[3] = {r[0] - r0_[0], r[1] - r0_[1], r[2] - r0_[2]};
    const double u[3] = {v[0], v[1], v[2]};
    const double p[3] = {mass * u[0], mass * u[1], mass * u[2]};
    const double l[3] = {mass * (d[1] * u[2] - d[2] * u[1]), mass * (d[2] * u[0] - d[0] * u[2]),
                         mass * (d[0] * u[1] - d[1] * u[0])};
    for (std::size_t a = 0; a < 3; ++a) {
      P_[a] += p[a];
      L_[a] += l[a];
    }
    if (!scales_found_) add_scales(mass, d, u);
  }
  const std::array<double, 3>& linear() const { return P_; }
  const std::array<double, 3>& angular() const { return L_; }
  /// The sample just summed into the report (RunReport::has_particles and
  /// the linear_/angular_momentum_* fields).
  void record(RunReport& report) {
    if (!started_) start(report);
    // |P − P₀| and |L − L₀| over the conserved components (weights 1, the
    // rest 0): the drifts of this sample.
    double sp = 0, sl = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      const double dp = P_[k] - report.linear_momentum_initial[k];
      const double dl = L_[k] - report.angular_momentum_initial[k];
      sp += wp_[k] * (dp * dp);
      sl += wl_[k] * (dl * dl);
    }
    report.linear_momentum_drift_final = std::sqrt(sp);
    report.angular_momentum_drift_final = std::sqrt(sl);
    report.linear_momentum_drift_max = std::max(report.linear_momentum_drift_max, report.linear_momentum_drift_final);
    report.angular_momentum_drift_max = std::max(report.angular_momentum_drift_max, report.angular_momentum_drift_final);
    if (!scales_found_) record_scales(report);
  }

 private:
  void add_scales(double mass, const double* d, const double* v);
  /// The first sample: its P and L are the initial ones, and the report's
  /// conserved components (judged before the first sample) weigh the
  /// drifts.
  void start(RunReport& report);
  /// The scales, from the first sample where they are nonzero.
  void record_scales(RunReport& report);
  std::array<double, 3> r0_;
  std::array<double, 3> P_{}, L_{};
  std::array<double, 3> wp_{}, wl_{};  // 1 for a conserved component, 0 for the rest
  double p_scale_ = 0, l_scale_ = 0;  // Σ m |v|, Σ m |r − r0| |v| of this sample
  bool started_ = false;
  bool scales_found_ = false;  // both scales set: the samples need not sum them
};

}  // namespace lagrangian::detail
