// Kinetic theory against a run of a gas (scene/run.hpp, GasCheck): the
// temperature and the speed distribution from the final velocities, the
// pressure from the impulses the box's walls received.

#include "gas_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <optional>
#include <sstream>

#include "lagrangian/scene/hard_spheres.hpp"

namespace {

std::string g(double v, int digits = 4) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

}  // namespace

namespace lagrangian::scene::detail {
namespace {

constexpr double kBoltzmann = 1.380649e-23;  // J/K, exact (SI 2019)

/// Maxwell–Boltzmann cumulative distribution of speeds with a = √(kT/m):
/// F(v) = erf(v / (√2 a)) − √(2/π) (v/a) exp(−v² / (2a²)).
double maxwell_cdf(double v, double a) {
  const double x = v / a;
  return std::erf(x / std::sqrt(2.0)) - std::sqrt(2.0 / M_PI) * x * std::exp(-0.5 * x * x);
}

}  // namespace

std::optional<GasCheck> gas_check(const Scene& scene, const RunResult& result) {
  // Equal spheres in a box, elastic, nothing else declared, wall impulses counted.
  if (scene.model || !scene.box || !scene.sphere_contacts || scene.bodies.size() < 10) return std::nullopt;
  for (const auto& kind : scene.declared())
    if (kind != "sphere_contacts" && kind != "box_contacts") return std::nullopt;
  if (scene.box->restitution != 1.0 || scene.sphere_contacts->restitution != 1.0) return std::nullopt;
  const Body& first = scene.bodies.front();
  for (const Body& b : scene.bodies)
    if (b.mass != first.mass || b.radius != first.radius || !(b.radius > 0)) return std::nullopt;
  const std::size_t n = scene.bodies.size();
  if (result.qd_final.size() != 3 * n || result.report.wall_impulses.empty()) return std::nullopt;

  GasCheck c;
  c.molecules = n;
  c.mass = first.mass;
  c.radius = first.radius;
  const Vec3 L = scene.box->max - scene.box->min;
  c.volume = L.prod();
  c.duration = result.report.t_final - result.report.t0;
  c.speeds.resize(n);
  double sum_v2 = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double v2 = result.qd_final[3 * i] * result.qd_final[3 * i] +
                      result.qd_final[3 * i + 1] * result.qd_final[3 * i + 1] +
                      result.qd_final[3 * i + 2] * result.qd_final[3 * i + 2];
    sum_v2 += v2;
    c.speeds[i] = std::sqrt(v2);
  }
  c.mean_square_speed = sum_v2 / static_cast<double>(n);
  c.kT = c.mass * c.mean_square_speed / 3;
  c.temperature = c.kT / kBoltzmann;

  // Pressure: each face's impulse over its area and the time, averaged over
  // the faces; its standard error from the same over the run's equal
  // stretches (RunReport::wall_impulse_blocks). The faces are not
  // independent samples (opposite faces share the momentum; energy moves
  // between the axes), the stretches nearly are.
  constexpr int kB = RunReport::kWallImpulseBlocks;
  std::vector<double> per_block(kB, 0.0);
  for (int f = 0; f < 6; ++f) {
    const auto it = result.report.wall_impulse_blocks.find(box_wall_names[f]);
    if (it == result.report.wall_impulse_blocks.end() || it->second.size() != kB || !(c.duration > 0))
      return std::nullopt;
    const double area = c.volume / L[f / 2];
    for (int b = 0; b < kB; ++b)
      per_block[static_cast<std::size_t>(b)] += it->second[static_cast<std::size_t>(b)] / (area * c.duration / kB) / 6;
  }
  // the whole run's: the stretches are equally long
  c.pressure = std::accumulate(per_block.begin(), per_block.end(), 0.0) / kB;
  double ss = 0;
  for (const double v : per_block) ss += (v - c.pressure) * (v - c.pressure);
  c.pressure_error = std::sqrt(ss / (kB - 1)) / std::sqrt(static_cast<double>(kB));
  c.pressure_ideal = static_cast<double>(n) * c.mass * c.mean_square_speed / (3 * c.volume);
  // The centres stay R from the walls: density n = N / V_free and a face's
  // force spread over the (L_j − 2R)(L_k − 2R) of it the centres reach; the
  // bulk pressure n kT Z with Z = 1 + B₂ n + B₃ n², B₂ = 2πσ³/3, B₃ = 5 B₂²/8.
  const Vec3 free = L - Vec3::Constant(2 * c.radius);
  const double v_free = free.prod();
  const double sigma = 2 * c.radius, b2n = 2 * M_PI * sigma * sigma * sigma / 3 * static_cast<double>(n) / v_free;
  const double z = 1 + b2n + 0.625 * b2n * b2n;
  double reach = 0;  // mean over the axes of the reached part of a face
  for (int a = 0; a < 3; ++a) reach += free.prod() / free[a] / (c.volume / L[a]) / 3;
  c.pressure_expected = static_cast<double>(n) / v_free * c.kT * z * reach;

  // Kolmogorov–Smirnov distance of the speeds from Maxwell–Boltzmann at kT.
  std::vector<double> v = c.speeds;
  std::sort(v.begin(), v.end());
  const double a = std::sqrt(c.kT / c.mass);
  for (std::size_t i = 0; i < n; ++i) {
    const double F = maxwell_cdf(v[i], a);
    c.ks_distance = std::max({c.ks_distance, static_cast<double>(i + 1) / static_cast<double>(n) - F,
                              F - static_cast<double>(i) / static_cast<double>(n)});
  }
  c.ks_critical = 1.36 / std::sqrt(static_cast<double>(n));
  return c;
}

}  // namespace lagrangian::scene::detail

namespace lagrangian::scene {

std::string GasCheck::summary() const {
  std::ostringstream os;
  os << "gas: " << molecules << " molecules, kT = m<v^2>/3 = " << g(kT) << " J (T = " << g(temperature) << " K)\n"
     << "  pressure on the walls " << g(pressure) << " Pa +- " << g(pressure_error, 2) << " (from their impulses over "
     << g(duration) << " s); kinetic theory N m <v^2>/(3V) = " << g(pressure_ideal) << " Pa (ratio "
     << g(pressure / pressure_ideal) << "), with the spheres' size " << g(pressure_expected) << " Pa (ratio "
     << g(pressure / pressure_expected) << ", " << g(std::abs(pressure - pressure_expected) / pressure_error, 2)
     << " standard errors)\n"
     << "  speeds against Maxwell-Boltzmann at kT: Kolmogorov-Smirnov D = " << g(ks_distance, 3)
     << (ks_distance < ks_critical ? " < " : " >= ") << g(ks_critical, 3) << " (the 5 % point 1.36/sqrt(N))"
     << (ks_distance < ks_critical ? "" : ": not yet Maxwellian") << "\n";
  return os.str();
}

}  // namespace lagrangian::scene
