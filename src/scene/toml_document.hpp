#pragma once
// Internal: a scene from an already parsed TOML document, so that a sweep can
// change values in the document and read it with the same keys, checks and
// messages as a scene file (toml_scene.cpp).

#include <string>

#include <toml++/toml.h>

#include "lagrangian/scene.hpp"

namespace lagrangian::scene::detail {

/// Reads `root` into a Scene and validates it, exactly as parse_scene() does
/// after parsing; `file` names the source in error messages.
Scene scene_from_document(const toml::table& root, const std::string& file);

}  // namespace lagrangian::scene::detail
