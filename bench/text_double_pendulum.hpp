#pragma once
// The double pendulum of models::DoublePendulum stated as text, for the
// benchmarks that set a text model beside the compiled one.
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/text/definition.hpp"

namespace bench {

/// T and V of models::DoublePendulum as the text of a scene's [model]
/// (coordinates th1, th2), with p's parameters.
inline lagrangian::text::Definition double_pendulum_text(
    const lagrangian::models::DoublePendulum& p = lagrangian::models::DoublePendulum()) {
  lagrangian::text::Definition d;
  d.coordinates = {"th1", "th2"};
  d.kinetic = "0.5*(m1 + m2)*l1^2*th1_dot^2 + 0.5*m2*l2^2*th2_dot^2 + m2*l1*l2*th1_dot*th2_dot*cos(th1 - th2)";
  d.potential = "-(m1 + m2)*g*l1*cos(th1) - m2*g*l2*cos(th2)";
  d.parameters = {{"m1", p.m1}, {"m2", p.m2}, {"l1", p.l1}, {"l2", p.l2}, {"g", p.g}};
  return d;
}

}  // namespace bench
