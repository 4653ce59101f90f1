#pragma once
/// \file projectile.hpp
/// A projectile over flat ground or an inclined plane (course notes 1.5),
/// with optional linear or quadratic air drag. SI units.
///
/// A particle of mass m, coordinates (x, y) (m), y up, gravity g:
///   T = ½ m (ẋ² + ẏ²),  V = m g y,
/// launched from the origin with speed u at elevation α above the
/// horizontal, over a plane through the origin at signed angle β to the
/// horizontal (β > 0 rises in +x: "up the slope"; β < 0 falls: "down the
/// slope"; β = 0: flat ground). Watched events: "apex" (ẏ falls through 0,
/// recorded) and "landing" (y − x tan β falls through 0, stops the run).
///
/// Drag, only when declared (Drag::linear or Drag::quadratic), as a
/// Rayleigh dissipation function:
///   linear     D = ½ b |v|²     (force −b v, b in kg/s),
///   quadratic  D = ⅓ c |v|³     (force −c |v| v, c in kg/m).

#include <array>
#include <cmath>
#include <string>

#include "lagrangian/mechanics/impact.hpp"
#include "lagrangian/analysis/detail/compiled_tangent_flow.hpp"
#include "lagrangian/integrate/detail/compiled_models.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/model_description.hpp"
#include "lagrangian/models/detail/particles.hpp"
#include "lagrangian/params.hpp"

