#pragma once
/// \file impacts.hpp
/// Smooth spheres that collide: on a line (direct impact, Newton's cradle),
/// in a plane or in space (oblique impact), a ball against a fixed plane or
/// wall, and spheres in a box. Each model states its contacts as gap
/// functions φ ≥ 0 (m) with restitution coefficients, so impacts are resolved
/// by the general law (impact.hpp); the closed forms of the course notes
/// (corrected, see below) are here too, so tests and tools can show the
/// deviation. SI units throughout.

#include <array>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/ad.hpp"
#include "lagrangian/analysis/detail/compiled_tangent_flow.hpp"
#include "lagrangian/integrate/detail/compiled_models.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/model_description.hpp"
#include "lagrangian/models/detail/parameter_arrays.hpp"
#include "lagrangian/models/detail/particles.hpp"
#include "lagrangian/params.hpp"

namespace lagrangian::models {

/// Result of a direct impact of two smooth spheres on a line (velocities
/// along the line, m/s; impulses N·s; energy J).
struct DirectImpact {
  double v1 = 0, v2 = 0;        ///< velocities after impact
  double impulse_on_1 = 0;      ///< m₁(v₁ − u₁); the impulse on sphere 2 is its negative
  double impulse_on_2 = 0;      ///< m₂(v₂ − u₂)
  double kinetic_energy_loss = 0;  ///< T before − T after ≥ 0
};

/// Direct impact of smooth spheres m₁, m₂ (kg) with velocities u₁, u₂ (m/s)
/// along the line of centres and restitution e (course notes 1.3):
///   v₁ = ((m₁ − e m₂) u₁ + (1 + e) m₂ u₂) / (m₁ + m₂)             (1.3.3)
///   v₂ = ((m₂ − e m₁) u₂ + (1 + e) m₁ u₁) / (m₁ + m₂)             (1.3.4)
///   m₁(v₁ − u₁) = m₁m₂(1 + e)(u₂ − u₁) / (m₁ + m₂)                 (Cor. 1)
///   loss = ½ m₁m₂(1 − e²)(u₁ − u₂)² / (m₁ + m₂)                    (1.3.7)
/// The notes print (1.3.4) with u₂(m₂ + e m₁); with that sign the momentum
/// m₁v₁ + m₂v₂ would change by 2 e m₁m₂u₂/(m₁ + m₂), so the sign must be
/// minus (it is what the notes' own derivation, (1.3.1) − m₁·(1.3.2), gives).
inline DirectImpact direct_impact(double m1, double m2, double u1, double u2, double e) {
  require_positive("direct_impact", "m1", m1);
  require_positive("direct_impact", "m2", m2);
  require_finite("direct_impact", "u1", u1);
  require_finite("direct_impact", "u2", u2);
  require_in_range("direct_impact", "e", e, 0.0, 1.0);
  DirectImpact r;
  const double m = m1 + m2;
  // Written as u + Δu with Δu from the impulse, which keeps full relative
  // accuracy for extreme mass ratios.
  const double j = (1.0 + e) * (u2 - u1) / m;  // impulse on 1 divided by m₁m₂
  r.v1 = u1 + m2 * j;
  r.v2 = u2 - m1 * j;
  r.impulse_on_1 = m1 * m2 * j;
  r.impulse_on_2 = -r.impulse_on_1;
  r.kinetic_energy_loss = 0.5 * m1 * m2 * (1.0 - e * e) * (u1 - u2) * (u1 - u2) / m;
  return r;
}

/// Result of an oblique impact of two smooth spheres, in the plane that
/// holds the common normal and each velocity (speeds m/s, angles rad).
struct ObliqueImpact {
  double v1 = 0, v2 = 0;         ///< speeds after impact
  double theta = 0, phi = 0;     ///< angles of v₁, v₂ with the common normal
  double v1_normal = 0, v2_normal = 0;          ///< v₁ cos θ, v₂ cos φ
  double v1_tangential = 0, v2_tangential = 0;  ///< v₁ sin θ = u₁ sin α, v₂ sin φ = u₂ sin β
  double impulse_on_1 = 0;       ///< along the normal, m₁(v₁ cos θ − u₁ cos α) (N·s)
  double impulse_on_2 = 0;       ///< m₂(v₂ cos φ − u₂ cos β) = −impulse_on_1 (N·s)
  double kinetic_energy_loss = 0;  ///< J
};

/// Oblique impact (course notes 1.4): sphere 1 (m₁, speed u₁ at angle α to
/// the common normal) meets sphere 2 (m₂, u₂ at angle β):
///   v₁ cos θ = ((m₁ − e m₂) u₁ cos α + (1 + e) m₂ u₂ cos β) / (m₁ + m₂)   (1.4.5)
///   v₂ cos φ = ((1 + e) m₁ u₁ cos α + (m₂ − e m₁) u₂ cos β) / (m₁ + m₂)   (1.4.6)
///   v₁ sin θ = u₁ sin α,  v₂ sin φ = u₂ sin β                          (1.4.3–4)
///   impulse = m₁m₂(1 + e)(u₂ cos β − u₁ cos α) / (m₁ + m₂)              (1.4.7)
///   loss = m₁m₂(1 − e²)(u₁ cos α − u₂ cos β)² / (2(m₁ + m₂))            (1.4.1)
/// The notes print (1.4.6) with v₁ cos α for u₁ cos α (and m₂v₂ cos β for
/// m₂u₂ cos β in the line before): the velocity after impact cannot appear
/// on the right; momentum along the normal holds only with u₁.
inline ObliqueImpact oblique_impact(double m1, double m2, double u1, double u2, double alpha, double beta, double e) {
  require_finite("oblique_impact", "alpha", alpha);
  require_finite("oblique_impact", "beta", beta);
  const DirectImpact d = direct_impact(m1, m2, u1 * std::cos(alpha), u2 * std::cos(beta), e);
  ObliqueImpact r;
  r.v1_normal = d.v1;
  r.v2_normal = d.v2;
  r.v1_tangential = u1 * std::sin(alpha);
  r.v2_tangential = u2 * std::sin(beta);
  r.v1 = std::hypot(r.v1_normal, r.v1_tangential);
  r.v2 = std::hypot(r.v2_normal, r.v2_tangential);
  r.theta = std::atan2(r.v1_tangential, r.v1_normal);
  r.phi = std::atan2(r.v2_tangential, r.v2_normal);
  r.impulse_on_1 = d.impulse_on_1;
  r.impulse_on_2 = d.impulse_on_2;
  r.kinetic_energy_loss = d.kinetic_energy_loss;
  return r;
}

/// Velocities of two smooth spheres after they collide, as vectors: the
/// components along the unit normal n (from sphere 1 to sphere 2) follow
/// direct_impact(), the tangential components are unchanged.
template <int D>
struct SphereVelocities {
  Eigen::Matrix<double, D, 1> v1, v2;  ///< m/s
  double impulse_on_2 = 0;             ///< along n (N·s)
  double kinetic_energy_loss = 0;      ///< J
};
template <int D>
SphereVelocities<D> smooth_spheres_impact(double m1, double m2, const Eigen::Matrix<double, D, 1>& u1,
                                          const Eigen::Matrix<double, D, 1>& u2,
                                          const Eigen::Matrix<double, D, 1>& n, double e) {
  const double a = u1.dot(n), b = u2.dot(n);
  const DirectImpact d = direct_impact(m1, m2, a, b, e);
  SphereVelocities<D> r;
  r.v1 = u1 + (d.v1 - a) * n;
  r.v2 = u2 + (d.v2 - b) * n;
  r.impulse_on_2 = d.impulse_on_2;
  r.kinetic_energy_loss = d.kinetic_energy_loss;
  return r;
}

namespace detail {
inline std::string sphere_name(int i) { return "s" + std::to_string(i + 1); }
}  // namespace detail

/// N smooth spheres on a line, centres x₁ < x₂ < … < x_N (m), masses m_i
/// (kg), radii r_i (m); neighbours collide with restitution e.
///   T = ½ Σ m_i ẋ_i²,  V = 0,
///   contacts φ_i = x_{i+1} − x_i − r_i − r_{i+1} ≥ 0  ("s1-s2", …).
/// N = 2 is the direct impact of course notes 1.3; equal touching spheres
/// are Newton's cradle. P is the parameters' type (parameter sensitivities,
/// analysis/sensitivity.hpp: m1 … mN, r1 … rN, e; restitution() gives P, so
/// a parameter's column crosses the impacts).
template <int N, class P = double>
struct BasicSpheresOnLine {
  static_assert(N >= 2 && N <= 64, "SpheresOnLine needs 2 to 64 spheres");
  static constexpr int coordinate_count = N;
  /// T = Σ ½ m_i ẋ_i²: M constant (model.hpp, constant_mass_matrix_v; used
  /// up to detail::kMaxSinglePassDof = 64 coordinates).
  static constexpr bool constant_mass_matrix = coordinate_count <= lagrangian::detail::kMaxSinglePassDof;
  std::array<P, N> m{}, r{};
  P e = 1.0;
  /// The model with parameters of type Q, and its parameters: m1 … mN,
  /// r1 … rN, e.
  template <class Q>
  using with_parameter_type = BasicSpheresOnLine<N, Q>;
  static std::string parameter_name(std::size_t i) {
    return detail::indexed_parameter_name<N>(i, std::array<std::string_view, 2>{"m", "r"},
                                             std::array<std::string_view, 1>{"e"});
  }
  static constexpr auto parameter_members() {
    using Self = BasicSpheresOnLine;
    return detail::array_then_scalar_accessors<Self, P, N, &Self::m, &Self::r>(
        &detail::member_accessor<Self, P, &Self::e>);
  }
  /// Unit masses, radii 0.1 m, e = 1.
  BasicSpheresOnLine() {
    m.fill(1.0);
    r.fill(0.1);
  }
  BasicSpheresOnLine(const std::array<double, N>& masses, const std::array<double, N>& radii, double restitution)
      : e(0) {
    for (int i = 0; i < N; ++i) {
      m[static_cast<std::size_t>(i)] = require_positive("SpheresOnLine", "m" + std::to_string(i + 1), masses[static_cast<std::size_t>(i)]);
      r[static_cast<std::size_t>(i)] = require_nonnegative("SpheresOnLine", "r" + std::to_string(i + 1), radii[static_cast<std::size_t>(i)]);
    }
    e = require_in_range("SpheresOnLine", "e", restitution, 0.0, 1.0);
  }
  std::string name() const { return "spheres_on_line"; }
  std::vector<std::string> coordinate_names() const {
    std::vector<std::string> out;
    for (int i = 0; i < N; ++i) out.push_back("x" + std::to_string(i + 1));
    return out;
  }
  std::vector<std::string> coordinate_units() const { return std::vector<std::string>(N, "m"); }
  std::vector<std::string> unilateral_names() const {
    std::vector<std::string> out;
    for (int i = 0; i + 1 < N; ++i) out.push_back(detail::sphere_name(i) + "-" + detail::sphere_name(i + 1));
    return out;
  }
  /// Every gap in m: each λ in N.
  std::vector<std::string> constraint_units() const { return std::vector<std::string>(N - 1, "m"); }
  std::array<P, N - 1> restitution() const {
    std::array<P, N - 1> out;
    out.fill(e);
    return out;
  }
  std::array<Particle, N> particles() const {
    std::array<Particle, N> out;
    for (int i = 0; i < N; ++i) out[static_cast<std::size_t>(i)] = {ad::value_of(m[static_cast<std::size_t>(i)]), {i, -1, -1}};
    return out;
  }
  template <class S>
  S kinetic(const Vec<S, N>&, const Vec<S, N>& qd, const S&) const {
    S t = S(0);
    for (int i = 0; i < N; ++i) t += 0.5 * m[static_cast<std::size_t>(i)] * qd[i] * qd[i];
    return t;
  }
  template <class S>
  S potential(const Vec<S, N>&, const S&) const {
    return S(0);
  }
  template <class S>
  Vec<S, N - 1> unilateral(const Vec<S, N>& q, const S&) const {
    Vec<S, N - 1> g;
    for (int i = 0; i + 1 < N; ++i) g[i] = q[i + 1] - q[i] - (r[static_cast<std::size_t>(i)] + r[static_cast<std::size_t>(i + 1)]);
    return g;
  }
};
/// N spheres on a line with parameters in double precision.
template <int N>
using SpheresOnLine = BasicSpheresOnLine<N>;

/// Two smooth spheres free in a plane (D = 2) or in space (D = 3), no
/// gravity; coordinates (x₁, y₁[, z₁], x₂, y₂[, z₂]) of the centres (m).
///   T = ½ m₁|ṙ₁|² + ½ m₂|ṙ₂|²,  contact φ = |r₂ − r₁| − (R₁ + R₂) ≥ 0.
/// The oblique impact of course notes 1.4: the common normal is r₂ − r₁.
/// P is the parameters' type (parameter sensitivities,
/// analysis/sensitivity.hpp: restitution() gives P, so a parameter's
/// column crosses the impact).
template <int D, class P = double>
struct TwoSpheres : detail::ParticlePair<D, P> {
  static constexpr int coordinate_count = 2 * D;
  using detail::ParticlePair<D, P>::m1;
  using detail::ParticlePair<D, P>::m2;
  P r1, r2, e;
  /// The model with parameters of type Q, and its parameters in the order
  /// of parameter_names (the scene's `oblique_impact`).
  template <class Q>
  using with_parameter_type = TwoSpheres<D, Q>;
  static constexpr std::array<std::string_view, 5> parameter_names{"m1", "m2", "r1", "r2", "e"};
  static constexpr std::array<P TwoSpheres::*, 5> parameter_members() {
    using Pair = detail::ParticlePair<D, P>;
    return {&Pair::m1, &Pair::m2, &TwoSpheres::r1, &TwoSpheres::r2, &TwoSpheres::e};
  }
  /// Unit masses, radii 0.1 m, e = 0.9: the scene `oblique_impact`'s defaults.
  TwoSpheres() : TwoSpheres(1.0, 1.0, 0.1, 0.1, 0.9) {}
  TwoSpheres(double mass1, double mass2, double radius1, double radius2, double restitution)
      : detail::ParticlePair<D, P>{require_positive("TwoSpheres", "m1", mass1),
                                   require_positive("TwoSpheres", "m2", mass2)},
        r1(require_positive("TwoSpheres", "r1", radius1)),
        r2(require_positive("TwoSpheres", "r2", radius2)),
        e(require_in_range("TwoSpheres", "e", restitution, 0.0, 1.0)) {}
  std::string name() const { return D == 2 ? "two_spheres_2d" : "two_spheres_3d"; }
  std::array<std::string, 1> unilateral_names() const { return {"s1-s2"}; }
  std::array<std::string, 1> constraint_units() const { return {"m"}; }  ///< gap in m: λ in N
  std::array<P, 1> restitution() const { return {e}; }
  template <class S>
  S potential(const Vec<S, coordinate_count>&, const S&) const {
    return S(0);
  }
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, coordinate_count>& q, const S&) const {
    using std::sqrt;
    S d2 = S(0);
    for (int k = 0; k < D; ++k) d2 += (q[D + k] - q[k]) * (q[D + k] - q[k]);
    return Vec<S, 1>(sqrt(d2) - (r1 + r2));
  }
};

