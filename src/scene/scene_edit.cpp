// Changing a scene document: scene keys parsed into paths and numbers written
// at them (scene_edit.hpp), and a scene read with its numeric keys overridden
// (scene/io.hpp, `lagrangian run --set`).

#include "scene_edit.hpp"

#include <charconv>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>

#include "lagrangian/errors.hpp"
#include "lagrangian/scene/io.hpp"
#include "scene_messages.hpp"
#include "toml_document.hpp"

namespace lagrangian::scene::detail {

std::vector<PathPart> parse_path(const std::string& option, const std::string& key) {
  std::vector<PathPart> parts;
  std::size_t i = 0;
  auto bad = [&](const std::string& why) {
    throw OptionError(option + " " + key + ": not a scene key: " + why +
                      " (write keys as in the scene file, e.g. model.parameters.e or bodies[0].velocity[2])");
  };
  while (i < key.size()) {
    if (key[i] == '[') {
      const std::size_t close = key.find(']', i);
      if (close == std::string::npos) bad("'[' without ']'");
      std::size_t v = 0;
      const auto r = std::from_chars(key.data() + i + 1, key.data() + close, v);
      if (r.ec != std::errc() || r.ptr != key.data() + close) bad("the index in '[]' must be an integer >= 0");
      if (parts.empty()) bad("it starts with an index");
      parts.emplace_back(v);
      i = close + 1;
      if (i < key.size() && key[i] == '.') {
        ++i;
        if (i == key.size()) bad("it ends with '.'");
      }
    } else {
      std::size_t end = key.find_first_of(".[", i);
      if (end == std::string::npos) end = key.size();
      if (end == i) bad("an empty name");
      parts.emplace_back(key.substr(i, end - i));
      i = end;
      if (i < key.size() && key[i] == '.') {
        ++i;
        if (i == key.size()) bad("it ends with '.'");
      }
    }
  }
  return parts;
}

namespace {

std::string type_of(const toml::node& n) {
  std::ostringstream os;
  os << n.type();
  return os.str();
}

/// A built-in model takes a parameter the scene does not write (its
/// default then); a model stated as text has only the parameters its
/// [model.parameters] declares, so a new one is a misspelt name: `fail`.
template <class Fail>
void refuse_new_text_parameter(const toml::table& root, const toml::table& parameters, const std::string& name,
                               Fail&& fail) {
  const toml::table* model = root["model"].as_table();
  if (!model || !model->contains("kinetic")) return;
  std::vector<std::string> names;
  for (const auto& [key, value] : parameters) names.emplace_back(key.str());
  fail("the model stated as text has no parameter '" + name + "'" + unknown_hint(name, names) +
       "; its parameters are those its [model.parameters] declares");
}

}  // namespace

void assign(toml::table& root, const std::string& option, const std::string& key, const std::vector<PathPart>& path,
            double value) {
  toml::node* cur = &root;
  std::string where;
  auto fail = [&](const std::string& why) { throw OptionError(option + " " + key + ": " + why); };
  auto numeric = [&](const toml::node* old, auto&& put) {
    if (old && !old->is_number())
      fail("the scene has " + where + " = " + type_of(*old) + ", not a number; only numbers can be varied");
    // Integral values go in as TOML integers where the file has an integer or
    // nothing (the reader takes an integer for a float key, not the reverse).
    if ((!old || old->is_integer()) && std::nearbyint(value) == value && std::abs(value) < 9.2e18)
      put(toml::value<std::int64_t>(static_cast<std::int64_t>(value)));
    else
      put(toml::value<double>(value));
  };
  for (std::size_t k = 0; k < path.size(); ++k) {
    const bool last = k + 1 == path.size();
    if (const auto* name = std::get_if<std::string>(&path[k])) {
      where += (where.empty() ? "" : ".") + *name;
      toml::table* t = cur->as_table();
      if (!t) fail("the scene has " + where.substr(0, where.rfind('.')) + " as " + type_of(*cur) + ", not a table");
      toml::node* child = t->get(*name);
      if (last) {
        if (!child && where == "model.parameters." + *name) refuse_new_text_parameter(root, *t, *name, fail);
        numeric(child, [&](auto&& v) { t->insert_or_assign(*name, std::move(v)); });
        return;
      }
      if (!child) {
        if (std::holds_alternative<std::size_t>(path[k + 1]))
          fail("the scene file does not write " + where + "; write it in the scene to vary one of its elements");
        child = &t->insert_or_assign(*name, toml::table{}).first->second;
      }
      cur = child;
    } else {
      const std::size_t i = std::get<std::size_t>(path[k]);
      toml::array* a = cur->as_array();
      if (!a) fail("the scene has " + where + " as " + type_of(*cur) + ", not an array");
      if (i >= a->size())
        fail("index " + std::to_string(i) + " is out of range: the scene's " + where + " has " +
             std::to_string(a->size()) + " element" + (a->size() == 1 ? "" : "s"));
      where += "[" + std::to_string(i) + "]";
      toml::node* child = a->get(i);
      if (last) {
        numeric(child, [&](auto&& v) { a->replace(a->cbegin() + static_cast<std::ptrdiff_t>(i), std::move(v)); });
        return;
      }
      cur = child;
    }
  }
}

}  // namespace lagrangian::scene::detail

namespace lagrangian::scene {

KeySetting parse_key_setting(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw OptionError("--set: '" + text + "' is not KEY=VALUE (e.g. model.parameters.e=0.5)");
  KeySetting s{text.substr(0, eq), 0};
  const std::string v = text.substr(eq + 1);
  const char* end = v.data() + v.size();
  const auto r = std::from_chars(v.data(), end, s.value);
  if (v.empty() || r.ec != std::errc() || r.ptr != end || !std::isfinite(s.value))
    throw OptionError("--set " + s.key + ": '" + v + "' is not a finite number");
  detail::parse_path("--set", s.key);  // a key's shape is checked here, its name when the scene is read
  return s;
}

Scene load_scene(const std::string& path, const std::vector<KeySetting>& settings) {
  const std::string file = path == "-" ? "<stdin>" : path;
  toml::table doc = detail::parse_document(detail::read_scene_text(path), file);
  std::map<std::string, std::string> overrides;
  for (const KeySetting& s : settings) {
    detail::assign(doc, "--set", s.key, detail::parse_path("--set", s.key), s.value);
    overrides[s.key] = "--set";
  }
  return detail::scene_from_document(doc, file, overrides);
}

}  // namespace lagrangian::scene