namespace lagrangian::models {

/// Air drag on a projectile.
enum class Drag { none, linear, quadratic };

namespace detail {
/// The description of Projectile<D>: a scene's `projectile`,
/// `projectile_linear_drag` or `projectile_quadratic_drag`. The drag models'
/// coefficients default to a positive value (with b = 0 the linear-drag
/// closed form divides 0 by 0); `projectile` is the model without drag.
template <Drag D>
consteval auto projectile_description() {
  if constexpr (D == Drag::none) {
    return ModelDescription{
          "projectile",
          "Projectile over a plane through the launch point at angle beta, no drag; stops at landing",
          {{"x", "m"}, {"y", "m"}},
          {{"m", 1.0, "kg", "mass"},
           {"g", 9.81, "m/s^2", "acceleration of gravity"},
           {"beta", 0.0, "rad", "angle of the ground plane to the horizontal, |beta| < pi/2"}}};
  } else if constexpr (D == Drag::linear) {
    return ModelDescription{
          "projectile_linear_drag",
          "Projectile with linear air drag F = -b v; stops at landing",
          {{"x", "m"}, {"y", "m"}},
          {{"m", 1.0, "kg", "mass"},
           {"g", 9.81, "m/s^2", "acceleration of gravity"},
           {"beta", 0.0, "rad", "angle of the ground plane to the horizontal, |beta| < pi/2"},
           {"b", 0.1, "kg/s", "linear drag coefficient, > 0"}}};
  } else {
    return ModelDescription{
          "projectile_quadratic_drag",
          "Projectile with quadratic air drag F = -c |v| v; stops at landing",
          {{"x", "m"}, {"y", "m"}},
          {{"m", 1.0, "kg", "mass"},
           {"g", 9.81, "m/s^2", "acceleration of gravity"},
           {"beta", 0.0, "rad", "angle of the ground plane to the horizontal, |beta| < pi/2"},
           {"c", 0.01, "kg/m", "quadratic drag coefficient, > 0"}}};
  }
}
}  // namespace detail

template <Drag D = Drag::none, class P = double>
struct Projectile : detail::PlanarParticle<P> {
  using detail::PlanarParticle<P>::m;
  using detail::PlanarParticle<P>::g;
  static constexpr int coordinate_count = 2;
  static constexpr double kHalfPi = 1.5707963267948966;
  static constexpr auto description = detail::projectile_description<D>();
  /// The drag coefficient's default: b (kg/s) or c (kg/m), 0 without drag.
  static constexpr double default_drag = [] {
    if constexpr (D == Drag::none) {
      return 0.0;
    } else {
      return description.value(D == Drag::linear ? "b" : "c");
    }
  }();
  P beta, drag;
  /// The model with parameters of type Q (parameter sensitivities,
  /// analysis/sensitivity.hpp), and its parameters in the description's
  /// order (the drag coefficient last; none without drag).
  template <class Q>
  using with_parameter_type = Projectile<D, Q>;
  static constexpr auto parameter_members() {
    // m and g named through their base: clang rejects &Projectile::m for a
    // member brought in by a using-declaration here.
    using Base = detail::PlanarParticle<P>;
    if constexpr (D == Drag::none) {
      return std::array<P Projectile::*, 3>{&Base::m, &Base::g, &Projectile::beta};
    } else {
      return std::array<P Projectile::*, 4>{&Base::m, &Base::g, &Projectile::beta, &Projectile::drag};
    }
  }
  /// m (kg), g (m/s²), plane angle β (rad, |β| < π/2), drag coefficient (b
  /// in kg/s or c in kg/m; must be 0 for Drag::none).
  explicit Projectile(double mass = description.value("m"), double gravity = description.value("g"),
                      double plane_angle = description.value("beta"), double drag_coefficient = default_drag)
      : detail::PlanarParticle<P>{require_positive("Projectile", "m", mass),
                                  require_positive("Projectile", "g", gravity)},
        beta(plane_angle),
        drag(require_nonnegative("Projectile", "drag", drag_coefficient)) {
    if (!(std::abs(plane_angle) < kHalfPi))
      lagrangian::detail::parameter_failure("Projectile", "beta", "in (-pi/2, pi/2) rad", plane_angle);
    if (D == Drag::none && drag_coefficient != 0)
      lagrangian::detail::parameter_failure("Projectile", "drag", "0 when no drag is declared (Drag::none)",
                                            drag_coefficient);
  }
  std::string name() const { return std::string(description.name); }
  template <class S>
    requires(D != Drag::none)
  S dissipation(const Vec<S, 2>&, const Vec<S, 2>& qd) const {
    using std::pow;
    const S v2 = qd[0] * qd[0] + qd[1] * qd[1];
    if constexpr (D == Drag::linear) {
      return 0.5 * drag * v2;
    } else {
      // (v²)^{3/2}, not v²·√v²: its derivative 3/2 √v² · 2v stays finite
      // (zero) at rest, where √'s derivative is infinite.
      return drag / 3.0 * pow(v2, 1.5);
    }
  }
  template <class S>
  Vec<S, 2> events(const Vec<S, 2>& q, const Vec<S, 2>& qd, const S&) const {
    return Vec<S, 2>(qd[1], q[1] - q[0] * std::tan(beta));
  }
  std::array<EventSpec, 2> event_specs() const {
    return {EventSpec{"apex", Direction::falling, EventAction::record},
            EventSpec{"landing", Direction::falling, EventAction::stop}};
  }

