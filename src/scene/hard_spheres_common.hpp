#pragma once
// Internal: what the hard-sphere engine (hard_spheres_engine.cpp) and its
// validation (hard_spheres_validate.cpp) share: names, the cell grid, and the
// event encoding that bounds the number of spheres.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "lagrangian/scene/hard_spheres.hpp"

namespace lagrangian::detail::hard_spheres {

constexpr const char* kAxis[3] = {"x", "y", "z"};

std::string num(double v);

std::string vec(const Eigen::Vector3d& v);

std::string sphere_name(const HardSphereSystem& s, std::size_t i);

std::string wall_name(const HardSphereSystem& s, std::size_t k);

// A uniform grid over the box whose cells are at least `reach` wide on every
// axis, so that spheres closer than `reach` are in the same or adjacent cells.
// The number of cells is capped at ~8 per sphere (wider cells stay correct).
// Its small members stay inline here: index() and locate() run in the
// engine's inner loops (cell lists, neighbour scans), where a call out of
// line would cost speed.
struct Grid {
  Eigen::Vector3d lo = Eigen::Vector3d::Zero();
  Eigen::Vector3d width = Eigen::Vector3d::Ones();
  std::array<int, 3> n{1, 1, 1};

  std::size_t cells() const { return static_cast<std::size_t>(n[0]) * n[1] * n[2]; }
  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * n[1] + y) * n[0] + x;
  }
  std::size_t index(const std::array<int, 3>& c) const { return index(c[0], c[1], c[2]); }
  std::array<int, 3> locate(const Eigen::Vector3d& r) const {
    std::array<int, 3> c{};
    for (int d = 0; d < 3; ++d) {
      const double f = std::floor((r[d] - lo[d]) / width[d]);
      c[d] = static_cast<int>(std::clamp(f, 0.0, static_cast<double>(n[d] - 1)));
    }
    return c;
  }
};

Grid make_grid(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double reach, std::size_t count, bool single);

double largest_radius(const HardSphereSystem& s);

// ---------------------------------------------------------------------------
// The engine's events. Their 30 index bits bound the number of spheres and
// walls; kind() and b() stay inline, as they are read for every event.

enum Kind : std::uint32_t { kPair = 0, kWall = 1, kCross = 2 };

// A predicted event, 24 bytes. The top two bits of `code` are the kind, the
// rest the partner b: for pairs the other sphere (a < b), for walls the wall
// (0–5 the box faces 2·axis + side, 6 + k the extra walls), for crossings
// 2·axis + (1 if moving up). ca, cb: the spheres' impact counts (mod 2³²)
// when predicted; the queue is purged at least every 2³⁰ events, so a stale
// entry never meets a wrapped-around count.
struct Event {
  double t;
  std::uint32_t a, code, ca, cb;
  Kind kind() const { return static_cast<Kind>(code >> 30); }
  std::uint32_t b() const { return code & kIndexMask; }
  static constexpr std::uint32_t kIndexMask = (1u << 30) - 1;
};
constexpr std::size_t kMaxSpheres = Event::kIndexMask;

}  // namespace lagrangian::detail::hard_spheres
