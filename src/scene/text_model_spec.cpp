// A scene's model stated by expressions, as the text layer reads it.
#include "text_model_spec.hpp"

#include "lagrangian/scene/detail/model_run.hpp"

namespace lagrangian::scene {

lagrangian::text::Definition text_definition(const ModelSpec& m) {
  if (!m.text) throw SceneError("model.kinetic", "the model is not stated by expressions (no kinetic energy given)");
  lagrangian::text::Definition d;
  d.name = "text";
  d.coordinates = m.text->coordinates;
  d.units = m.text->units;
  d.kinetic = m.text->kinetic;
  d.potential = m.text->potential;
  d.forces = m.text->forces;
  d.dissipation = m.text->dissipation;
  d.holonomic = m.text->holonomic;
  d.pfaffian = m.text->pfaffian;
  d.constraint_names = m.text->constraint_names;
  d.constraint_units = m.text->constraint_units;
  d.contacts = m.text->contacts;
  for (const auto& [name, value] : m.parameters) d.parameters.emplace_back(name, value);
  for (const TextModelSpec::Point& pt : m.text->points) d.points.push_back({pt.name, pt.mass, pt.x, pt.y, pt.z});
  d.rods = m.text->rods;
  d.field_prefix = "model.";
  return d;
}

namespace detail {

std::string scene_message(const lagrangian::text::ExpressionError& e) {
  return e.column() > 0 ? "column " + std::to_string(e.column()) + ": " + e.message() : e.message();
}

std::optional<ModelInfo> model_info(const ModelSpec& m) {
  if (m.user) return m.user->info();
  if (!m.text) {
    if (const ModelInfo* info = find_model(m.name)) return *info;
    return std::nullopt;
  }
  ModelInfo info;
  info.name = "text";
  info.description = "a model stated in the scene by its kinetic and potential energy";
  info.coordinates = m.text->coordinates;
  info.units = m.text->units.empty() ? std::vector<std::string>(m.text->coordinates.size()) : m.text->units;
  for (const auto& [name, value] : m.parameters) info.parameters.push_back({name, value, "", ""});
  return info;
}

}  // namespace detail
}  // namespace lagrangian::scene
