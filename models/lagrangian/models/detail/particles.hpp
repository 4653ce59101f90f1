#pragma once
// Point-mass building blocks shared by the built-in models.

#include <array>
#include <string>
#include <vector>

#include "lagrangian/model.hpp"

namespace lagrangian::models::detail {

/// A particle of mass m in a vertical plane, coordinates (x, y), gravity g
/// along −y: T = ½ m (ẋ² + ẏ²), V = m g y; P is the parameters' type.
template <class P = double>
struct PlanarParticle {
  /// T = ½ m|v|²: M constant (model.hpp, constant_mass_matrix_v).
  static constexpr bool constant_mass_matrix = true;
  P m, g;
  std::array<std::string, 2> coordinate_names() const { return {"x", "y"}; }
  std::array<std::string, 2> coordinate_units() const { return {"m", "m"}; }
  std::array<Particle, 1> particles() const { return {Particle{m, {0, 1, -1}}}; }
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    return m * g * q[1];
  }
};

/// Two free particles m₁, m₂ in D = 2 or 3 dimensions, coordinates
/// (x₁, y₁[, z₁], x₂, y₂[, z₂]): T = ½ m₁|ṙ₁|² + ½ m₂|ṙ₂|²; P is the
/// masses' type.
template <int D, class P = double>
struct ParticlePair {
  static_assert(D == 2 || D == 3, "a particle pair is planar (D = 2) or spatial (D = 3)");
  /// T = ½ m|v|²: M constant (model.hpp, constant_mass_matrix_v).
  static constexpr bool constant_mass_matrix = true;
  P m1, m2;
  std::vector<std::string> coordinate_names() const {
    const char* axes[] = {"x", "y", "z"};
    std::vector<std::string> out;
    for (int b = 1; b <= 2; ++b)
      for (int k = 0; k < D; ++k) out.push_back(std::string(axes[k]) + std::to_string(b));
    return out;
  }
  std::vector<std::string> coordinate_units() const { return std::vector<std::string>(2 * D, "m"); }
  std::array<Particle, 2> particles() const {
    return {Particle{m1, {0, 1, D == 3 ? 2 : -1}}, Particle{m2, {D, D + 1, D == 3 ? D + 2 : -1}}};
  }
  template <class S>
  S kinetic(const Vec<S, 2 * D>&, const Vec<S, 2 * D>& qd, const S&) const {
    S a = S(0), b = S(0);
    for (int k = 0; k < D; ++k) {
      a += qd[k] * qd[k];
      b += qd[D + k] * qd[D + k];
    }
    return 0.5 * m1 * a + 0.5 * m2 * b;
  }
};

}  // namespace lagrangian::models::detail
