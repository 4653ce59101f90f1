#pragma once
/// \file constraint_names.hpp
/// Names and multiplier units of a model's constraints.

#include <string>
#include <vector>

#include "lagrangian/detail/csv_header.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/constraint_counts.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

namespace detail {
/// Appends one kind's names (the model's own, checked for count, or
/// prefix0, prefix1, …).
template <class Names>
void append_constraint_names(std::vector<std::string>& out, const Names* given, int count, const char* prefix,
                             const char* accessor, const char* kind) {
  if (given) {
    const std::size_t before = out.size();
    for (const auto& s : *given) out.emplace_back(s);
    if (out.size() - before != static_cast<std::size_t>(count))
      throw ConstraintError(std::string(accessor) + "() gives " + std::to_string(out.size() - before) +
                            " names for " + std::to_string(count) + " " + kind + " constraints");
  } else {
    for (int i = 0; i < count; ++i) out.push_back(prefix + std::to_string(i));
  }
}
}  // namespace detail

/// Names of the constraints, holonomic, unilateral, then Pfaffian: the
/// model's own, or g0, g1, …, u0, …, a0, ….
template <class M>
std::vector<std::string> constraint_names(const M& model) {
  std::vector<std::string> names;
  if constexpr (holonomic_count_v<M> != 0) {
    if constexpr (requires { model.holonomic_names(); }) {
      const auto given = model.holonomic_names();
      detail::append_constraint_names(names, &given, holonomic_count(model), "g", "holonomic_names", "holonomic");
    } else {
      detail::append_constraint_names<std::vector<std::string>>(names, nullptr, holonomic_count(model), "g", "", "");
    }
  }
  if constexpr (unilateral_count_v<M> != 0) {
    if constexpr (requires { model.unilateral_names(); }) {
      const auto given = model.unilateral_names();
      detail::append_constraint_names(names, &given, unilateral_count(model), "u", "unilateral_names", "unilateral");
    } else {
      detail::append_constraint_names<std::vector<std::string>>(names, nullptr, unilateral_count(model), "u", "", "");
    }
  }
  if constexpr (pfaffian_count_v<M> != 0) {
    if constexpr (requires { model.pfaffian_names(); }) {
      const auto given = model.pfaffian_names();
      detail::append_constraint_names(names, &given, pfaffian_count(model), "a", "pfaffian_names", "Pfaffian");
    } else {
      detail::append_constraint_names<std::vector<std::string>>(names, nullptr, pfaffian_count(model), "a", "", "");
    }
  }
  return names;
}

/// True when the model gives the units of its constraint functions.
template <class M>
inline constexpr bool has_constraint_units_v = requires(const M& m) {
  { m.constraint_units() };
};

/// SI unit of each constraint's multiplier λ, in constraint_names() order:
/// λ ∂g/∂q is a generalized force, so λ is work per unit of the constraint
/// function, from the model's optional `constraint_units()` (the unit of
/// each g, gap or Pfaffian row A δq): "m" gives "N", "rad" "N*m", "m^2"
/// "N/m". "" for each when the model gives none. Throws ConstraintError
/// when it gives a different number of units than constraints.
template <class M>
std::vector<std::string> multiplier_units(const M& model) {
  const std::size_t count = constraint_names(model).size();
  std::vector<std::string> units;
  if constexpr (has_constraint_units_v<M>) {
    for (const auto& u : model.constraint_units()) units.push_back(detail::csv_force_unit(u));
    if (units.size() != count)
      throw ConstraintError("constraint_units() gives " + std::to_string(units.size()) + " units for " +
                            std::to_string(count) + " constraints");
  } else {
    units.resize(count);
  }
  return units;
}

}  // namespace lagrangian
