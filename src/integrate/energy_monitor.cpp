#include "lagrangian/integrate/detail/energy_monitor.hpp"

#include <algorithm>
#include <cmath>

#include "lagrangian/integrate/report.hpp"

namespace lagrangian::detail {

void EnergyMonitor::start(RunReport& report, double h0) {
  pending_.clear();
  total_ = false;
  h0_ = h_last_ = h0;
  h_drift_ = e_drift_ = h_differs_ = 0;
  scale_ = EnergyScale();
  scale_.meet(h0);
  report.energy_initial = h0;
  rescale(report);
}

void EnergyMonitor::start(RunReport& report, double h0, double kinetic0, double potential0) {
  start(report, h0);
  total_ = true;
  e0_ = e_last_ = kinetic0 + potential0;
  scale_.meet(kinetic0, potential0);
  report.has_total_energy = true;
  report.total_energy_initial = e0_;
  rescale(report);
}

void EnergyMonitor::shift(double t, double dh, double dE) { pending_.push_back({t, dh, dE}); }

void EnergyMonitor::apply_shifts(double t) {
  std::size_t k = 0;
  for (; k < pending_.size() && pending_[k].t <= t; ++k) {
    h0_ += pending_[k].dh;
    e0_ += pending_[k].dE;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(k));
}

void EnergyMonitor::finish(RunReport& report, double t) {
  apply_shifts(t);
  report.energy_final = h_last_;
  report.energy_drift_final = std::abs(h_last_ - h0_) / report.energy_scale;
  if (total_) {
    report.total_energy_final = e_last_;
    report.total_energy_drift_final = std::abs(e_last_ - e0_) / report.energy_scale;
    report.total_energy_is_h = h_differs_ <= 1e-9 * report.energy_scale;
  }
}

}  // namespace lagrangian::detail
