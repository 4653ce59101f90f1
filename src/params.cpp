#include "lagrangian/params.hpp"

#include <cstdio>

namespace lagrangian::detail {

std::string format_number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
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
