// Hard-sphere validation: validate() checks the options, the box and walls,
// each sphere, unique names, and that no spheres overlap at t0.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <string>
#include <vector>

#include "lagrangian/errors.hpp"
#include "lagrangian/scene/hard_spheres.hpp"
#include "hard_spheres_common.hpp"

namespace lagrangian {

namespace {

using detail::hard_spheres::Grid;
using detail::hard_spheres::kAxis;
using detail::hard_spheres::kMaxSpheres;
using detail::hard_spheres::largest_radius;
using detail::hard_spheres::make_grid;
using detail::hard_spheres::num;
using detail::hard_spheres::sphere_name;
using detail::hard_spheres::vec;
using detail::hard_spheres::wall_name;

[[noreturn]] void fail(const std::string& what) { throw OptionError("hard spheres: " + what); }

void check_restitution(const std::string& field, double e) {
  if (!(e >= 0.0 && e <= 1.0)) fail(field + " must be in [0, 1], got " + num(e));
}

/// The run options: finite times, t_end > t0, the output interval, the
/// event limit, the collapse time and the angular momentum's point.
void check_options(const HardSphereOptions& opt) {
  if (!std::isfinite(opt.t0)) fail("option 't0' must be finite, got " + num(opt.t0));
  if (!std::isfinite(opt.t_end)) fail("option 't_end' must be finite, got " + num(opt.t_end));
  if (!(opt.t_end > opt.t0))
    fail("option 't_end' must be greater than t0 = " + num(opt.t0) + ", got " + num(opt.t_end));
  if (!(std::isfinite(opt.output_interval) && opt.output_interval >= 0))
    fail("option 'output_interval' must be finite and >= 0, got " + num(opt.output_interval));
  if (opt.max_events == 0) fail("option 'max_events' must be > 0, got 0");
  if (!(std::isfinite(opt.collapse_time) && opt.collapse_time >= 0))
    fail("option 'collapse_time' must be finite and >= 0 s, got " + num(opt.collapse_time));
  if (!opt.angular_momentum_point.allFinite())
    fail("option 'angular_momentum_point' must be finite, got " + vec(opt.angular_momentum_point));
}

/// The box's corners, the restitutions and each wall's point, normal and
/// restitution.
void check_box_and_walls(const HardSphereSystem& sys) {
  for (int d = 0; d < 3; ++d) {
    if (!std::isfinite(sys.box_min[d]) || !std::isfinite(sys.box_max[d]))
      fail("box corners must be finite, got box_min = " + vec(sys.box_min) + " m, box_max = " + vec(sys.box_max) + " m");
    if (!(sys.box_max[d] > sys.box_min[d]))
      fail(std::string("box_max.") + kAxis[d] + " = " + num(sys.box_max[d]) + " m must be greater than box_min." +
           kAxis[d] + " = " + num(sys.box_min[d]) + " m");
  }
  check_restitution("box_restitution", sys.box_restitution);
  check_restitution("pair_restitution", sys.pair_restitution);
  for (std::size_t k = 0; k < sys.walls.size(); ++k) {
    const auto& w = sys.walls[k];
    const std::string who = "wall \"" + wall_name(sys, k) + "\"";
    if (!w.point.allFinite()) fail(who + ": point must be finite, got " + vec(w.point) + " m");
    if (!w.normal.allFinite() || !(w.normal.norm() > 0))
      fail(who + ": normal must be finite and non-zero, got " + vec(w.normal));
    check_restitution(who + ": restitution", w.restitution);
  }
}

/// Each sphere: mass, radius, finite state, inside the box and on the open
/// side of every wall; the number of spheres and walls.
void check_spheres(const HardSphereSystem& sys) {
  const std::size_t n = sys.spheres.size();
  if (n > kMaxSpheres || sys.walls.size() > kMaxSpheres - 6)
    fail("at most " + std::to_string(kMaxSpheres) + " spheres and walls are supported, got " + std::to_string(n) +
         " spheres and " + std::to_string(sys.walls.size()) + " walls");
  for (std::size_t i = 0; i < n; ++i) {
    const auto& s = sys.spheres[i];
    const std::string who = "sphere \"" + sphere_name(sys, i) + "\"";
    if (!(std::isfinite(s.mass) && s.mass > 0)) fail(who + ": mass must be finite and > 0 kg, got " + num(s.mass));
    if (!(std::isfinite(s.radius) && s.radius > 0))
      fail(who + ": radius must be finite and > 0 m, got " + num(s.radius));
    for (int d = 0; d < 3; ++d) {
      if (!std::isfinite(s.position[d]))
        fail(who + ": position." + kAxis[d] + " must be finite, got " + num(s.position[d]));
      if (!std::isfinite(s.velocity[d]))
        fail(who + ": velocity." + kAxis[d] + " must be finite, got " + num(s.velocity[d]));
    }
    for (int d = 0; d < 3; ++d) {
      const double lo = sys.box_min[d] + s.radius, hi = sys.box_max[d] - s.radius;
      const double x = s.position[d];
      if (!(x >= lo && x <= hi))
        fail(who + " (radius " + num(s.radius) + " m) at " + vec(s.position) + " m is not inside the box: its centre's " +
             kAxis[d] + " = " + num(x) + " m must lie in [box_min." + kAxis[d] + " + R, box_max." + kAxis[d] +
             " - R] = [" + num(lo) + ", " + num(hi) + "] m");
    }
    for (std::size_t k = 0; k < sys.walls.size(); ++k) {
      const auto& w = sys.walls[k];
      const double g = w.normal.normalized().dot(s.position - w.point);
      if (!(g >= s.radius))
        fail(who + " (radius " + num(s.radius) + " m) at " + vec(s.position) + " m is not on the open side of wall \"" +
             wall_name(sys, k) + "\": its distance along the normal n·(r - p) = " + num(g) + " m must be >= R");
    }
  }
}

/// No two spheres overlap at t0, looked for on a cell grid (neighbouring
/// cells only); `names` are the spheres' names.
void check_no_overlaps(const HardSphereSystem& sys, const std::vector<std::string>& names) {
  const std::size_t n = sys.spheres.size();
  const Grid g = make_grid(sys.box_min, sys.box_max, 2 * largest_radius(sys), n, false);
  std::vector<std::size_t> cell(n), start(g.cells() + 1, 0), sorted(n);
  for (std::size_t i = 0; i < n; ++i) {
    cell[i] = g.index(g.locate(sys.spheres[i].position));
    ++start[cell[i] + 1];
  }
  std::partial_sum(start.begin(), start.end(), start.begin());
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) sorted[fill[cell[i]]++] = i;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const auto& s = sys.spheres[i];
    const auto c = g.locate(s.position);
    for (int z = std::max(c[2] - 1, 0); z <= std::min(c[2] + 1, g.n[2] - 1); ++z)
      for (int y = std::max(c[1] - 1, 0); y <= std::min(c[1] + 1, g.n[1] - 1); ++y)
        for (int x = std::max(c[0] - 1, 0); x <= std::min(c[0] + 1, g.n[0] - 1); ++x) {
          const std::size_t cc = g.index(x, y, z);
          for (std::size_t k = start[cc]; k < start[cc + 1]; ++k) {
            const std::size_t j = sorted[k];
            if (j <= i) continue;
            const auto& o = sys.spheres[j];
            const double dist = (s.position - o.position).norm();
            const double sum = s.radius + o.radius;
            if (dist < sum)
              fail("spheres \"" + names[i] + "\" and \"" + names[j] + "\" overlap at t0: the distance between their centres " +
                   num(dist) + " m is less than the sum of their radii " + num(sum) + " m");
          }
        }
  }
}

}  // namespace

void validate(const HardSphereSystem& sys, const HardSphereOptions& opt) {
  check_options(opt);
  check_box_and_walls(sys);
  check_spheres(sys);
  const std::size_t n = sys.spheres.size();

  // Unique names.
  std::vector<std::string> names(n);
  for (std::size_t i = 0; i < n; ++i) names[i] = sphere_name(sys, i);
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return names[a] < names[b]; });
  for (std::size_t k = 1; k < n; ++k)
    if (names[order[k]] == names[order[k - 1]]) {
      const auto a = std::min(order[k], order[k - 1]), b = std::max(order[k], order[k - 1]);
      fail("spheres " + std::to_string(a + 1) + " and " + std::to_string(b + 1) + " are both named \"" + names[a] +
           "\"; names must be unique");
    }

  check_no_overlaps(sys, names);
}

}  // namespace lagrangian
