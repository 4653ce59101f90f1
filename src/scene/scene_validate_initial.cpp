// Scene validation of the initial state: bodies inside the box, no
// overlapping spheres, bodies on the open side of contact planes, links at
// their lengths and constrained bodies on their surfaces at t0.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "lagrangian/scene/scene.hpp"
#include "scene_gas_fill.hpp"
#include "scene_messages.hpp"
#include "scene_validate.hpp"

namespace lagrangian::scene::detail {

// -- the initial state --

void Validator::check_initial_state() const {
  check_in_box();
  check_overlaps();
  check_planes();
  check_links();
  check_surfaces();
  check_gravity_singularity();
}

/// Newtonian gravity between two bodies at the same place is infinite (V = −G m_a m_b / r at r = 0): the
/// scene names the pair and their position keys instead of starting a run whose energy is not finite.
/// Exact coincidence only (a map of the positions, linear in the number of bodies); spheres that overlap
/// are refused by check_overlaps.
void Validator::check_gravity_singularity() const {
  if (!s_.newtonian_gravity || !(s_.newtonian_gravity->G > 0)) return;
  std::map<std::array<double, 3>, std::size_t> at;
  for (std::size_t i = 0; i < s_.bodies.size(); ++i) {
    const Body& b = s_.bodies[i];
    if (!(b.mass > 0)) continue;
    const auto [it, fresh] = at.emplace(std::array<double, 3>{b.position[0], b.position[1], b.position[2]}, i);
    if (fresh) continue;
    const Body& a = s_.bodies[it->second];
    fail(idx("bodies", i) + ".position",
         "bodies " + quote_text(a.name) + " (" + idx("bodies", it->second) + ".position) and " + quote_text(b.name) +
             " are both at " + format_vec(b.position) + " at t0: Newtonian gravity between them, V = -G m1 m2 / r, "
             "is infinite at r = 0; place them apart");
  }
}

void Validator::check_in_box() const {
  if (!s_.box) return;
  const BoxContact& box = *s_.box;
  static const char* axis = "xyz";
  for (std::size_t i = 0; i < s_.bodies.size(); ++i) {
    const Body& b = s_.bodies[i];
    const double scale = std::max({box.min.cwiseAbs().maxCoeff(), box.max.cwiseAbs().maxCoeff(), b.radius});
    const double tol = 1e-12 * scale;
    for (int a = 0; a < 3; ++a) {
      const double lo = b.position[a] - b.radius, hi = b.position[a] + b.radius;
      std::string what;
      if (lo < box.min[a] - tol) {
        what = std::string(1, axis[a]) + " - R = " + format_derived(lo) + " < min " + format_value(box.min[a]);
      } else if (hi > box.max[a] + tol) {
        what = std::string(1, axis[a]) + " + R = " + format_derived(hi) + " > max " + format_value(box.max[a]);
      }
      if (!what.empty())
        fail(idx("bodies", i) + ".position", "body " + quote_text(b.name) + " (radius " + format_value(b.radius) +
                                                 ") at " + format_vec(b.position) + " is outside the box " +
                                                 format_vec(box.min) + " to " + format_vec(box.max) + ": " + what);
    }
  }
}

void Validator::overlap_failure(const BodyRef& a, const BodyRef& b, double d) const {
  const double sum = radius(a) + radius(b);
  fail(position_key(b), "spheres " + quote_text(body_name(a)) + " and " + quote_text(body_name(b)) +
                            " overlap at t0: distance " + format_derived(d) + " < R1 + R2 = " + format_derived(sum));
}

bool Validator::overlapping(double d, double sum) { return d < sum * (1.0 - 1e-12); }

/// Finds a pair of overlapping spheres among `set` in time linear in its
/// size for usual scenes: spheres are sorted into grids by size class
/// (radius in [2^k, 2^(k+1)), cells of 2^(k+2)), and each sphere looks only
/// at the few cells around it in its own class and in every larger one.
/// Point masses overlap nothing but the inside of spheres.
void Validator::check_pairs(const std::vector<BodyRef>& set) const {
  using Key = std::array<std::int64_t, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const noexcept {
      std::uint64_t h = 0x9e3779b97f4a7c15ull;
      for (const auto v : k) h = (h ^ static_cast<std::uint64_t>(v)) * 0xff51afd7ed558ccdull;
      return static_cast<std::size_t>(h ^ (h >> 29));
    }
  };
  struct Level {
    double cell = 0;
    double rmax = 0;
    std::unordered_map<Key, std::vector<std::size_t>, KeyHash> cells;
  };
  // Cell index along one axis; far cells are lumped (2^50 keeps the
  // arithmetic exact, so a neighbourhood is at most 4 cells wide).
  auto cell_of = [](double x, double cell) {
    return static_cast<std::int64_t>(std::clamp(std::floor(x / cell), -0x1p50, 0x1p50));
  };
  std::vector<Vec3> p(set.size());
  std::vector<double> r(set.size());
  for (std::size_t i = 0; i < set.size(); ++i) {
    p[i] = position(set[i]);
    r[i] = radius(set[i]);
  }
  std::map<int, Level> levels;
  for (std::size_t i = 0; i < set.size(); ++i) {
    if (!(r[i] > 0)) continue;
    const int k = std::ilogb(r[i]);
    Level& L = levels[k];
    L.cell = std::ldexp(1.0, k + 2);
    L.rmax = std::max(L.rmax, r[i]);
    L.cells[{cell_of(p[i].x(), L.cell), cell_of(p[i].y(), L.cell), cell_of(p[i].z(), L.cell)}].push_back(i);
  }
  for (std::size_t i = 0; i < set.size(); ++i) {
    const bool point = !(r[i] > 0);
    const int own = point ? 0 : std::ilogb(r[i]);
    for (auto it = point ? levels.begin() : levels.find(own); it != levels.end(); ++it) {
      const Level& L = it->second;
      const bool same = !point && it->first == own;
      const double reach = r[i] + L.rmax;
      Key lo, hi;
      for (int a = 0; a < 3; ++a) {
        lo[static_cast<std::size_t>(a)] = cell_of(p[i][a] - reach, L.cell);
        hi[static_cast<std::size_t>(a)] = cell_of(p[i][a] + reach, L.cell);
      }
      for (std::int64_t cx = lo[0]; cx <= hi[0]; ++cx)
        for (std::int64_t cy = lo[1]; cy <= hi[1]; ++cy)
          for (std::int64_t cz = lo[2]; cz <= hi[2]; ++cz) {
            const auto found = L.cells.find({cx, cy, cz});
            if (found == L.cells.end()) continue;
            for (const std::size_t j : found->second) {
              if (same && j >= i) continue;                   // each pair once, from its later sphere
              if (set[i].gas && set[j].gas) continue;        // lattice sites never overlap
              const double d = (p[i] - p[j]).norm();
              if (overlapping(d, r[i] + r[j])) overlap_failure(set[std::min(i, j)], set[std::max(i, j)], d);
            }
          }
    }
  }
}

