// Scene diagnostics: value formatting and "did you mean" hints for error
// messages, SourceMap line lookup, SceneError and nearest().

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "lagrangian/detail/nearest_name.hpp"
#include "lagrangian/scene/scene.hpp"
#include "scene_messages.hpp"

#include "lagrangian/params.hpp"

namespace lagrangian::scene {

// -- formatting helpers ---------------------------------------------------------

namespace detail {

std::string quote_text(std::string_view s, char quote) { return text::quoted(s, quote); }

std::string format_value(double v) { return lagrangian::detail::format_shortest(v); }

/// A computed quantity (a distance, a sum): 15 significant digits, so that
/// rounding noise such as 0.21000000000000002 reads 0.21.
std::string format_derived(double v) {
  if (!std::isfinite(v)) return format_value(v);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.15g", v);
  return buf;
}

std::string format_vec(const Vec3& v) {
  return "[" + format_value(v.x()) + ", " + format_value(v.y()) + ", " + format_value(v.z()) + "]";
}



std::string unknown_hint(const std::string& word, const std::vector<std::string>& candidates) {
  const std::string near = nearest(word, candidates);
  if (!near.empty()) return "; did you mean '" + near + "'?";
  if (candidates.empty()) return "";
  return "; expected one of: " + join(candidates);
}

}  // namespace detail

// -- SourceMap, SceneError, nearest -----------------------------------------------

int SourceMap::line_of(const std::string& key) const {
  std::string k = key;
  for (;;) {
    if (const auto it = lines.find(k); it != lines.end() && it->second > 0) return it->second;
    if (k.empty()) return 0;
    // Parent: drop a trailing "[i]" or ".name".
    std::size_t cut = std::string::npos;
    if (k.back() == ']') {
      cut = k.rfind('[');
    } else {
      cut = k.rfind('.');
    }
    if (cut == std::string::npos || cut == 0) return 0;
    k.resize(cut);
  }
}

namespace {

std::string scene_message(const std::string& key, const std::string& what, const SourceMap& source, int line) {
  if (const auto it = source.overrides.find(key); it != source.overrides.end())
    return "command line: " + it->second + " sets " + key + ": " + what;
  std::string where;
  if (source.file.empty()) {
    where = "scene: ";
  } else if (line > 0) {
    where = source.file + ":" + std::to_string(line) + ": ";
  } else {
    where = source.file + ": ";
  }
  return where + (key.empty() ? "" : key + ": ") + what;
}

}  // namespace

SceneError::SceneError(const std::string& key, const std::string& what, const SourceMap& source)
    : OptionError(scene_message(key, what, source, source.line_of(key))),
      key_(key),
      message_(what),
      line_(source.overrides.count(key) ? 0 : source.line_of(key)) {}

std::string nearest(const std::string& word, const std::vector<std::string>& candidates) {
  return lagrangian::detail::nearest_name(word, candidates, std::max<std::size_t>(2, word.size() / 3));
}

}  // namespace lagrangian::scene
