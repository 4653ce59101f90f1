// Gas fill: the lattice that holds a [gas] in its box, the molecules' random
// velocities with zero total momentum, their names, and Scene::expand_gas.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>

#include "lagrangian/scene/scene.hpp"
#include "scene_gas_fill.hpp"
#include "scene_messages.hpp"

namespace lagrangian::scene {

namespace detail {

// -- the gas lattice ------------------------------------------------------------

namespace {

constexpr double kLatticeMargin = 1e-6;  // spacing ≥ 2R(1 + margin), walls ≥ R(1 + margin) away

/// Sites per axis at spacing s (capped at `count`, as doubles: no overflow).
std::array<double, 3> sites_per_axis(const Vec3& usable, double s, double count) {
  std::array<double, 3> n{};
  for (int a = 0; a < 3; ++a) {
    if (!(usable[a] >= 0)) {
      n[a] = 0;
    } else {
      n[a] = std::min(std::floor(usable[a] / s) + 1.0, count);
    }
  }
  return n;
}

double capacity(const std::array<double, 3>& n) { return n[0] * n[1] * n[2]; }

}  // namespace

double gas_capacity(const GasFill& gas, const BoxContact& box) {
  const double s = 2.0 * gas.radius * (1.0 + kLatticeMargin);
  const Vec3 usable = (box.max - box.min).array() - s;
  return capacity(sites_per_axis(usable, s, std::max(1.0, static_cast<double>(gas.count))));
}

std::optional<GasLayout> gas_layout(const GasFill& gas, const BoxContact& box) {
  if (gas.count < 1 || !(gas.radius > 0) || !std::isfinite(gas.radius)) return std::nullopt;
  const double count = static_cast<double>(gas.count);
  const double s_min = 2.0 * gas.radius * (1.0 + kLatticeMargin);
  const Vec3 usable = (box.max - box.min).array() - s_min;
  if (!usable.allFinite() || !std::isfinite(s_min)) return std::nullopt;
  if (capacity(sites_per_axis(usable, s_min, count)) < count) return std::nullopt;

  // The widest spacing that still holds `count` sites spreads the gas over the box.
  double lo = s_min;
  if (gas.count > 1) {
    double hi = s_min + usable.maxCoeff();
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
      const double mid = lo + 0.5 * (hi - lo);
      if (capacity(sites_per_axis(usable, mid, count)) >= count) {
        lo = mid;
      } else {
        hi = mid;
      }
    }
  }
  GasLayout layout;
  layout.spacing = lo;
  layout.count = gas.count;
  const auto n = sites_per_axis(usable, lo, count);
  for (int a = 0; a < 3; ++a) {
    layout.n[a] = static_cast<std::int64_t>(n[a]);
    layout.first[a] = 0.5 * (box.min[a] + box.max[a]) - 0.5 * static_cast<double>(layout.n[a] - 1) * lo;
  }
  return layout;
}

Vec3 GasLayout::site(std::int64_t k) const {
  const std::int64_t ix = k % n[0];
  const std::int64_t iy = (k / n[0]) % n[1];
  const std::int64_t iz = k / (n[0] * n[1]);
  return site(ix, iy, iz);
}

Vec3 GasLayout::site(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
  return {first[0] + static_cast<double>(ix) * spacing, first[1] + static_cast<double>(iy) * spacing,
          first[2] + static_cast<double>(iz) * spacing};
}

std::vector<GasLayout::Block> GasLayout::blocks() const {
  // Sites are filled x fastest, then y, then z: full layers, full rows of the
  // next layer, then part of a row.
  std::vector<Block> out;
  const std::int64_t layer = n[0] * n[1];
  const std::int64_t layers = count / layer;
  const std::int64_t rem = count % layer;
  const std::int64_t rows = rem / n[0];
  const std::int64_t part = rem % n[0];
  if (layers > 0) out.push_back({{0, 0, 0}, {n[0], n[1], layers}});
  if (rows > 0) out.push_back({{0, 0, layers}, {n[0], rows, layers + 1}});
  if (part > 0) out.push_back({{0, rows, layers}, {part, rows + 1, layers + 1}});
  return out;
}

std::int64_t GasLayout::index(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
  return ix + n[0] * (iy + n[1] * iz);
}

namespace {

/// Mean of the random unit directions and 1/rms of the directions less
/// their mean: molecule k moves with speed·(d_k − mean)·inv_rms, so that the
/// total momentum is zero and the rms speed is `speed`. |(d_k − mean)·inv_rms|
/// ≤ √count, so no intermediate overflows when speed·√count is finite.
struct GasVelocity {
  Vec3 mean = Vec3::Zero();
  double inv_rms = 0;
  Vec3 velocity(const Vec3& direction, double speed) const { return ((direction - mean) * inv_rms) * speed; }
};

/// Uniform double in [0, 1) from the top 53 bits of one draw.
double unit(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

Vec3 random_direction(std::mt19937_64& rng) {
  const double z = 2.0 * unit(rng) - 1.0;
  const double phi = 2.0 * std::numbers::pi * unit(rng);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

GasVelocity gas_velocity(const GasFill& gas) {
  GasVelocity out;
  if (gas.count < 1) return out;
  const double n = static_cast<double>(gas.count);
  std::mt19937_64 rng(gas.seed);
  Vec3 sum = Vec3::Zero();
  for (std::int64_t k = 0; k < gas.count; ++k) sum += random_direction(rng);
  out.mean = sum / n;
  rng.seed(gas.seed);
  double sq = 0;
  for (std::int64_t k = 0; k < gas.count; ++k) sq += (random_direction(rng) - out.mean).squaredNorm();
  const double rms = std::sqrt(sq / n);
  // One sphere (or directions that cancel to rounding) cannot move with zero momentum.
  out.inv_rms = rms > 1e-12 ? 1.0 / rms : 0.0;
  return out;
}

}  // namespace

std::string gas_name(const GasFill& gas, std::int64_t k) { return gas.prefix + std::to_string(k + 1); }

std::int64_t gas_index(const GasFill& gas, const std::string& name) {
  if (name.size() <= gas.prefix.size() || name.compare(0, gas.prefix.size(), gas.prefix) != 0) return -1;
  const std::string digits = name.substr(gas.prefix.size());
  if (digits.size() > 9 || digits[0] == '0') return -1;
  std::int64_t v = 0;
  for (const char c : digits) {
    if (c < '0' || c > '9') return -1;
    v = v * 10 + (c - '0');
  }
  if (v < 1 || v > gas.count) return -1;
  return v - 1;
}

}  // namespace detail

using detail::format_value;

// -- expand_gas ------------------------------------------------------------------------

void Scene::expand_gas() {
  if (!gas) return;
  const GasFill& g = *gas;
  if (g.count < 1 || g.count > detail::kMaxGasCount)
    throw SceneError("gas.count", "must be in [1, " + std::to_string(detail::kMaxGasCount) + "], got " +
                                      std::to_string(g.count), source);
  if (!box) throw SceneError("gas", "needs [contacts.box] to hold the gas", source);
  const auto layout = detail::gas_layout(g, *box);
  if (!layout)
    throw SceneError("gas.count", std::to_string(g.count) + " spheres of radius " + format_value(g.radius) +
                                      " do not fit in the box",
                     source);
  const detail::GasVelocity gv = detail::gas_velocity(g);
  std::mt19937_64 rng(g.seed);
  bodies.reserve(bodies.size() + static_cast<std::size_t>(g.count));
  for (std::int64_t k = 0; k < g.count; ++k) {
    Body b;
    b.name = detail::gas_name(g, k);
    b.mass = g.mass;
    b.radius = g.radius;
    b.position = layout->site(k);
    b.velocity = gv.velocity(detail::random_direction(rng), g.speed);
    bodies.push_back(std::move(b));
  }
  gas.reset();
}

}  // namespace lagrangian::scene
