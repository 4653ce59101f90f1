#pragma once
// The momentum monitor of a system of point masses, one for every engine
// (models with particles() or mass_points(), particle scenes, the
// hard-sphere engine; compiled once: src/integrate/point_momenta_monitor.cpp).

#include <array>
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
    const double d[3] = {r[0] - r0_[0], r[1] - r0_[1], r[2] - r0_[2]};
    for (std::size_t a = 0; a < 3; ++a) P_[a] += mass * v[a];
    L_[0] += mass * (d[1] * v[2] - d[2] * v[1]);
    L_[1] += mass * (d[2] * v[0] - d[0] * v[2]);
    L_[2] += mass * (d[0] * v[1] - d[1] * v[0]);
    if (!scales_found_) add_scales(mass, d, v);
  }
  const std::array<double, 3>& linear() const { return P_; }
  const std::array<double, 3>& angular() const { return L_; }
  /// The sample just summed into the report (RunReport::has_particles and
  /// the linear_/angular_momentum_* fields).
  void record(RunReport& report);

 private:
  void add_scales(double mass, const double* d, const double* v);
  std::array<double, 3> r0_;
  std::array<double, 3> P_{}, L_{};
  double p_scale_ = 0, l_scale_ = 0;  // Σ m |v|, Σ m |r − r0| |v| of this sample
  bool started_ = false;
  bool scales_found_ = false;  // both scales set: the samples need not sum them
};

}  // namespace lagrangian::detail
