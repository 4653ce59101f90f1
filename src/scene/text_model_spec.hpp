#pragma once
// Internal: a scene's model stated by expressions (TextModelSpec) as the
// text layer's Definition, and the model facts (coordinates, units,
// parameters) of either kind of [model] in one shape.

#include <optional>
#include <string>

#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/models.hpp"
#include "lagrangian/scene/text_model.hpp"
#include "lagrangian/text/definition.hpp"
#include "lagrangian/text/expression.hpp"

namespace lagrangian::scene::detail {

/// What an expression error says after its key in a scene error:
/// "column N: what is wrong", or what is wrong alone.
std::string scene_message(const lagrangian::text::ExpressionError& e);

/// The facts of the model: the catalog entry of a built-in model, those of
/// a text model (named "text", its parameters with their given values as
/// defaults) or of a user's C++ model; nullopt for an unknown built-in name.
std::optional<ModelInfo> model_info(const ModelSpec& m);

}  // namespace lagrangian::scene::detail