void Validator::check_overlaps() const {
  if (!s_.sphere_contacts) return;
  // The spheres that collide with each other.
  std::vector<BodyRef> set;
  bool all_gas = false;
  if (s_.sphere_contacts->bodies.empty()) {
    for (std::size_t i = 0; i < s_.bodies.size(); ++i) set.push_back({false, static_cast<std::int64_t>(i)});
    all_gas = s_.gas.has_value();
  } else {
    std::set<std::pair<bool, std::int64_t>> seen;
    for (const auto& name : s_.sphere_contacts->bodies) {
      const auto r = find(name);
      if (r && seen.insert({r->gas, r->index}).second) set.push_back(*r);
    }
  }
  // Pairs among explicit bodies and listed molecules.
  if (set.size() > 1) check_pairs(set);
  // Every molecule collides: compare each explicit body with the nearest
  // lattice site of each block of filled sites.
  if (all_gas) {
    for (std::size_t i = 0; i < s_.bodies.size(); ++i) {
      const Body& b = s_.bodies[i];
      for (const auto& blk : layout_->blocks()) {
        std::array<std::int64_t, 3> near{};
        for (int a = 0; a < 3; ++a) {
          const double t = std::round((b.position[a] - layout_->first[a]) / layout_->spacing);
          const double c = std::clamp(t, static_cast<double>(blk.lo[a]), static_cast<double>(blk.hi[a] - 1));
          near[a] = static_cast<std::int64_t>(c);
        }
        const Vec3 p = layout_->site(near[0], near[1], near[2]);
        const double d = (p - b.position).norm();
        if (overlapping(d, b.radius + s_.gas->radius))
          fail(idx("bodies", i) + ".position",
               "spheres " + quote_text(b.name) + " and " +
                   quote_text(detail::gas_name(*s_.gas, layout_->index(near[0], near[1], near[2]))) +
                   " (gas) overlap at t0: distance " + format_derived(d) +
                   " < R1 + R2 = " + format_derived(b.radius + s_.gas->radius));
      }
    }
  }
}

