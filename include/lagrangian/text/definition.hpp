#pragma once
/// \file text/definition.hpp
/// What a model stated as text consists of (read by text::read(),
/// text/text_model.hpp).

#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace lagrangian::text {

/// A point of the system placed by expressions of q and t (m): what the
/// animation page draws, and with a mass, what `inspect` sums into the
/// centre of mass and the momenta P and L.
struct Point {
  std::string name;
  double mass = 0;  ///< kg; 0: a point drawn, not weighed
  std::string x, y, z;  ///< coordinates (m); empty: 0
};

/// A contact: a unilateral constraint gap(q, t) ≥ 0 whose impacts follow
/// Newton's law of restitution with coefficient e; a contact that stops
/// bouncing (Zeno) or is pressed shut rests, and lifts off when its force
/// would pull.
struct Contact {
  std::string name;  ///< empty: u0, u1, …
  std::string gap;   ///< φ(q, t) ≥ 0 (m for a distance)
  double restitution = std::numeric_limits<double>::quiet_NaN();  ///< e in [0, 1] (required)
  std::string unit;  ///< the gap's unit ("m": the contact force in N); empty: none given
};

/// A system as text. Every expression may use the coordinates, their
/// velocities `<coordinate>_dot`, t and the parameters (D: not t).
struct Definition {
  std::string name = "text model";       ///< for reports
  std::vector<std::string> coordinates;  ///< names of q_i (at least one)
  std::vector<std::string> units;        ///< SI unit of each q_i ("m", "rad"); empty: none given
  std::string kinetic;                   ///< T(q, q̇, t) (J)
  std::string potential;                 ///< V(q, t) (J); empty: 0
  std::vector<std::string> forces;       ///< Q_i(q, q̇, t), one per coordinate (N or N·m); empty: none
  std::string dissipation;               ///< Rayleigh D(q, q̇) (W), Q −= ∂D/∂q̇; empty: none
  /// Holonomic constraints g_i(q, t) = 0 (named g0, g1, …); their
  /// multipliers λ_i are the forces along +∇g_i (N when g_i is a length).
  std::vector<std::string> holonomic;
  /// Pfaffian constraints φ_i = A_i(q, t)·q̇ + a_i(q, t) = 0, each affine in
  /// the velocities (named a0, a1, …).
  std::vector<std::string> pfaffian;
  std::vector<Contact> contacts;  ///< unilateral constraints with impacts
  /// A name for each constraint, holonomic then Pfaffian; empty: g0, g1, …, a0, ….
  std::vector<std::string> constraint_names;
  /// The unit of each constraint function, in the same order ("m" makes
  /// its multiplier a force in N, "rad" a torque in N·m); empty: none given.
  std::vector<std::string> constraint_units;
  std::vector<std::pair<std::string, double>> parameters;  ///< named constants (SI units)
  std::vector<Point> points;  ///< points to draw (none: nothing is drawn in space)
  /// Draw rods from the origin to the first point and between consecutive
  /// points (a chain hanging from a pivot at the origin).
  bool rods = false;
  /// Prefix of the field names in error messages ("model." in scenes).
  std::string field_prefix;
};

}  // namespace lagrangian::text
