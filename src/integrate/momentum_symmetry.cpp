#include "lagrangian/integrate/detail/momentum_symmetry.hpp"

#include <cmath>
#include <cstdint>
#include <vector>

namespace lagrangian::detail {

namespace {

constexpr const char* kAxis[3] = {"x", "y", "z"};

}  // namespace

void MomentumSymmetry::add(double m, const double* r, const double* a) {
  const double d[3] = {r[0] - r0_[0], r[1] - r0_[1], r[2] - r0_[2]};
  const double f[3] = {m * a[0], m * a[1], m * a[2]};
  const double torque[3] = {d[1] * f[2] - d[2] * f[1], d[2] * f[0] - d[0] * f[2], d[0] * f[1] - d[1] * f[0]};
  const double fn = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  const double dn = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (int k = 0; k < 3; ++k) {
    p_[k] += f[k];
    l_[k] += torque[k];
  }
  p_scale_ += fn;
  l_scale_ += fn * dn;
}

void MomentumSymmetry::end_probe(Source source) {
  // A sum of terms that cancel exactly keeps rounding of about ε per term:
  // 1e-9 of the terms' scale is far above it and far below any force that
  // acts.
  constexpr double rel = 1e-9;
  for (int k = 0; k < 3; ++k) {
    if (!(std::abs(p_[k]) <= rel * p_scale_)) (source == Source::force ? p_force_ : p_contact_)[k] = true;
    if (!(std::abs(l_[k]) <= rel * l_scale_)) (source == Source::force ? l_force_ : l_contact_)[k] = true;
  }
  p_ = {};
  l_ = {};
  p_scale_ = l_scale_ = 0;
}

void MomentumSymmetry::write(RunReport& report) const {
  for (int k = 0; k < 3; ++k) {
    const auto i = static_cast<std::size_t>(k);
    report.linear_momentum_conserved[i] = !p_force_[i] && !p_contact_[i];
    report.angular_momentum_conserved[i] = !l_force_[i] && !l_contact_[i];
    std::string why;
    if (p_force_[i]) why = std::string("the external forces have a part along ") + kAxis[k];
    if (p_contact_[i]) why += std::string(why.empty() ? "" : "; ") + "impacts with fixed surfaces push along " + kAxis[k];
    report.linear_momentum_reason[i] = why;
    why.clear();
    if (l_force_[i]) why = std::string("the external forces have a moment about ") + kAxis[k];
    if (l_contact_[i])
      why += std::string(why.empty() ? "" : "; ") + "impacts with fixed surfaces have a moment about " + kAxis[k];
    report.angular_momentum_reason[i] = why;
  }
}

void for_each_probe_state(const double* x0, int m, double t0, double t_end,
                          FunctionRef<void(const double*, double)> probe) {
  std::vector<double> x(x0, x0 + m);
  std::uint64_t seed = 0x2545F4914F6CDD1DULL;
  auto uniform = [&seed] {  // in [−1, 1)
    seed = seed * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(seed >> 11) * 0x1.0p-52 - 1.0;
  };
  constexpr int probes = 5;
  for (int k = 0; k < probes; ++k) {
    if (k > 0)
      for (int i = 0; i < m; ++i) x[static_cast<std::size_t>(i)] = x0[i] + 0.1 * (1 + std::abs(x0[i])) * uniform();
    probe(x.data(), t0 + (t_end - t0) * k / probes);
  }
}

}  // namespace lagrangian::detail
