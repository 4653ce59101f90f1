#pragma once
// Built-in models restated as text definitions, shared by the text tests.

#include <string>

#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/text/definition.hpp"

namespace lagrangian::testing {

/// The double pendulum `p` (models::DoublePendulum) as a text definition.
inline text::Definition double_pendulum_text(const models::DoublePendulum& p) {
  text::Definition d;
  d.name = "double pendulum as text";
  d.coordinates = {"th1", "th2"};
  d.units = {"rad", "rad"};
  // T of the two bobs, v₁ = l₁θ̇₁, v₂ = v₁ + l₂θ̇₂ at an angle θ₁ − θ₂.
  d.kinetic = "0.5*(m1 + m2)*l1^2*th1_dot^2 + 0.5*m2*l2^2*th2_dot^2 + m2*l1*l2*th1_dot*th2_dot*cos(th1 - th2)";
  d.potential = "-(m1 + m2)*g*l1*cos(th1) - m2*g*l2*cos(th2)";
  d.parameters = {{"m1", p.m1}, {"m2", p.m2}, {"l1", p.l1}, {"l2", p.l2}, {"g", p.g}};
  return d;
}

/// models::PendulumChain<n> (unit masses and lengths) as text, coordinates
/// q0 … q(n−1): bob k moves at (Σ_{j≤k} cos q_j q̇_j, Σ_{j≤k} sin q_j q̇_j)
/// and hangs at −Σ_{j≤k} cos q_j; T = ½ m Σ_k |v_k|², V = m g Σ_k y_k.
inline text::Definition pendulum_chain_text(int n) {
  text::Definition d;
  std::string vx, vy, y;
  for (int k = 0; k < n; ++k) {
    const std::string q = "q" + std::to_string(k);
    d.coordinates.push_back(q);
    vx += (k ? " + " : "") + std::string("cos(") + q + ")*" + q + "_dot";
    vy += (k ? " + " : "") + std::string("sin(") + q + ")*" + q + "_dot";
    y += " - cos(" + q + ")";
    d.kinetic += (k ? " + " : "") + std::string("0.5*m*((") + vx + ")^2 + (" + vy + ")^2)";
    d.potential += (k ? " + " : "") + std::string("m*g*(") + y + ")";
  }
  d.parameters = {{"m", 1.0}, {"g", 9.81}};
  return d;
}

}  // namespace lagrangian::testing
