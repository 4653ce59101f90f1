#pragma once
// Internal: the lattice on which a [gas] is laid out in its box, and the
// names of its molecules (definitions in scene_gas_fill.cpp).

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "lagrangian/scene/scene.hpp"

namespace lagrangian::scene::detail {

constexpr std::int64_t kMaxGasCount = GasFill::max_count;

/// Where the molecules of a gas sit: a cubic lattice of n[0] × n[1] × n[2]
/// sites with spacing `spacing`, site (0, 0, 0) at `first`, filled x fastest,
/// then y, then z, with the first `count` sites.
struct GasLayout {
  double spacing = 0;
  std::array<std::int64_t, 3> n{};
  Vec3 first = Vec3::Zero();
  std::int64_t count = 0;
  /// A box of site indices [lo, hi) per axis.
  struct Block {
    std::array<std::int64_t, 3> lo, hi;
  };
  Vec3 site(std::int64_t k) const;
  Vec3 site(std::int64_t ix, std::int64_t iy, std::int64_t iz) const;
  std::int64_t index(std::int64_t ix, std::int64_t iy, std::int64_t iz) const;
  /// The filled sites as at most three blocks.
  std::vector<Block> blocks() const;
};

double gas_capacity(const GasFill& gas, const BoxContact& box);
std::optional<GasLayout> gas_layout(const GasFill& gas, const BoxContact& box);
std::string gas_name(const GasFill& gas, std::int64_t k);
std::int64_t gas_index(const GasFill& gas, const std::string& name);

}  // namespace lagrangian::scene::detail