/// A smooth ball (mass m, radius R) in uniform gravity g along −z, above a
/// fixed plane n·r = d (unit normal n pointing to the allowed side, d in m);
/// coordinates (x, y, z) of the centre (m). With n = (0, 0, 1) the plane is
/// a floor; with a horizontal n, a wall.
///   T = ½ m |ṙ|²,  V = m g z,  contact φ = n·r − d − R ≥ 0.
/// Bounce: v⁺ = v⁻ − (1 + e)(n·v⁻) n (bounce_velocity). Dropped from rest
/// with its lowest point at height h above a floor, it lands at t = √(2h/g).
/// The normal is kept as given (nx, ny, nz) and normalised where it is
/// used, so its parameters may be numbers of another type P (parameter
/// sensitivities, analysis/sensitivity.hpp: with restitution() of type P a
/// parameter's column crosses the bounces) and a column of nx is the
/// derivative along the given nx, the normal renormalised.
template <class P = double>
struct BasicBallAndPlane {
  static constexpr int coordinate_count = 3;
  static constexpr ModelDescription description{
      "ball_and_plane",
      "Smooth ball bouncing on a fixed plane n.r = offset (a floor by default) under gravity along -z",
      {{"x", "m"}, {"y", "m"}, {"z", "m"}},
      {{"m", 1.0, "kg", "mass of the ball"},
       {"R", 0.1, "m", "radius of the ball"},
       {"e", 0.5, "1", "coefficient of restitution"},
       {"g", 9.81, "m/s^2", "acceleration of gravity"},
       {"nx", 0.0, "1", "plane normal, x component (normalised)"},
       {"ny", 0.0, "1", "plane normal, y component"},
       {"nz", 1.0, "1", "plane normal, z component"},
       {"offset", 0.0, "m", "plane offset d in n.r = d"}}};
  /// T = ½ m|v|²: M constant (model.hpp, constant_mass_matrix_v).
  static constexpr bool constant_mass_matrix = true;
  P m, R, e, g, nx, ny, nz, d;
  template <class Q>
  using with_parameter_type = BasicBallAndPlane<Q>;
  static constexpr std::array<P BasicBallAndPlane::*, 8> parameter_members() {
    return {&BasicBallAndPlane::m,  &BasicBallAndPlane::R,  &BasicBallAndPlane::e,  &BasicBallAndPlane::g,
            &BasicBallAndPlane::nx, &BasicBallAndPlane::ny, &BasicBallAndPlane::nz, &BasicBallAndPlane::d};
  }
  BasicBallAndPlane(double mass = description.value("m"), double radius = description.value("R"),
                    double restitution = description.value("e"), double gravity = description.value("g"),
                    std::array<double, 3> normal = {description.value("nx"), description.value("ny"),
                                                    description.value("nz")},
                    double offset = description.value("offset"))
      : m(require_positive("BallAndPlane", "m", mass)),
        R(require_nonnegative("BallAndPlane", "R", radius)),
        e(require_in_range("BallAndPlane", "e", restitution, 0.0, 1.0)),
        g(require_nonnegative("BallAndPlane", "g", gravity)),
        nx(require_finite("BallAndPlane", "nx", normal[0])),
        ny(require_finite("BallAndPlane", "ny", normal[1])),
        nz(require_finite("BallAndPlane", "nz", normal[2])),
        d(require_finite("BallAndPlane", "offset", offset)) {
    require_positive("BallAndPlane", "|normal|",
                     std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]));
  }
  std::string name() const { return std::string(description.name); }
  std::array<std::string_view, 3> coordinate_names() const { return description.coordinate_names(); }
  std::array<std::string_view, 3> coordinate_units() const { return description.coordinate_units(); }
  std::array<std::string, 1> unilateral_names() const { return {"ball-plane"}; }
  std::array<std::string, 1> constraint_units() const { return {"m"}; }  ///< gap in m: λ in N
  std::array<P, 1> restitution() const { return {e}; }
  std::array<Particle, 1> particles() const { return {Particle{ad::value_of(m), {0, 1, 2}}}; }
  /// The plane's unit normal n = (nx, ny, nz) / |(nx, ny, nz)|.
  std::array<P, 3> normal() const {
    using std::sqrt;
    const P length = sqrt(nx * nx + ny * ny + nz * nz);
    return {nx / length, ny / length, nz / length};
  }
  template <class S>
  S kinetic(const Vec<S, 3>&, const Vec<S, 3>& qd, const S&) const {
    return 0.5 * m * (qd[0] * qd[0] + qd[1] * qd[1] + qd[2] * qd[2]);
  }
  template <class S>
  S potential(const Vec<S, 3>& q, const S&) const {
    return m * g * q[2];
  }
  template <class S>
  Vec<S, 1> unilateral(const Vec<S, 3>& q, const S&) const {
    const std::array<P, 3> n = normal();
    return Vec<S, 1>(n[0] * q[0] + n[1] * q[1] + n[2] * q[2] - d - R);
  }
  /// Velocity after bouncing off the plane with velocity v (m/s):
  /// v − (1 + e)(n·v) n, the normal part reversed and scaled by e, the
  /// tangential part unchanged.
  std::array<double, 3> bounce_velocity(const std::array<double, 3>& v) const {
    const std::array<double, 3> n = normal();
    const double vn = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
    return {v[0] - (1 + e) * vn * n[0], v[1] - (1 + e) * vn * n[1], v[2] - (1 + e) * vn * n[2]};
  }
  /// Time to fall from rest through a height h (m) onto a floor: √(2h/g) (s).
  double drop_time(double h) const { return std::sqrt(2.0 * h / g); }
};
/// The ball and plane with parameters in double precision.
using BallAndPlane = BasicBallAndPlane<>;

