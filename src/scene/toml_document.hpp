#pragma once
// Internal: a scene from an already parsed TOML document, so that a sweep can
// change values in the document and read it with the same keys, checks and
// messages as a scene file (toml_scene.cpp), and the document-level parts
// (toml_document.cpp).

#include <map>
#include <string>
#include <string_view>

#include <toml++/toml.h>

#include "lagrangian/scene/scene.hpp"

namespace lagrangian::scene::detail {

/// Reads `root` into a Scene and validates it, exactly as parse_scene() does
/// after parsing; `file` names the source in error messages, `overrides`
/// (key → option) the keys the command line set (SourceMap::overrides).
Scene scene_from_document(const toml::table& root, const std::string& file,
                          const std::map<std::string, std::string>& overrides = {});

/// Parses TOML text; a syntax error is a SceneError at its line.
toml::table parse_document(std::string_view text, const std::string& file);

/// The text of a scene file, or of standard input for "-"; SceneError when it
/// cannot be read.
std::string read_scene_text(const std::string& path);

/// The TOML type of a value ("string", "integer", ...).
std::string toml_type_name(const toml::node& n);

/// A short description of a TOML value for messages: its type and value
/// ("float 2.5", "an array of 3 [1, 2, 3]"); arrays inside arrays shortened.
std::string describe_value(const toml::node& n, int depth = 0);

}  // namespace lagrangian::scene::detail
