// TOML documents: parsing scene text, reading scene files, and describing a
// value for messages (toml_document.hpp).

#include "toml_document.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>

#include "lagrangian/scene/scene.hpp"
#include "scene_messages.hpp"
#include "text.hpp"

namespace lagrangian::scene::detail {

namespace {
std::string quoted_string(std::string_view s) { return text::quoted(s, '"'); }
}  // namespace

std::string toml_type_name(const toml::node& n) {
  std::ostringstream os;
  os << n.type();
  return os.str();
}

std::string describe_value(const toml::node& n, int depth) {
  switch (n.type()) {
    case toml::node_type::string: return "string " + quoted_string(n.as_string()->get());
    case toml::node_type::integer: return "integer " + std::to_string(n.as_integer()->get());
    case toml::node_type::floating_point: return "float " + format_value(n.as_floating_point()->get());
    case toml::node_type::boolean: return std::string("boolean ") + (n.as_boolean()->get() ? "true" : "false");
    case toml::node_type::table: return "a table";
    case toml::node_type::array: {
      const toml::array& a = *n.as_array();
      std::string out = depth == 0 ? "an array of " + std::to_string(a.size()) + " [" : "[";
      for (std::size_t i = 0; i < a.size(); ++i) {
        if (i == 4 || depth > 0) {
          out += "...";
          break;
        }
        out += (i ? ", " : "");
        const toml::node& e = *a.get(i);
        if (e.is_integer()) {
          out += std::to_string(e.as_integer()->get());
        } else if (e.is_floating_point()) {
          out += format_value(e.as_floating_point()->get());
        } else if (e.is_string()) {
          out += quoted_string(e.as_string()->get());
        } else if (e.is_array()) {
          out += describe_value(e, depth + 1);
        } else {
          out += "<" + toml_type_name(e) + ">";
        }
      }
      return out + "]";
    }
    default: {
      std::ostringstream os;
      if (const auto* d = n.as_date()) os << *d;
      if (const auto* t = n.as_time()) os << *t;
      if (const auto* dt = n.as_date_time()) os << *dt;
      return toml_type_name(n) + " " + os.str();
    }
  }
}

toml::table parse_document(std::string_view text, const std::string& file) {
  try {
    return toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    SourceMap where;
    where.file = file;
    const auto line = e.source().begin.line;
    if (line <= static_cast<toml::source_index>(std::numeric_limits<int>::max()))
      where.lines[""] = static_cast<int>(line);
    std::string what = "TOML syntax error: " + std::string(e.description());
    if (e.source().begin.column > 0) what += " (column " + std::to_string(e.source().begin.column) + ")";
    throw SceneError("", what, where);
  }
}

std::string read_scene_text(const std::string& path) {
  SourceMap where;
  where.file = path == "-" ? "<stdin>" : path;
  std::ostringstream text;
  if (path == "-") {
    text << std::cin.rdbuf();
    if (std::cin.bad()) throw SceneError("", "cannot read the scene from standard input: read error", where);
    return text.str();
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw SceneError("", "cannot read the scene file: it is a directory", where);
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw SceneError("", std::string("cannot read the scene file: ") + (err ? std::strerror(err) : "open failed"),
                     where);
  }
  text << in.rdbuf();
  if (in.bad()) throw SceneError("", "cannot read the scene file: read error", where);
  return text.str();
}

}  // namespace lagrangian::scene::detail