/// N smooth discs (spheres moving in a plane) in the box [0, W] × [0, H]
/// (m), gravity g along −y (0 by default); coordinates (x₁, y₁, …, x_N, y_N).
///   T = ½ Σ m_i |ṙ_i|²,  V = Σ m_i g y_i,
///   contacts: each sphere against the four walls (φ = x_i − r_i,
///   W − x_i − r_i, y_i − r_i, H − y_i − r_i; restitution e_wall) and every
///   pair (φ = |r_j − r_i| − r_i − r_j; restitution e_pair).
/// P is the parameters' type (parameter sensitivities,
/// analysis/sensitivity.hpp: m1 … mN, r1 … rN, W, H, e_wall, e_pair, g).
template <int N, class P = double>
struct BasicSpheresInBox {
  static constexpr int pairs = N * (N - 1) / 2;
  static constexpr int contacts = 4 * N + pairs;
  static_assert(N >= 1 && contacts <= 64, "SpheresInBox supports up to 64 contacts (N <= 8)");
  static constexpr int coordinate_count = 2 * N;
  /// T = Σ ½ m_i |v_i|²: M constant (model.hpp, constant_mass_matrix_v;
  /// used up to detail::kMaxSinglePassDof = 64 coordinates).
  static constexpr bool constant_mass_matrix = coordinate_count <= lagrangian::detail::kMaxSinglePassDof;
  std::array<P, N> m{}, r{};
  P W = 2.0, H = 1.0, g = 0.0, e_wall = 1.0, e_pair = 1.0;
  /// The model with parameters of type Q, and its parameters: m1 … mN,
  /// r1 … rN, W, H, e_wall, e_pair, g.
  template <class Q>
  using with_parameter_type = BasicSpheresInBox<N, Q>;
  static std::string parameter_name(std::size_t i) {
    return detail::indexed_parameter_name<N>(i, std::array<std::string_view, 2>{"m", "r"},
                                             std::array<std::string_view, 5>{"W", "H", "e_wall", "e_pair", "g"});
  }
  static constexpr auto parameter_members() {
    using Self = BasicSpheresInBox;
    return detail::array_then_scalar_accessors<Self, P, N, &Self::m, &Self::r>(
        &detail::member_accessor<Self, P, &Self::W>, &detail::member_accessor<Self, P, &Self::H>,
        &detail::member_accessor<Self, P, &Self::e_wall>, &detail::member_accessor<Self, P, &Self::e_pair>,
        &detail::member_accessor<Self, P, &Self::g>);
  }
  /// Unit masses, radii 0.1 m, the box 2 m × 1 m, elastic, no gravity.
  BasicSpheresInBox() {
    m.fill(1.0);
    r.fill(0.1);
  }
  BasicSpheresInBox(const std::array<double, N>& masses, const std::array<double, N>& radii, double width,
                    double height, double restitution_wall, double restitution_pair = 1.0, double gravity = 0.0)
      : W(require_positive("SpheresInBox", "W", width)),
        H(require_positive("SpheresInBox", "H", height)),
        g(require_nonnegative("SpheresInBox", "g", gravity)),
        e_wall(require_in_range("SpheresInBox", "e_wall", restitution_wall, 0.0, 1.0)),
        e_pair(require_in_range("SpheresInBox", "e_pair", restitution_pair, 0.0, 1.0)) {
    for (int i = 0; i < N; ++i) {
      const auto k = static_cast<std::size_t>(i);
      m[k] = require_positive("SpheresInBox", "m" + std::to_string(i + 1), masses[k]);
      r[k] = require_positive("SpheresInBox", "r" + std::to_string(i + 1), radii[k]);
      if (2 * radii[k] >= std::min(width, height))
        throw ParameterError("SpheresInBox: sphere " + std::to_string(i + 1) + " (radius " +
                             std::to_string(radii[k]) + ") does not fit in the box");
    }
  }
  std::string name() const { return "spheres_in_box"; }
  std::vector<std::string> coordinate_names() const {
    std::vector<std::string> out;
    for (int i = 0; i < N; ++i) {
      out.push_back("x" + std::to_string(i + 1));
      out.push_back("y" + std::to_string(i + 1));
    }
    return out;
  }
  std::vector<std::string> coordinate_units() const { return std::vector<std::string>(2 * N, "m"); }
  std::vector<std::string> unilateral_names() const {
    std::vector<std::string> out;
    for (int i = 0; i < N; ++i)
      for (const char* w : {"left", "right", "bottom", "top"}) out.push_back(detail::sphere_name(i) + "-" + w);
    for (int i = 0; i < N; ++i)
      for (int j = i + 1; j < N; ++j) out.push_back(detail::sphere_name(i) + "-" + detail::sphere_name(j));
    return out;
  }
  /// Every gap in m: each λ in N.
  std::vector<std::string> constraint_units() const { return std::vector<std::string>(4 * N + N * (N - 1) / 2, "m"); }
  std::array<Particle, N> particles() const {
    std::array<Particle, N> out;
    for (int i = 0; i < N; ++i)
      out[static_cast<std::size_t>(i)] = {ad::value_of(m[static_cast<std::size_t>(i)]), {2 * i, 2 * i + 1, -1}};
    return out;
  }
  std::array<P, contacts> restitution() const {
    std::array<P, contacts> out;
    for (int k = 0; k < contacts; ++k) out[static_cast<std::size_t>(k)] = k < 4 * N ? e_wall : e_pair;
    return out;
  }
  template <class S>
  S kinetic(const Vec<S, coordinate_count>&, const Vec<S, coordinate_count>& qd, const S&) const {
    S t = S(0);
    for (int i = 0; i < N; ++i)
      t += 0.5 * m[static_cast<std::size_t>(i)] * (qd[2 * i] * qd[2 * i] + qd[2 * i + 1] * qd[2 * i + 1]);
    return t;
  }
  template <class S>
  S potential(const Vec<S, coordinate_count>& q, const S&) const {
    S v = S(0);
    for (int i = 0; i < N; ++i) v += m[static_cast<std::size_t>(i)] * g * q[2 * i + 1];
    return v;
  }
  template <class S>
  Vec<S, contacts> unilateral(const Vec<S, coordinate_count>& q, const S&) const {
    using std::sqrt;
    Vec<S, contacts> phi;
    for (int i = 0; i < N; ++i) {
      const P& ri = r[static_cast<std::size_t>(i)];
      phi[4 * i + 0] = q[2 * i] - ri;
      phi[4 * i + 1] = W - q[2 * i] - ri;
      phi[4 * i + 2] = q[2 * i + 1] - ri;
      phi[4 * i + 3] = H - q[2 * i + 1] - ri;
    }
    int k = 4 * N;
    for (int i = 0; i < N; ++i)
      for (int j = i + 1; j < N; ++j, ++k) {
        const S dx = q[2 * j] - q[2 * i], dy = q[2 * j + 1] - q[2 * i + 1];
        phi[k] = sqrt(dx * dx + dy * dy) - (r[static_cast<std::size_t>(i)] + r[static_cast<std::size_t>(j)]);
      }
    return phi;
  }
};
/// N discs in a box with parameters in double precision.
template <int N>
using SpheresInBox = BasicSpheresInBox<N>;

