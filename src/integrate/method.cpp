// The table of steppers (method.hpp).

#include "lagrangian/integrate/method.hpp"

#include <algorithm>
#include <array>
#include <ostream>

#include "lagrangian/detail/nearest_name.hpp"
#include "lagrangian/errors.hpp"

namespace lagrangian {
namespace {

using F = MethodFamily;
// name, family, order, error order, adaptive, dense output, needs L, needs separable
constexpr std::array<MethodInfo, 10> kMethods{{
    {Method::rk4, "rk4", F::explicit_runge_kutta, 4, 0, false, false, false, false},
    {Method::dopri5, "dopri5", F::explicit_runge_kutta, 5, 4, true, true, false, false},
    {Method::cash_karp54, "cash_karp54", F::explicit_runge_kutta, 5, 4, true, false, false, false},
    {Method::fehlberg78, "fehlberg78", F::explicit_runge_kutta, 8, 7, true, false, false, false},
    {Method::bulirsch_stoer, "bulirsch_stoer", F::explicit_runge_kutta, 0, 0, true, false, false, false},
    {Method::gauss_radau15, "gauss_radau15", F::gauss_radau, 15, 0, true, true, false, false},
    {Method::rosenbrock4, "rosenbrock4", F::rosenbrock, 4, 0, true, false, false, false},
    {Method::variational, "variational", F::variational, 2, 0, false, false, true, false},
    {Method::symplectic_rkn_sb3a_mclachlan, "symplectic_rkn_sb3a_mclachlan", F::symplectic, 4, 0, false, false, false,
     true},
    {Method::velocity_verlet, "velocity_verlet", F::symplectic, 2, 0, false, false, false, true},
}};

constexpr bool rows_in_enum_order() {
  for (std::size_t i = 0; i < kMethods.size(); ++i)
    if (static_cast<std::size_t>(kMethods[i].method) != i) return false;
  return true;
}
static_assert(rows_in_enum_order(), "method_table(): one row per Method, in the enumeration's order");

}  // namespace

std::span<const MethodInfo> method_table() { return kMethods; }

const MethodInfo& method_info(Method method) {
  const auto i = static_cast<std::size_t>(method);
  if (i >= kMethods.size()) throw OptionError("not a method: " + std::to_string(i));
  return kMethods[i];
}

std::string_view to_string(Method method) { return method_info(method).name; }

std::ostream& operator<<(std::ostream& os, Method method) { return os << to_string(method); }

std::optional<Method> find_method(std::string_view name) {
  for (const MethodInfo& m : kMethods)
    if (m.name == name) return m.method;
  return std::nullopt;
}

Method parse_method(std::string_view name, std::string_view field) {
  if (const auto m = find_method(name)) return *m;
  const std::vector<std::string> names = stepper_names();
  const std::string near =
      detail::nearest_name(std::string(name), names, std::max<std::size_t>(2, name.size() / 3));
  std::string list;
  for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
  throw OptionError(std::string(field) + ": unknown stepper '" + std::string(name) + "'" +
                    (near.empty() ? std::string() : "; did you mean '" + near + "'?") + " (the steppers are: " + list +
                    ")");
}

std::vector<std::string> stepper_names() {
  std::vector<std::string> names;
  for (const MethodInfo& m : kMethods) names.emplace_back(m.name);
  return names;
}

bool fixed_step_method(Method method) { return !method_info(method).adaptive; }

}  // namespace lagrangian
