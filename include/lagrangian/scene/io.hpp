#pragma once
/// \file scene/io.hpp
/// Scene files in TOML (every key is documented in docs/scenes.md).

#include <string>
#include <string_view>
#include <vector>

#include "lagrangian/scene/scene.hpp"

namespace lagrangian::scene {

/// Parses a scene from TOML text and validates it (Scene::validate()).
/// `file` names the source in error messages. Throws SceneError
/// "<file>:<line>: <key>: <message>" for a TOML syntax error, an unknown key
/// (with the nearest valid key suggested), a missing required key, a value
/// of the wrong type, or any invalid value.
Scene parse_scene(std::string_view text, const std::string& file = "<scene>");

/// Reads and parses a scene file ("-": standard input, named "<stdin>" in
/// messages); an unreadable file is a SceneError naming it.
Scene load_scene(const std::string& path);

/// A numeric scene key set from the command line (`run --set KEY=VALUE`).
struct KeySetting {
  std::string key;  ///< as written in the file: "model.parameters.e", "bodies[0].velocity[2]", "run.rtol"
  double value = 0;
};

/// Parses "KEY=VALUE" (VALUE a number); OptionError "--set: …" naming the
/// text otherwise.
KeySetting parse_key_setting(const std::string& text);

/// Reads a scene file ("-": standard input) with numeric keys set: each value
/// is written at its key in the file's document, then the scene is read and
/// checked as if the file said so (a key the file does not have is added,
/// unknown keys are refused as in the file). Errors in a set value name the
/// option: "command line: --set sets KEY: …".
Scene load_scene(const std::string& path, const std::vector<KeySetting>& settings);

}  // namespace lagrangian::scene
