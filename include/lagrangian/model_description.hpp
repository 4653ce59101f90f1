#pragma once
/// \file model_description.hpp
/// What a built-in model says about itself, written once as constant data:
/// its name, one line of description, its generalized coordinates with their
/// SI units and its parameters with their defaults, SI units and meanings.
///
/// A model states it as a static member,
///
///   struct SimplePendulum {
///     static constexpr ModelDescription description{
///         "simple_pendulum", "Plane pendulum: ...",
///         {{"theta", "rad"}},
///         {{"m", 1.0, "kg", "mass of the bob"}, {"l", 1.0, "m", "length of the rod"}, ...}};
///     explicit SimplePendulum(double mass = description.value("m"), ...);
///     std::string name() const { return std::string(description.name); }
///     auto coordinate_names() const { return description.coordinate_names(); }
///     auto coordinate_units() const { return description.coordinate_units(); }
///   };
///
/// and everything else reads it: the constructor's defaults, name(), the
/// coordinate names and units of every output, and the scene catalog
/// (`lagrangian list`, the parameters a scene may set and their defaults).
/// value() is consteval: a default naming a parameter the description does
/// not list does not compile.

#include <array>
#include <cstddef>
#include <stdexcept>
#include <string_view>

namespace lagrangian {

/// A generalized coordinate: its name in outputs and scenes, and its SI unit
/// ("m", "rad").
struct CoordinateDescription {
  std::string_view name;
  std::string_view unit;
};

/// A parameter: its key under a scene's [model.parameters], its default in
/// SI units, the unit ("kg", "m/s^2") and one line saying what it is.
struct ParameterDescription {
  std::string_view name;
  double value = 0;
  std::string_view unit;
  std::string_view meaning;
};

/// A model's description: N coordinates and P parameters.
template <std::size_t N, std::size_t P>
struct ModelDescription {
  std::string_view name;     ///< registry name, e.g. "double_pendulum"
  std::string_view summary;  ///< one line
  std::array<CoordinateDescription, N> coordinates{};
  std::array<ParameterDescription, P> parameters{};

  constexpr ModelDescription(std::string_view name_, std::string_view summary_,
                             const CoordinateDescription (&coordinates_)[N],
                             const ParameterDescription (&parameters_)[P])
      : name(name_), summary(summary_) {
    for (std::size_t i = 0; i < N; ++i) coordinates[i] = coordinates_[i];
    for (std::size_t i = 0; i < P; ++i) parameters[i] = parameters_[i];
  }

  /// The default of the parameter `parameter` (SI units); a name the
  /// description does not list is a compile error.
  consteval double value(std::string_view parameter) const {
    for (const ParameterDescription& p : parameters)
      if (p.name == parameter) return p.value;
    throw std::logic_error("the model's description lists no such parameter");
  }

  /// The coordinates' names, in order.
  constexpr std::array<std::string_view, N> coordinate_names() const {
    std::array<std::string_view, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = coordinates[i].name;
    return out;
  }

  /// The coordinates' SI units, in order.
  constexpr std::array<std::string_view, N> coordinate_units() const {
    std::array<std::string_view, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = coordinates[i].unit;
    return out;
  }
};

}  // namespace lagrangian
