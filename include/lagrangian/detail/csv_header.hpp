#pragma once
// Internal: the header fields of the CSV files a run writes. A field is a
// column's name followed by its SI unit in brackets, "t [s]", "x_dot [m/s]",
// or the name alone when the unit is not known or the column has none
// ("kind"). pandas keeps a field whole; readers here look columns up by
// name, with the unit cut off.

#include <string>
#include <string_view>

namespace lagrangian::detail {

/// "name [unit]", or "name" when `unit` is empty.
inline std::string csv_field(std::string_view name, std::string_view unit) {
  std::string out(name);
  if (!unit.empty()) {
    out += " [";
    out += unit;
    out += ']';
  }
  return out;
}

/// Where a field's " [unit]" begins, or its size when it has none.
inline std::size_t csv_unit_start(std::string_view field) {
  if (!field.ends_with(']')) return field.size();
  const std::size_t open = field.rfind(" [");
  return open == std::string_view::npos ? field.size() : open;
}

/// The column's name: the field without its " [unit]".
inline std::string_view csv_field_name(std::string_view field) { return field.substr(0, csv_unit_start(field)); }

/// The column's unit, "" when the field has none.
inline std::string_view csv_field_unit(std::string_view field) {
  const std::size_t at = csv_unit_start(field);
  return at == field.size() ? std::string_view() : field.substr(at + 2, field.size() - at - 3);
}

/// Unit of the rate of a quantity in `unit`: "m" → "m/s"; "" stays "".
inline std::string csv_rate_unit(std::string_view unit) {
  return unit.empty() ? std::string() : std::string(unit) + "/s";
}

/// Unit of the generalized force on a coordinate in `unit` (work per unit
/// of the coordinate): "m" → "N", "rad" → "N*m", "m^2" → "N/m", other u →
/// "J/u"; "" stays "".
inline std::string csv_force_unit(std::string_view unit) {
  if (unit.empty()) return {};
  if (unit == "m") return "N";
  if (unit == "rad") return "N*m";
  if (unit == "m^2") return "N/m";
  return "J/" + std::string(unit);
}

}  // namespace lagrangian::detail
