// Reading and checking a text model's definition (text/text_model.hpp).
#include <cmath>
#include <set>
#include <sstream>
#include <string>

#include "lagrangian/text/text_model.hpp"

namespace lagrangian::text {

namespace {

/// The coordinates and parameters, their names checked; the parameters' values.
std::vector<double> read_symbols(const Definition& d, Parsed& p) {
  const std::string& pre = d.field_prefix;
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
    p.symbols.coordinates.push_back(q);
  }
  for (const std::string& q : d.coordinates) names.insert(q + "_dot");
  std::vector<double> values;
  for (const auto& [name, value] : d.parameters) {
    check_name(name, pre + "parameters." + name);
    if (!std::isfinite(value)) throw ExpressionError(pre + "parameters." + name, 0, "the value is not finite");
    p.symbols.parameters.push_back(name);
    values.push_back(value);
  }
  if (!d.units.empty() && d.units.size() != d.coordinates.size())
    throw ExpressionError(pre + "units", 0,
                          "one unit per coordinate: " + std::to_string(d.units.size()) + " units for " +
                              std::to_string(d.coordinates.size()) + " coordinates");
  return values;
}

/// T, V, the generalized forces and D, parsed and bound to the parameters.
void read_energies(const Definition& d, Parsed& p, const std::vector<double>& values) {
  const std::string& pre = d.field_prefix;
  if (d.kinetic.empty()) throw ExpressionError(pre + "kinetic", 0, "T is missing");

  p.kinetic = parse(d.kinetic, p.symbols, pre + "kinetic");
  p.potential = parse(d.potential.empty() ? std::string("0") : d.potential, p.symbols, pre + "potential");
  if (p.potential.reads_velocities())
    throw ExpressionError(pre + "potential", 0, "V depends on q and t only; a velocity appears in it");
  p.kinetic_bound = bind_parameters(p.kinetic, values);
  p.potential_bound = bind_parameters(p.potential, values);

  if (!d.forces.empty()) {
    if (d.forces.size() != d.coordinates.size())
      throw ExpressionError(pre + "forces", 0,
                            "one generalized force per coordinate: " + std::to_string(d.forces.size()) +
                                " for " + std::to_string(d.coordinates.size()) + " coordinates");
    for (std::size_t i = 0; i < d.forces.size(); ++i) {
      p.forces.push_back(parse(d.forces[i], p.symbols, pre + "forces[" + std::to_string(i) + "]"));
      p.forces_bound.push_back(bind_parameters(p.forces.back(), values));
    }
    p.has_forces = true;
  }
  p.dissipation = parse(d.dissipation.empty() ? std::string("0") : d.dissipation, p.symbols, pre + "dissipation");
  if (p.dissipation.reads_time())
    throw ExpressionError(pre + "dissipation", 0, "D depends on q and q̇ only; t appears in it");
  p.dissipation_bound = bind_parameters(p.dissipation, values);
  p.has_dissipation = !d.dissipation.empty();
}

/// The holonomic rows g(q, t) = 0 and the Pfaffian rows, affine in q̇.
void read_constraints(const Definition& d, Parsed& p, const std::vector<double>& values) {
  const std::string& pre = d.field_prefix;
  for (std::size_t i = 0; i < d.holonomic.size(); ++i) {
    const std::string field = pre + "holonomic[" + std::to_string(i) + "]";
    p.holonomic.push_back(parse(d.holonomic[i], p.symbols, field));
    if (p.holonomic.back().reads_velocities())
      throw ExpressionError(field, 0,
                            "a holonomic constraint g(q, t) = 0 depends on q and t only; a velocity appears in it "
                            "(a constraint on velocities belongs in pfaffian)");
    p.holonomic_bound.push_back(bind_parameters(p.holonomic.back(), values));
  }
  for (std::size_t i = 0; i < d.pfaffian.size(); ++i) {
    const std::string field = pre + "pfaffian[" + std::to_string(i) + "]";
    const Expression e = parse(d.pfaffian[i], p.symbols, field);
    // Affine in q̇: no ∂φ/∂q̇_k may depend on a velocity.
    for (int k = 0; k < static_cast<int>(d.coordinates.size()); ++k) {
      bool affine = true;
      try {
        affine = !derivative(e, Op::velocity, k).reads_velocities();
      } catch (const ExpressionError&) {
        affine = false;  // min or max of a velocity
      }
      if (!affine)
        throw ExpressionError(field, 0,
                              "a Pfaffian constraint must be linear in the velocities, A(q, t)·q̇ + a(q, t) = 0; "
                              "its derivative by " + d.coordinates[static_cast<std::size_t>(k)] +
                                  "_dot still depends on a velocity");
    }
    p.pfaffian.push_back(e);
    p.pfaffian_bound.push_back(bind_parameters(e, values));
  }
}

/// The contacts' gaps and restitutions; the contacts' names.
std::set<std::string> read_contacts(const Definition& d, Parsed& p, const std::vector<double>& values) {
  const std::string& pre = d.field_prefix;
  std::set<std::string> contact_names;
  for (std::size_t j = 0; j < d.contacts.size(); ++j) {
    const Contact& c = d.contacts[j];
    const std::string key = pre + "contacts[" + std::to_string(j) + "]";
    if (!c.name.empty() && !contact_names.insert(c.name).second)
      throw ExpressionError(key + ".name", 0, "'" + c.name + "' names two contacts");
    if (c.gap.empty()) throw ExpressionError(key + ".gap", 0, "a contact needs its gap, an expression >= 0");
    p.gaps.push_back(parse(c.gap, p.symbols, key + ".gap"));
    if (p.gaps.back().reads_velocities())
      throw ExpressionError(key + ".gap", 0, "a contact's gap depends on q and t only; a velocity appears in it");
    p.gaps_bound.push_back(bind_parameters(p.gaps.back(), values));
    if (!(c.restitution >= 0.0 && c.restitution <= 1.0)) {
      std::ostringstream os;
      if (std::isnan(c.restitution)) {
        os << "a contact needs its restitution e in [0, 1]";
      } else {
        os << "must be in [0, 1], got " << c.restitution;
      }
      throw ExpressionError(key + ".restitution", 0, os.str());
    }
  }
  return contact_names;
}

/// The constraints' names and units: one per row, no name twice or a contact's.
void check_constraint_labels(const Definition& d, const std::set<std::string>& contact_names) {
  const std::string& pre = d.field_prefix;
  const std::size_t rows = d.holonomic.size() + d.pfaffian.size();
  auto check_count = [&](const std::vector<std::string>& v, const char* key, const char* what) {
    if (!v.empty() && v.size() != rows)
      throw ExpressionError(pre + key, 0,
                            std::string("one ") + what + " per constraint (holonomic, then pfaffian): " +
                                std::to_string(v.size()) + " for " + std::to_string(rows) + " constraints");
  };
  check_count(d.constraint_names, "constraint_names", "name");
  check_count(d.constraint_units, "constraint_units", "unit");
  std::set<std::string> constraint_names;
  for (const std::string& name : d.constraint_names)
    if (name.empty() || !constraint_names.insert(name).second || contact_names.count(name))
      throw ExpressionError(pre + "constraint_names", 0,
                            name.empty() ? "a constraint name is empty" : "'" + name + "' names two constraints");
}

/// The points with a mass and their positions r(q, t).
void read_points(const Definition& d, Parsed& p, const std::vector<double>& values) {
  const std::string& pre = d.field_prefix;
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
      const Expression e = parse(axes[a]->empty() ? std::string("0") : *axes[a], p.symbols, field);
      if (e.reads_velocities())
        throw ExpressionError(field, 0, "a point's position depends on q and t only; a velocity appears in it");
      xyz[static_cast<std::size_t>(a)] = bind_parameters(e, values);
    }
    p.points.push_back(std::move(xyz));
  }
}

}  // namespace

std::shared_ptr<const Parsed> read(const Definition& d) {
  auto p = std::make_shared<Parsed>();
  p->definition = d;
  if (d.coordinates.empty()) throw ExpressionError(d.field_prefix + "coordinates", 0, "at least one coordinate is needed");
  const std::vector<double> values = read_symbols(d, *p);
  read_energies(d, *p, values);
  read_constraints(d, *p, values);
  const std::set<std::string> contact_names = read_contacts(d, *p, values);
  check_constraint_labels(d, contact_names);
  read_points(d, *p, values);
  return p;
}

}  // namespace lagrangian::text
