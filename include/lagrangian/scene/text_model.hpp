#pragma once
/// \file scene/text_model.hpp
/// A scene's model stated by expressions (`[model]` with `coordinates` and
/// `kinetic`, docs/scenes.md) as the text layer's Definition, so that a
/// program can build the same model from a scene file:
///
/// \code
/// const lagrangian::scene::Scene s = lagrangian::scene::load_scene("atwood_machine.toml");
/// const lagrangian::text::TextModel model(lagrangian::scene::text_definition(*s.model));
/// \endcode
///
/// Target lagrangian::scene (and lagrangian::text for TextModel).

#include "lagrangian/scene/scene.hpp"
#include "lagrangian/text/definition.hpp"

namespace lagrangian::scene {

/// The definition stated by `m` (m.text set; otherwise SceneError naming
/// model.kinetic), its parameters those of m.parameters, its error messages
/// keyed "model.…".
lagrangian::text::Definition text_definition(const ModelSpec& m);

}  // namespace lagrangian::scene
