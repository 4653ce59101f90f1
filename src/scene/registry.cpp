// The registry of built-in models (run and inspect entry points), and the
// helpers the registry translation units share that need no model.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "lagrangian/detail/text_output.hpp"
#include "registry_common.hpp"

namespace lagrangian::scene::detail {

const std::vector<ModelEntry>& model_entries() {
  static const std::vector<ModelEntry> entries = [] {
    std::vector<ModelEntry> all;
    add_pendulum_models(all);
    add_constrained_models(all);
    add_impact_models(all);
    add_orbit_models(all);
    std::sort(all.begin(), all.end(), [](const ModelEntry& a, const ModelEntry& b) { return a.name < b.name; });
    return all;
  }();
  return entries;
}

const ModelEntry* find_entry(const std::string& name) {
  const auto& all = model_entries();
  const auto it = std::lower_bound(all.begin(), all.end(), name,
                                   [](const ModelEntry& e, const std::string& n) { return e.name < n; });
  return it != all.end() && it->name == name ? &*it : nullptr;
}

const ModelEntry* entry_for(const ModelSpec& spec) {
  if (spec.user) return &user_entry();
  return spec.text ? &text_entry() : find_entry(spec.name);
}

const ModelInfo& catalog_entry(std::string_view name) {
  const ModelInfo* info = find_model(std::string(name));
  if (!info) throw std::logic_error("built-in model '" + std::string(name) + "' is registered but not in the catalog");
  return *info;
}

namespace {

std::string parameter_names(const ModelInfo& info) {
  std::string out;
  for (std::size_t i = 0; i < info.parameters.size(); ++i) out += (i ? ", " : "") + info.parameters[i].name;
  return out;
}

bool has_parameter(const ModelInfo& info, std::string_view name) {
  return std::any_of(info.parameters.begin(), info.parameters.end(),
                     [&](const ParameterInfo& p) { return p.name == name; });
}

std::string join(const std::vector<std::string>& v) {
  std::string out;
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + v[i];
  return out;
}

}  // namespace

Parameters::Parameters(const ModelInfo& info, const ModelSpec& spec) : info_(&info) {
  for (const auto& [key, value] : spec.parameters) {
    if (!has_parameter(info, key)) {
      std::vector<std::string> names;
      for (const auto& p : info.parameters) names.push_back(p.name);
      const std::string hint = nearest(key, names);
      throw SceneError("model.parameters." + key, "model '" + info.name + "' has no parameter '" + key + "'" +
                                                       (hint.empty() ? "" : "; did you mean '" + hint + "'?") +
                                                       " (its parameters: " + parameter_names(info) + ")");
    }
    if (!std::isfinite(value))
      throw SceneError("model.parameters." + key, "must be finite, got " + lagrangian::detail::format_number(value));
  }
  for (const auto& p : info.parameters) {
    const auto it = spec.parameters.find(p.name);
    given_.push_back(it != spec.parameters.end());
    values_.push_back(it != spec.parameters.end() ? it->second : p.default_value);
  }
}

double Parameters::operator[](std::string_view name) const {
  for (std::size_t i = 0; i < info_->parameters.size(); ++i)
    if (info_->parameters[i].name == name) return values_[i];
  throw std::logic_error("built-in model '" + info_->name + "' has no catalog parameter '" + std::string(name) + "'");
}

void throw_parameter_error(const ModelInfo& info, const std::string& what, ParameterAlias alias) {
  // The models' messages read "<Model>: parameter '<name>' must be <condition>, got <value>".
  constexpr std::string_view marker = "parameter '";
  std::string name;
  std::string message = what;
  if (const auto at = what.find(marker); at != std::string::npos) {
    const auto start = at + marker.size();
    if (const auto end = what.find('\'', start); end != std::string::npos) {
      name = what.substr(start, end - start);
      message = what.substr(std::min(what.size(), end + 2));  // "must be …, got …"
    }
  }
  std::string key;
  if (!name.empty() && has_parameter(info, name)) {
    key = name;
  } else if (alias && has_parameter(info, alias(name))) {
    key = std::string(alias(name));
  } else if (!name.empty()) {
    const std::string_view stem = parameter_stem(name);
    if (has_parameter(info, stem)) key = std::string(stem);
  }
  if (key.empty()) throw SceneError("model.parameters", what);
  throw SceneError("model.parameters." + key, message);
}

void check_state_sizes(const ModelInfo& info, const ModelSpec& spec) {
  const std::size_t n = info.coordinates.size();
  auto check = [&](const std::vector<double>& v, const std::string& key) {
    if (v.empty()) return;
    if (v.size() != n)
      throw SceneError(key, "has " + std::to_string(v.size()) + (v.size() == 1 ? " value" : " values") +
                                "; model '" + info.name + "' has " + std::to_string(n) +
                                (n == 1 ? " coordinate" : " coordinates") + " (" + join(info.coordinates) + ")");
    for (std::size_t i = 0; i < n; ++i)
      if (!std::isfinite(v[i]))
        throw SceneError(key, "value " + std::to_string(i) + " (" + info.coordinates[i] + ") is " +
                                  lagrangian::detail::format_number(v[i]) + "; it must be finite");
  };
  check(spec.q, "model.q");
  check(spec.qd, "model.qd");
}

std::string number(double v) {
  if (v == 0.0) v = 0.0;  // no "-0"
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.12g", v);
  return buf;
}

std::string numbers(const double* v, int n) {
  std::string out = "[";
  for (int i = 0; i < n; ++i) out += (i ? ", " : "") + number(v[i]);
  return out + "]";
}

std::string columns(const std::vector<std::vector<std::string>>& rows, const std::string& indent) {
  std::vector<std::size_t> width;
  for (const auto& row : rows) {
    if (width.size() < row.size()) width.resize(row.size(), 0);
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  }
  std::string out;
  for (const auto& row : rows) {
    std::size_t last = row.size();
    while (last > 0 && row[last - 1].empty()) --last;
    std::string line = indent;
    for (std::size_t c = 0; c < last; ++c) {
      line += row[c];
      if (c + 1 < last) line += std::string(width[c] - row[c].size() + 2, ' ');
    }
    out += line + "\n";
  }
  return out;
}

void inspect_header_json(JsonObject& js, const ModelInfo& info, std::string_view type, const Parameters& p) {
  js.string("model", info.name);
  js.string("description", info.description);
  js.string("type", std::string("lagrangian::") + std::string(type));
  std::vector<std::string> params;
  for (std::size_t i = 0; i < info.parameters.size(); ++i) {
    const ParameterInfo& q = info.parameters[i];
    JsonObject pj;
    pj.string("name", q.name);
    pj.number("value", p.value(i));
    pj.string("unit", q.unit == "1" ? "" : q.unit);
    pj.string("description", q.description);
    pj.boolean("from_scene", p.given(i));
    params.push_back(pj.str());
  }
  js.raw("parameters", json_array(params));
}

std::string inspect_header(const ModelInfo& info, std::string_view type, const Parameters& p) {
  std::string out = info.name + ": " + info.description + "\n";
  std::string coords;
  for (std::size_t i = 0; i < info.coordinates.size(); ++i)
    coords += (i ? ", " : "") + info.coordinates[i] + " (" + info.units[i] + ")";
  out += columns({{"model", std::string("lagrangian::") + std::string(type)}, {"coordinates", coords}});
  out += "\nParameters\n";
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < info.parameters.size(); ++i) {
    const ParameterInfo& q = info.parameters[i];
    rows.push_back({q.name, "=", number(p.value(i)), q.unit == "1" ? "" : q.unit, q.description,
                    p.given(i) ? "(from the scene)" : "(default)"});
  }
  out += columns(rows);
  return out;
}

}  // namespace lagrangian::scene::detail
