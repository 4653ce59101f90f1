// Units of scene keys and sweep columns (key_units.hpp), from the keys'
// documented units (docs/scenes.md) and the model catalog.

#include "key_units.hpp"

#include <map>
#include <string_view>

#include "lagrangian/scene/models.hpp"
#include "text_model_spec.hpp"

namespace lagrangian::scene::detail {
namespace {

/// A coordinate's unit: a model's from the catalog, a body's x, y, z in m.
std::string coordinate_unit(const Scene& scene, const std::string& name) {
  if (scene.model) {
    if (const auto info = model_info(*scene.model))
      for (std::size_t i = 0; i < info->coordinates.size() && i < info->units.size(); ++i)
        if (info->coordinates[i] == name) return info->units[i];
    return "";
  }
  return name.ends_with(".x") || name.ends_with(".y") || name.ends_with(".z") ? "m" : "";
}

/// The last name of a key without its indices: "bodies[0].velocity[2]" → "velocity".
std::string last_name(const std::string& key) {
  std::string k = key;
  while (!k.empty() && k.back() == ']') k.erase(k.rfind('['));
  const std::size_t dot = k.rfind('.');
  return dot == std::string::npos ? k : k.substr(dot + 1);
}

}  // namespace

std::string velocity_unit(const std::string& u) { return u.empty() ? "1/s" : u + "/s"; }

std::string momentum_unit(const std::string& u) {
  if (u.empty()) return "";
  if (u == "rad") return "kg*m^2/s";
  return "kg*" + u + "/s";
}

std::string key_unit(const Scene& scene, const std::string& key) {
  if (key.starts_with("model.parameters.")) {
    if (!scene.model) return "";
    const std::string name = key.substr(std::string_view("model.parameters.").size());
    if (const auto info = model_info(*scene.model))
      for (const ParameterInfo& p : info->parameters)
        if (p.name == name) return p.unit == "1" ? "" : p.unit;  // dimensionless: no unit shown
    return "";
  }
  if (key.starts_with("model.q[") || key.starts_with("model.qd[")) {
    const std::optional<ModelInfo> info = scene.model ? model_info(*scene.model) : std::nullopt;
    const std::size_t open = key.find('[');
    const std::size_t i = std::stoul(key.substr(open + 1));
    if (!info || i >= info->units.size()) return "";
    return key.starts_with("model.qd[") ? velocity_unit(info->units[i]) : info->units[i];
  }
  static const std::map<std::string, std::string> units = {
      {"t0", "s"}, {"t_end", "s"}, {"dt", "s"}, {"output_interval", "s"}, {"baumgarte_omega", "1/s"},
      {"mass", "kg"}, {"radius", "m"}, {"rest_length", "m"}, {"length", "m"}, {"position", "m"},
      {"anchor", "m"}, {"point", "m"}, {"min", "m"}, {"max", "m"}, {"velocity", "m/s"}, {"speed", "m/s"},
      {"g", "m/s^2"}, {"G", "m^3/(kg s^2)"}, {"stiffness", "N/m"}};
  const std::string name = last_name(key);
  if (name == "coefficient") {
    if (key.starts_with("linear_drag")) return "kg/s";
    if (key.starts_with("quadratic_drag")) return "kg/m";
    return "";
  }
  const auto it = units.find(name);
  return it == units.end() ? "" : it->second;
}

std::string column_unit(const Scene& scene, const std::string& column) {
  if (column == "t_final" || column == "wall_time_s") return "s";
  if (column == "impact_energy_loss") return "J";
  if (column == "lyapunov_max") return "1/s";
  if (column.starts_with("qd_")) {
    const std::string u = coordinate_unit(scene, column.substr(3));
    return u.empty() && !scene.model ? "" : velocity_unit(u);
  }
  if (column.starts_with("q_")) return coordinate_unit(scene, column.substr(2));
  if (column.starts_with("first_") || column.starts_with("last_") || column.starts_with("t_")) return "s";
  if (column.find('.') != std::string::npos || column.find('[') != std::string::npos) return key_unit(scene, column);
  return "";
}

}  // namespace lagrangian::scene::detail
