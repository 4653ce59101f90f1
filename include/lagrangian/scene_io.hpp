#pragma once
/// \file scene_io.hpp
/// Scene files in TOML (every key is documented in docs/scenes.md).

#include <string>
#include <string_view>

#include "lagrangian/scene.hpp"

namespace lagrangian::scene {

/// Parses a scene from TOML text and validates it (Scene::validate()).
/// `file` names the source in error messages. Throws SceneError
/// "<file>:<line>: <key>: <message>" for a TOML syntax error, an unknown key
/// (with the nearest valid key suggested), a missing required key, a value
/// of the wrong type, or any invalid value.
Scene parse_scene(std::string_view text, const std::string& file = "<scene>");

/// Reads and parses a scene file; an unreadable file is a SceneError naming it.
Scene load_scene(const std::string& path);

}  // namespace lagrangian::scene
