#pragma once
// Internal: a scene parameter that sets several of a built-in model's
// parameters at once, and its sensitivity column.

#include <string>
#include <string_view>
#include <vector>

#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/scene/models.hpp"

namespace lagrangian::scene::detail {

/// Parameter columns asked for by the scene's names, computed by the
/// model's (src/scene/shared_parameter_columns.cpp). A scene parameter the
/// model does not have stands for every model parameter named it with a
/// body number (newtons_cradle's m for SpheresOnLine<5>'s m1 … m5), and its
/// column is the sum of theirs: ∂x/∂m = Σ_i ∂x/∂m_i, all m_i set by the one
/// value.
struct SharedParameterColumns {
  std::vector<std::string> scene;        ///< the names asked for
  std::vector<std::string> model;        ///< the model's parameters to compute
  std::vector<std::vector<int>> sum_of;  ///< per scene name, its columns among `model`
  /// True when every scene name is a model parameter of its own.
  bool one_to_one() const { return model == scene; }
};
/// A model parameter's name without its body number ("m" of "m12"): the
/// scene parameter it belongs to when the scene sets one value for every
/// body (also how a model's error about "m3" is keyed "m").
std::string_view parameter_stem(std::string_view name);
/// OptionError for a name the scene does not list or one listed twice;
/// std::logic_error for a scene parameter that is none of the model's (a
/// registry bug, caught by the tests).
SharedParameterColumns shared_parameter_columns(const std::vector<std::string>& wanted, const ModelInfo& info,
                                                const std::vector<std::string>& model_parameters);
/// The result of the model's columns with each scene parameter's summed
/// into one column under the scene's name.
SensitivityResult fold_shared_columns(SensitivityResult model_columns, const SharedParameterColumns& columns);

}  // namespace lagrangian::scene::detail