void Validator::check_planes() const {
  for (std::size_t k = 0; k < s_.planes.size(); ++k) {
    const PlaneContact& pl = s_.planes[k];
    const Vec3 n = pl.normal.normalized();
    const std::string label = idx("contacts.planes", k) + (pl.name.empty() ? "" : " (" + quote_text(pl.name) + ")");
    auto check = [&](const std::string& key, const std::string& name, const Vec3& r, double R) {
      const double phi = n.dot(r - pl.point) - R;
      const double tol = 1e-12 * std::max({R, r.cwiseAbs().maxCoeff(), pl.point.cwiseAbs().maxCoeff()});
      if (!(phi >= -tol))
        fail(key, "body " + quote_text(name) + " (radius " + format_value(R) + ") at " + format_vec(r) +
                      " is on the wrong side of " + label + " at t0: n.(r - p) - R = " + format_derived(phi) +
                      " < 0");
    };
    if (pl.bodies.empty()) {
      for (std::size_t i = 0; i < s_.bodies.size(); ++i)
        check(idx("bodies", i) + ".position", s_.bodies[i].name, s_.bodies[i].position, s_.bodies[i].radius);
      if (s_.gas) {
        // A linear function is least at a corner of each block of sites.
        for (const auto& blk : layout_->blocks())
          for (int c = 0; c < 8; ++c) {
            const std::int64_t ix = (c & 1) ? blk.hi[0] - 1 : blk.lo[0];
            const std::int64_t iy = (c & 2) ? blk.hi[1] - 1 : blk.lo[1];
            const std::int64_t iz = (c & 4) ? blk.hi[2] - 1 : blk.lo[2];
            check("gas", detail::gas_name(*s_.gas, layout_->index(ix, iy, iz)), layout_->site(ix, iy, iz),
                  s_.gas->radius);
          }
      }
    } else {
      for (const auto& name : pl.bodies) {
        const auto r = find(name);
        if (r) check(position_key(*r), name, position(*r), radius(*r));
      }
    }
  }
}

void Validator::check_links() const {
  for (std::size_t i = 0; i < s_.links.size(); ++i) {
    const Link& l = s_.links[i];
    const std::string key = idx("links", i);
    const BodyRef a = *find(l.a);
    const Vec3 pa = position(a);
    Vec3 pb = l.anchor;
    std::string other = "anchor " + format_vec(l.anchor);
    if (!l.b.empty()) {
      const BodyRef b = *find(l.b);
      pb = position(b);
      other = quote_text(l.b);
    }
    const double d = (pa - pb).norm();
    if (std::isnan(l.length)) {
      if (!(d > 0))
        fail(key, "the initial distance between " + quote_text(l.a) + " and " + other +
                      " is 0; give the link a length or separate its ends");
    } else if (!(std::abs(d - l.length) <= 1e-9 * l.length)) {
      fail(key + ".length", "length " + format_value(l.length) + " disagrees with the initial distance " +
                                format_derived(d) + " between " + quote_text(l.a) + " and " + other +
                                " (more than 1e-9 relative)");
    }
  }
}

void Validator::check_surfaces() const {
  for (std::size_t i = 0; i < s_.surfaces.size(); ++i) {
    const Surface& sf = s_.surfaces[i];
    const std::string key = idx("surfaces", i);
    const BodyRef b = *find(sf.body);
    const Vec3 r = position(b);
    // A gas molecule on a surface must be at rest (checked in check_constraints).
    const Vec3 v = b.gas ? Vec3::Zero() : s_.bodies[static_cast<std::size_t>(b.index)].velocity;
    const std::string who = "body " + quote_text(sf.body);
    Vec3 n;
    if (sf.kind == Surface::Kind::plane) {
      n = sf.normal.normalized();
      const double g = n.dot(r - sf.point);
      const double tol = 1e-9 * std::max(r.cwiseAbs().maxCoeff(), sf.point.cwiseAbs().maxCoeff());
      if (!(std::abs(g) <= tol))
        fail(position_key(b), who + " at " + format_vec(r) + " is not on " + key + " (plane through " +
                                  format_vec(sf.point) + " with normal " + format_vec(sf.normal) +
                                  ") at t0: distance " + format_derived(g) + " (tolerance 1e-9 relative)");
    } else {
      const Vec3 rel = r - sf.point;
      const double d = rel.norm();
      if (!(std::abs(d - sf.radius) <= 1e-9 * sf.radius))
        fail(position_key(b), who + " at " + format_vec(r) + " is not on " + key + " (sphere of radius " +
                                  format_value(sf.radius) + " about " + format_vec(sf.point) +
                                  ") at t0: its distance from the centre is " + format_derived(d) +
                                  " (tolerance 1e-9 relative)");
      n = rel / d;
    }
    const double vn = n.dot(v);
    if (!(std::abs(vn) <= 1e-9 * v.norm()))
      fail(velocity_key(b), who + " has velocity " + format_vec(v) + " not tangent to " + key +
                                " at t0: normal component " + format_derived(vn) + " (tolerance 1e-9 relative)");
  }
}

}  // namespace lagrangian::scene::detail
