#pragma once
/// \file params.hpp
/// Validation of model parameters. Each check throws ParameterError with a
/// message of the form
///   "<Model>: parameter '<name>' must be <condition>, got <value>".

#include <cmath>
#include <string>
#include <string_view>

#include "lagrangian/errors.hpp"

namespace lagrangian {

namespace detail {
std::string format_number(double v);
/// v as the shortest text that reads back as the same double ("1e-09", "0.1",
/// "inf", "nan").
std::string format_shortest(double v);
[[noreturn]] void parameter_failure(std::string_view model, std::string_view name, std::string_view condition,
                                    double value);
}  // namespace detail

/// Throws unless `value` is finite.
inline double require_finite(std::string_view model, std::string_view name, double value) {
  if (!std::isfinite(value)) detail::parameter_failure(model, name, "finite", value);
  return value;
}

/// Throws unless `value` is finite and > 0 (masses, lengths, stiffnesses).
inline double require_positive(std::string_view model, std::string_view name, double value) {
  if (!std::isfinite(value) || !(value > 0.0)) detail::parameter_failure(model, name, "positive and finite", value);
  return value;
}

/// Throws unless `value` is finite and ≥ 0 (gravity, damping coefficients).
inline double require_nonnegative(std::string_view model, std::string_view name, double value) {
  if (!std::isfinite(value) || !(value >= 0.0))
    detail::parameter_failure(model, name, "non-negative and finite", value);
  return value;
}

/// Throws unless lo ≤ value ≤ hi.
inline double require_in_range(std::string_view model, std::string_view name, double value, double lo, double hi) {
  if (!std::isfinite(value) || value < lo || value > hi)
    detail::parameter_failure(model, name, "in [" + detail::format_number(lo) + ", " + detail::format_number(hi) + "]",
                              value);
  return value;
}

}  // namespace lagrangian
