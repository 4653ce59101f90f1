#include "lagrangian/params.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace lagrangian::detail {

std::string format_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string format_shortest(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

void parameter_failure(std::string_view model, std::string_view name, std::string_view condition, double value) {
  std::string msg(model);
  msg += ": parameter '";
  msg += name;
  msg += "' must be ";
  msg += condition;
  msg += ", got ";
  msg += format_number(value);
  throw ParameterError(msg);
}

}  // namespace lagrangian::detail
