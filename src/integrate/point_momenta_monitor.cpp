#include "lagrangian/integrate/detail/point_momenta_monitor.hpp"

#include <cmath>

namespace lagrangian::detail {

void PointMomenta::add_scales(double mass, const double* d, const double* v) {
  const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  p_scale_ += std::abs(mass) * speed;
  l_scale_ += std::abs(mass) * std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) * speed;
}

void PointMomenta::start(RunReport& report) {
  started_ = true;
  report.has_particles = true;
  report.linear_momentum_initial = P_;
  report.angular_momentum_initial = L_;
  for (std::size_t k = 0; k < 3; ++k) {
    wp_[k] = report.linear_momentum_conserved[k] ? 1.0 : 0.0;
    wl_[k] = report.angular_momentum_conserved[k] ? 1.0 : 0.0;
  }
}

void PointMomenta::record_scales(RunReport& report) {
  // The scales at t0: a run whose error flings the bodies off would grow a
  // running maximum with its own error. Zero at t0 (all at rest): the first
  // nonzero value met.
  if (report.momentum_scale == 0) report.momentum_scale = p_scale_;
  if (report.angular_momentum_scale == 0) report.angular_momentum_scale = l_scale_;
  scales_found_ = report.momentum_scale != 0 && report.angular_momentum_scale != 0;
}

}  // namespace lagrangian::detail
