#pragma once
/// \file scene/models.hpp
/// The built-in generalized-coordinate models a scene can name.

#include <string>
#include <vector>

namespace lagrangian::scene {

/// A parameter of a built-in model.
struct ParameterInfo {
  std::string name;         ///< key under [model.parameters]
  double default_value = 0; ///< SI units
  std::string unit;         ///< "kg", "m", "m/s^2", …
  std::string description;  ///< one line
};

/// A built-in model: what `lagrangian list` prints and what a scene's
/// [model] table may name.
struct ModelInfo {
  std::string name;                        ///< registry name, e.g. "double_pendulum"
  std::string description;                 ///< one line
  std::vector<std::string> coordinates;    ///< generalized coordinates, in order
  std::vector<std::string> units;          ///< unit of each coordinate ("m", "rad")
  std::vector<ParameterInfo> parameters;   ///< every parameter with its default
};

/// Every built-in model, sorted by name.
const std::vector<ModelInfo>& builtin_models();

/// The model named `name`, or nullptr.
const ModelInfo* find_model(const std::string& name);

}  // namespace lagrangian::scene
