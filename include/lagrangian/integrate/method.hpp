#pragma once
/// \file method.hpp
/// The steppers a run can take, and one table of what each is.

#include <iosfwd>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace lagrangian {

/// The steppers `simulate` accepts (SimulationOptions::method). In a scene
/// file or on the command line they go by their names (method_info().name).
enum class Method {
  rk4,             ///< classical Runge–Kutta, fixed step `dt`, order 4
  dopri5,          ///< Dormand–Prince 5(4), adaptive, dense output (the default)
  cash_karp54,     ///< Cash–Karp 5(4), adaptive
  fehlberg78,      ///< Runge–Kutta–Fehlberg 7(8), adaptive
  bulirsch_stoer,  ///< Bulirsch–Stoer extrapolation, adaptive order
  /// Gauss–Radau 15 (Everhart; Rein & Spiegel's IAS15 step control),
  /// adaptive, for q̈ = f(q, q̇, t) (integrate/detail/gauss_radau.hpp)
  gauss_radau15,
  /// linearly implicit Rosenbrock 4(3) for stiff problems; its Jacobian ∂f/∂x
  /// is formed by central finite differences of the AD-derived right-hand side
  rosenbrock4,
  /// variational integrator (variational.hpp), fixed step `dt`, any
  /// Lagrangian, holonomic constraints held by discrete multipliers;
  /// implicit (Newton, AD Jacobian). For models that opt in to the
  /// structure-preserving methods (structure_preserving_v, model.hpp).
  variational,
  /// Odeint's 4th-order symplectic Runge–Kutta–Nyström (McLachlan), fixed
  /// step `dt`; needs a separable model (below)
  symplectic_rkn_sb3a_mclachlan,
  /// Odeint's velocity Verlet, 2nd order, fixed step `dt`. This and the one
  /// above need L = ½ q̇ᵀMq̇ − V(q) with constant M, no constraints and no
  /// forces (detected, or declared by the model with `static constexpr bool
  /// separable = true;`); otherwise simulate() refuses them with an
  /// OptionError saying why.
  velocity_verlet,
};

/// How a method is integrated by the driver (src/integrate/).
enum class MethodFamily {
  explicit_runge_kutta,  ///< Odeint's explicit steppers (rk4, the embedded pairs, Bulirsch–Stoer)
  gauss_radau,           ///< gauss_radau15
  rosenbrock,            ///< rosenbrock4
  symplectic,            ///< Odeint's symplectic steppers
  variational,           ///< the variational integrator
};

/// What a method is: one row of method_table().
struct MethodInfo {
  Method method;
  std::string_view name;  ///< as written in scenes and on the command line
  MethodFamily family;
  /// Order of the solution (Bulirsch–Stoer: 0, it changes its order with the
  /// tolerance).
  int order;
  /// Order p of the embedded error estimate of an adaptive Runge–Kutta pair
  /// (local error ∝ h^(p+1), so steps grow as tol^(−1/(p+1))); 0 for the
  /// other methods.
  int error_order;
  bool adaptive;  ///< steps chosen by an error estimate (false: fixed step `dt`)
  /// Samples between steps come from the method's own interpolant (otherwise
  /// the adaptive methods shorten their steps to land on sample times, and
  /// the fixed-step ones take a sub-step or interpolate; the table in
  /// docs/architecture.md, section 4).
  bool dense_output;
  /// Works on the model's Lagrangian itself, not on q̈ (the model must opt
  /// in to the structure-preserving methods).
  bool needs_lagrangian;
  /// Needs a separable model (see Method::velocity_verlet).
  bool needs_separable;
};

/// Every method, in the order of the enumeration.
std::span<const MethodInfo> method_table();

/// The row of `method`.
const MethodInfo& method_info(Method method);

/// The name of `method` ("dopri5").
std::string_view to_string(Method method);

/// Writes the method's name.
std::ostream& operator<<(std::ostream& os, Method method);

/// The method named `name`, if there is one.
std::optional<Method> find_method(std::string_view name);

/// The method named `name`, or an OptionError "<field>: unknown stepper
/// 'name'; did you mean 'x'? (the steppers are: …)" for the field of the
/// input it came from ("run.method", "--methods").
Method parse_method(std::string_view name, std::string_view field);

/// Names of the steppers `simulate` accepts, in the order of the enumeration.
std::vector<std::string> stepper_names();

/// True for the steppers with a fixed step `dt` (rk4, variational, the
/// symplectic ones).
bool fixed_step_method(Method method);

}  // namespace lagrangian
