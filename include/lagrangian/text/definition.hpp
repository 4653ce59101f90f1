#pragma once
/// \file text/definition.hpp
/// What a model stated as text consists of (read by text::read(),
/// text/text_model.hpp).

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
  std::vector<std::pair<std::string, double>> parameters;  ///< named constants (SI units)
  std::vector<Point> points;  ///< points to draw (none: nothing is drawn in space)
  /// Draw rods from the origin to the first point and between consecutive
  /// points (a chain hanging from a pivot at the origin).
  bool rods = false;
  /// Prefix of the field names in error messages ("model." in scenes).
  std::string field_prefix;
};

}  // namespace lagrangian::text