/// What a scene names built-in models that are presets of the templates above
/// (the registry builds each from its description's parameters).
namespace presets {

/// SpheresOnLine<2>: two spheres of their own masses and radii.
inline constexpr ModelDescription direct_impact{
    "direct_impact",
    "Direct impact of two smooth spheres on a line (Newton's law of restitution)",
    {{"x1", "m"}, {"x2", "m"}},
    {{"m1", 1.0, "kg", "mass of sphere 1"},
     {"m2", 2.0, "kg", "mass of sphere 2"},
     {"r1", 0.1, "m", "radius of sphere 1"},
     {"r2", 0.1, "m", "radius of sphere 2"},
     {"e", 0.8, "1", "coefficient of restitution"}}};

/// SpheresOnLine<5>: five equal spheres.
inline constexpr ModelDescription newtons_cradle{
    "newtons_cradle",
    "Newton's cradle: five equal spheres on a line, four touching, the first swung in",
    {{"x1", "m"}, {"x2", "m"}, {"x3", "m"}, {"x4", "m"}, {"x5", "m"}},
    {{"m", 0.1, "kg", "mass of each sphere"},
     {"r", 0.0125, "m", "radius of each sphere"},
     {"e", 1.0, "1", "coefficient of restitution"}}};

/// TwoSpheres<2>.
inline constexpr ModelDescription oblique_impact{
    "oblique_impact",
    "Oblique impact of two smooth spheres moving in a plane, no gravity",
    {{"x1", "m"}, {"y1", "m"}, {"x2", "m"}, {"y2", "m"}},
    {{"m1", 1.0, "kg", "mass of sphere 1"},
     {"m2", 1.0, "kg", "mass of sphere 2"},
     {"r1", 0.1, "m", "radius of sphere 1"},
     {"r2", 0.1, "m", "radius of sphere 2"},
     {"e", 0.9, "1", "coefficient of restitution"}}};

/// SpheresInBox<3>: three equal discs.
inline constexpr ModelDescription spheres_in_box{
    "spheres_in_box",
    "Three smooth discs in the box [0, W] x [0, H], colliding with the walls and each other",
    {{"x1", "m"}, {"y1", "m"}, {"x2", "m"}, {"y2", "m"}, {"x3", "m"}, {"y3", "m"}},
    {{"m", 1.0, "kg", "mass of each disc"},
     {"r", 0.1, "m", "radius of each disc"},
     {"W", 2.0, "m", "width of the box"},
     {"H", 1.0, "m", "height of the box"},
     {"e_wall", 1.0, "1", "restitution against the walls"},
     {"e_pair", 1.0, "1", "restitution between discs"},
     {"g", 0.0, "m/s^2", "acceleration of gravity along -y"}}};

}  // namespace presets

}  // namespace lagrangian::models

// simulate() and the tangent flow (Lyapunov, Floquet, sensitivities) for
// these models are compiled once, in the library (src/models/); see
// lagrangian/integrate/detail/compiled_models.hpp and
// lagrangian/analysis/detail/compiled_tangent_flow.hpp.
#define LAGRANGIAN_IMPACT_MODELS(X) \
  X(lagrangian::models::SpheresOnLine<2>) \
  X(lagrangian::models::SpheresOnLine<5>) \
  X(lagrangian::models::TwoSpheres<2>) \
  X(lagrangian::models::BallAndPlane) \
  X(lagrangian::models::SpheresInBox<3>)
LAGRANGIAN_IMPACT_MODELS(LAGRANGIAN_BUILT_IN_MODEL)
LAGRANGIAN_IMPACT_MODELS(LAGRANGIAN_EXTERN_TANGENT_FLOW)
