// Reading and checking a text model's definition (text/text_model.hpp).
#include <cmath>
#include <set>
#include <string>

#include "lagrangian/text/text_model.hpp"

namespace lagrangian::text {

std::shared_ptr<const Parsed> read(const Definition& d) {
  auto p = std::make_shared<Parsed>();
  p->definition = d;
  const std::string& pre = d.field_prefix;
  if (d.coordinates.empty()) throw ExpressionError(pre + "coordinates", 0, "at least one coordinate is needed");
  std::set<std::string> names;
  auto check_name = [&](const std::string& name, const std::string& field) {
    if (!valid_name(name))
      throw ExpressionError(field, 0,
                            "'" + name +
                                "' cannot name a coordinate or parameter: a letter or '_' first, then letters, "
                                "digits and '_'; not t, pi or a function name");
    if (!names.insert(name).second) throw ExpressionError(field, 0, "'" + name + "' is named twice");
  };
  for (const std::string& q : d.coordinates) {
    check_name(q, pre + "coordinates");
    p->symbols.coordinates.push_back(q);
  }
  for (const std::string& q : d.coordinates) names.insert(q + "_dot");
  std::vector<double> values;
  for (const auto& [name, value] : d.parameters) {
    check_name(name, pre + "parameters." + name);
    if (!std::isfinite(value)) throw ExpressionError(pre + "parameters." + name, 0, "the value is not finite");
    p->symbols.parameters.push_back(name);
    values.push_back(value);
  }
  if (!d.units.empty() && d.units.size() != d.coordinates.size())
    throw ExpressionError(pre + "units", 0,
                          "one unit per coordinate: " + std::to_string(d.units.size()) + " units for " +
                              std::to_string(d.coordinates.size()) + " coordinates");
  if (d.kinetic.empty()) throw ExpressionError(pre + "kinetic", 0, "T is missing");

  p->kinetic = parse(d.kinetic, p->symbols, pre + "kinetic");
  p->potential = parse(d.potential.empty() ? std::string("0") : d.potential, p->symbols, pre + "potential");
  if (p->potential.reads_velocities())
    throw ExpressionError(pre + "potential", 0, "V depends on q and t only; a velocity appears in it");
  p->kinetic_bound = bind_parameters(p->kinetic, values);
  p->potential_bound = bind_parameters(p->potential, values);

  if (!d.forces.empty()) {
    if (d.forces.size() != d.coordinates.size())
      throw ExpressionError(pre + "forces", 0,
                            "one generalized force per coordinate: " + std::to_string(d.forces.size()) +
                                " for " + std::to_string(d.coordinates.size()) + " coordinates");
    for (std::size_t i = 0; i < d.forces.size(); ++i) {
      p->forces.push_back(parse(d.forces[i], p->symbols, pre + "forces[" + std::to_string(i) + "]"));
      p->forces_bound.push_back(bind_parameters(p->forces.back(), values));
    }
    p->has_forces = true;
  }
  p->dissipation = parse(d.dissipation.empty() ? std::string("0") : d.dissipation, p->symbols, pre + "dissipation");
  if (p->dissipation.reads_time())
    throw ExpressionError(pre + "dissipation", 0, "D depends on q and q̇ only; t appears in it");
  p->dissipation_bound = bind_parameters(p->dissipation, values);
  p->has_dissipation = !d.dissipation.empty();

  std::set<std::string> point_names;
  for (std::size_t i = 0; i < d.points.size(); ++i) {
    const Point& pt = d.points[i];
    const std::string key = pre + "points[" + std::to_string(i) + "]";
    if (pt.name.empty()) throw ExpressionError(key + ".name", 0, "a point needs a name");
    if (!point_names.insert(pt.name).second)
      throw ExpressionError(key + ".name", 0, "'" + pt.name + "' names two points");
    if (!(std::isfinite(pt.mass) && pt.mass >= 0))
      throw ExpressionError(key + ".mass", 0, "must be finite and >= 0 (kg)");
    std::array<Expression, 3> xyz;
    const std::string* axes[3] = {&pt.x, &pt.y, &pt.z};
    for (int a = 0; a < 3; ++a) {
      const std::string field = key + "." + "xyz"[a];
      const Expression e = parse(axes[a]->empty() ? std::string("0") : *axes[a], p->symbols, field);
      if (e.reads_velocities())
        throw ExpressionError(field, 0, "a point's position depends on q and t only; a velocity appears in it");
      xyz[static_cast<std::size_t>(a)] = bind_parameters(e, values);
    }
    p->points.push_back(std::move(xyz));
  }
  return p;
}

}  // namespace lagrangian::text