  /// Initial state for a launch from the origin with speed u (m/s) at
  /// elevation α (rad). Throws ParameterError unless u > 0 and β < α ≤ π/2
  /// (α = π/2: straight up), so that it flies.
  State<2> launch(double u, double alpha) const {
    require_positive("Projectile", "u", u);
    require_finite("Projectile", "alpha", alpha);
    if (!(alpha > beta && alpha <= kHalfPi))
      lagrangian::detail::parameter_failure("Projectile", "alpha",
                                            "above the plane (alpha > beta = " + lagrangian::detail::format_number(beta) +
                                                ") and at most pi/2, or the projectile does not fly",
                                            alpha);
    State<2> s;
    s.q << 0.0, 0.0;
    s.qd << u * std::cos(alpha), u * std::sin(alpha);
    return s;
  }
  /// Without drag: time of flight to the plane,
  ///   T = 2u sin(α − β) / (g cos β)                       (notes 1.5.1; β = 0: 2u sin α / g).
  double flight_time(double u, double alpha) const { return 2 * u * std::sin(alpha - beta) / (g * std::cos(beta)); }
  /// Without drag: range along the plane,
  ///   R = 2u² sin(α − β) cos α / (g cos² β)              (notes 1.5.2; β = 0: u² sin 2α / g).
  double range(double u, double alpha) const {
    return 2 * u * u * std::sin(alpha - beta) * std::cos(alpha) / (g * std::cos(beta) * std::cos(beta));
  }
  /// Without drag: greatest height above the launch point, H = u² sin²α / (2g).
  double max_height(double u, double alpha) const {
    const double s = std::sin(alpha);
    return u * u * s * s / (2 * g);
  }
  /// Without drag: the elevation of greatest range along the plane,
  /// α* = π/4 + β/2, and that range u² / (g (1 + sin β)).
  double best_elevation() const { return 0.7853981633974483 + 0.5 * beta; }
  double max_range(double u) const { return u * u / (g * (1 + std::sin(beta))); }
  /// With linear drag (k = b/m): the position at time t of the launch (u, α),
  ///   x = (u cos α / k)(1 − e^{−kt}),  y = ((u sin α + g/k)/k)(1 − e^{−kt}) − g t / k.
  std::array<double, 2> linear_drag_position(double u, double alpha, double t) const
    requires(D == Drag::linear)
  {
    const double k = drag / m, f = -std::expm1(-k * t);
    return {u * std::cos(alpha) / k * f, (u * std::sin(alpha) + g / k) / k * f - g * t / k};
  }
  /// The motion in closed form from `initial` (no drag, or linear drag):
  ///   no drag:  x = x0 + ẋ0 t,  y = y0 + ẏ0 t − g t²/2;
  ///   linear:   x = x0 + ẋ0 (1 − e^{−kt})/k,  y = y0 + (ẏ0 + g/k)(1 − e^{−kt})/k − g t/k.
  State<2> reference(const State<2>& initial, double t) const
    requires(D != Drag::quadratic)
  {
    State<2> s;
    if constexpr (D == Drag::none) {
      s.q << initial.q[0] + initial.qd[0] * t, initial.q[1] + initial.qd[1] * t - 0.5 * g * t * t;
      s.qd << initial.qd[0], initial.qd[1] - g * t;
    } else {
      const double k = drag / m, f = -std::expm1(-k * t), decay = std::exp(-k * t);
      s.q << initial.q[0] + initial.qd[0] * f / k, initial.q[1] + (initial.qd[1] + g / k) * f / k - g * t / k;
      s.qd << initial.qd[0] * decay, (initial.qd[1] + g / k) * decay - g / k;
    }
    return s;
  }
  /// A default scene: launched at 20 m/s, 45° above the horizontal (or
  /// halfway between the plane and the vertical when the plane is steeper).
  State<2> default_state() const { return launch(20.0, std::max(0.7853981633974483, 0.5 * (beta + kHalfPi))); }
  /// With quadratic drag: the terminal speed of a vertical fall, √(m g / c) (m/s).
  double terminal_speed() const
    requires(D == Drag::quadratic)
  {
    return std::sqrt(m * g / drag);
  }
};

}  // namespace lagrangian::models

// simulate() and the tangent flow (Lyapunov, Floquet, sensitivities) for
// these models are compiled once, in the library (src/models/); see
// lagrangian/integrate/detail/compiled_models.hpp and
// lagrangian/analysis/detail/compiled_tangent_flow.hpp.
#define LAGRANGIAN_PROJECTILE_MODELS(X) \
  X(lagrangian::models::Projectile<lagrangian::models::Drag::none>) \
  X(lagrangian::models::Projectile<lagrangian::models::Drag::linear>) \
  X(lagrangian::models::Projectile<lagrangian::models::Drag::quadratic>)
LAGRANGIAN_PROJECTILE_MODELS(LAGRANGIAN_BUILT_IN_MODEL)
LAGRANGIAN_PROJECTILE_MODELS(LAGRANGIAN_EXTERN_TANGENT_FLOW)
