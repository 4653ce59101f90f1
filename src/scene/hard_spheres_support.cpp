// Hard-sphere support shared by the engine and validate(): the uniform cell
// grid over the box (the broad phase), and sphere and wall names and numbers
// as error messages and reports write them.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>

#include "hard_spheres_common.hpp"
#include "lagrangian/params.hpp"

namespace lagrangian::detail::hard_spheres {

Grid make_grid(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double reach, std::size_t count, bool single) {
  Grid g;
  g.lo = lo;
  if (!single && reach > 0) {
    const double cap = 8.0 * static_cast<double>(count) + 64.0;
    std::array<double, 3> nd{};
    for (int d = 0; d < 3; ++d)
      nd[d] = std::clamp(std::floor((hi[d] - lo[d]) / (reach * (1 + 1e-9))), 1.0, cap);
    const double total = nd[0] * nd[1] * nd[2];
    if (total > cap) {
      const double f = std::cbrt(cap / total);
      for (auto& x : nd) x = std::max(1.0, std::floor(x * f));
    }
    while (nd[0] * nd[1] * nd[2] > cap) {
      auto& big = *std::max_element(nd.begin(), nd.end());
      big = std::max(1.0, std::floor(big / 2));
    }
    for (int d = 0; d < 3; ++d) g.n[d] = static_cast<int>(nd[d]);
  }
  for (int d = 0; d < 3; ++d) g.width[d] = (hi[d] - lo[d]) / g.n[d];
  return g;
}

double largest_radius(const HardSphereSystem& s) {
  double r = 0;
  for (const auto& sp : s.spheres) r = std::max(r, sp.radius);
  return r;
}

}  // namespace lagrangian::detail::hard_spheres

namespace lagrangian::detail::hard_spheres {

std::string num(double v) { return detail::format_number(v); }

std::string vec(const Eigen::Vector3d& v) { return "(" + num(v.x()) + ", " + num(v.y()) + ", " + num(v.z()) + ")"; }

std::string sphere_name(const HardSphereSystem& s, std::size_t i) {
  return s.spheres[i].name.empty() ? "s" + std::to_string(i + 1) : s.spheres[i].name;
}

std::string wall_name(const HardSphereSystem& s, std::size_t k) {
  return s.walls[k].name.empty() ? "wall" + std::to_string(k + 1) : s.walls[k].name;
}

}  // namespace lagrangian::detail::hard_spheres
