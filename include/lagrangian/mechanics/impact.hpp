#pragma once
/// \file impact.hpp
/// Contacts, Newton's law of restitution in generalized coordinates, and
/// watched events.
///
/// **Contacts.** A model's unilateral constraints φ_j(q, t) ≥ 0 (see
/// constraints.hpp) are its contacts: φ_j is the gap (m for a distance), and
/// the contact closes when φ_j falls through zero. A model that declares
///
///   std::array<double, u> restitution() const;   // e_j ∈ [0, 1], one per contact
///
/// has its impacts resolved by apply_impact(); without restitution() a
/// closing contact is reported as an error.
///
/// **Impact law.** At an impact of contact j at (q, t) with velocities q̇⁻,
/// let G = ∂φ_j/∂q (a row), and v⁻ = G q̇⁻ + ∂φ_j/∂t the normal velocity of
/// approach (< 0). Newton's experimental law v⁺ = −e v⁻ along the line of
/// impact, smooth bodies (no tangential impulse) and conservation of momentum
/// are one linear system: the generalized impulse P = Gᵀ Λ + Cᵀ μ changes the
/// velocities by M Δq̇ = P, subject to
///   G Δq̇ = −(1 + e) v⁻,    C Δq̇ = −(C q̇⁻ + c),
/// where C q̇ + c = 0 are the model's bilateral (holonomic and Pfaffian)
/// constraints at the velocity level. Λ = [G; C] M⁻¹ [G; C]ᵀ solved for the
/// right-hand side; for one contact without other constraints
///   Λ = −(1 + e) v⁻ / (G M⁻¹ Gᵀ).
/// For two spheres on a line (q = (x₁, x₂), φ = x₂ − x₁ − r₁ − r₂,
/// M = diag(m₁, m₂)) this gives the course notes' velocities
///   v₁ = ((m₁ − e m₂) u₁ + (1 + e) m₂ u₂) / (m₁ + m₂),
///   v₂ = ((m₂ − e m₁) u₂ + (1 + e) m₁ u₁) / (m₁ + m₂),
/// and a kinetic-energy loss ½ m₁m₂(1 − e²)(u₁ − u₂)²/(m₁ + m₂); the
/// velocities normal to G (in the M metric) are untouched.
///
/// **Watched events.** A model may declare functions whose zero crossings are
/// located and logged (or stop the run):
///
///   template <class S> Vec<S, k> events(const Vec<S, n>& q, const Vec<S, n>& qd, const S& t) const;
///   std::array<EventSpec, k> event_specs() const;   // name, direction, action

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>


#include "lagrangian/ad.hpp"
#include "lagrangian/mechanics/detail/min_norm_solver.hpp"
#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// Time tolerance of located events (impacts, lift-offs, watched events):
/// the TOMS 748 bracket is narrowed to event_time_tolerance · max(1 s, |t|),
/// i.e. 1e-12 relative with an absolute floor of 1e-12 s.
inline constexpr double event_time_tolerance = 1e-12;

/// Which zero crossings of a watched function count.
enum class Direction {
  falling,  ///< from positive to negative
  rising,   ///< from negative to positive
  either,   ///< both
};

/// What a watched event does when it fires.
enum class EventAction {
  record,  ///< log it and carry on
  stop,    ///< log it and end the run at the event time
};

/// A watched event function: its name, the crossings that count and what
/// happens then.
struct EventSpec {
  std::string name;
  Direction direction = Direction::either;
  EventAction action = EventAction::record;
};

/// True when the model declares restitution coefficients for its contacts.
template <class M>
inline constexpr bool has_restitution_v = requires(const M& m) {
  { m.restitution()[0] } -> std::convertible_to<double>;
};

namespace detail {
template <class M>
concept has_events_c = requires(const M& m, const Vec<double, coordinate_count_v<M>>& q, double t) {
  { m.events(q, q, t) };
  { m.event_specs() };
};
template <class M>
constexpr int event_rows() {
  if constexpr (has_events_c<M>) {
    using V = Vec<double, coordinate_count_v<M>>;
    using R =
        std::decay_t<decltype(std::declval<const M&>().events(std::declval<const V&>(), std::declval<const V&>(), 0.0))>;
    return R::RowsAtCompileTime;
  } else {
    return 0;
  }
}
}  // namespace detail

/// Number of watched event functions a model declares (0 when none).
template <class M>
inline constexpr int event_count_v = detail::event_rows<M>();

/// The contacts' restitution coefficients, checked: throws ParameterError
/// naming the contact and the value unless each is in [0, 1].
/// (A std::array for a compile-time number of contacts, a std::vector for a
/// run-time one.)
template <class M>
auto restitution_coefficients(const M& model) {
  constexpr int u = unilateral_count_v<M>;
  std::conditional_t<u == Dynamic, std::vector<double>, std::array<double, u == Dynamic ? 0 : u>> e{};
  const int count = unilateral_count(model);
  if constexpr (u == Dynamic) e.assign(static_cast<std::size_t>(count), 0.0);
  if constexpr (has_restitution_v<M>) {
    const auto given = model.restitution();
    const auto names = constraint_names(model);
    if (static_cast<int>(std::size(given)) != count)
      throw ParameterError(model_name(model) + ": restitution() gives " + std::to_string(std::size(given)) +
                           " coefficients for " + std::to_string(count) + " contacts");
    for (int j = 0; j < count; ++j) {
      const double v = given[static_cast<std::size_t>(j)];
      if (!(v >= 0.0 && v <= 1.0)) {
        std::ostringstream os;
        os.precision(17);
        os << model_name(model) << ": restitution of contact "
           << names[static_cast<std::size_t>(holonomic_count(model) + j)] << " must be in [0, 1], got " << v;
        throw ParameterError(os.str());
      }
      e[static_cast<std::size_t>(j)] = v;
    }
  }
  return e;
}

/// The event specifications of a model, checked for count.
template <class M>
std::vector<EventSpec> event_specs(const M& model) {
  std::vector<EventSpec> out;
  if constexpr (event_count_v<M> > 0) {
    const auto given = model.event_specs();
    for (const auto& s : given) out.push_back(s);
    if (static_cast<int>(out.size()) != event_count_v<M>)
      throw ParameterError(model_name(model) + ": event_specs() gives " + std::to_string(out.size()) +
                           " specifications for " + std::to_string(event_count_v<M>) + " event functions");
  }
  return out;
}

/// Gap and normal velocity of every contact at a state: φ_j(q, t) and
/// φ̇_j = ∂φ_j/∂q q̇ + ∂φ_j/∂t (one first-order pass along (q̇, 1)). For a
/// run-time number of contacts `gap` and `rate` must have that size.
template <class M>
void contact_gaps(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                  const Vec<double, coordinate_count_v<M>>& qd, double t,
                  Vec<double, unilateral_count_v<M>>& gap, Vec<double, unilateral_count_v<M>>& rate) {
  using J = ad::Jet<double, 1, 1>;
  constexpr int n = coordinate_count_v<M>;
  const int size = static_cast<int>(q.size());
  std::optional<Vec<J, n>> local;
  auto& qp = detail::jet_storage<J>(local, 0, size);
  J tp;
  ad::along_path(q, qd, t, qp, tp);
  const auto phi = model.unilateral(qp, tp);
  const int count = unilateral_count(model);
  detail::check_rows(phi, count, "unilateral()");
  for (int j = 0; j < count; ++j) {
    gap[j] = phi[j].v;
    rate[j] = phi[j].g[0];
  }
}

/// What one impact did.
template <int N>
struct ImpactResult {
  int contact = -1;                ///< index of the contact among the unilateral constraints
  double restitution = 0;          ///< e used
  double impulse = 0;              ///< Λ: impulse along +∇φ (N·s for a distance gap), ≥ 0
  double approach_speed = 0;       ///< −v⁻ = −φ̇ before the impact (m/s for a distance gap), > 0
  double separation_speed = 0;     ///< v⁺ = φ̇ after the impact = e · approach_speed
  Vec<double, N> generalized_impulse;  ///< P = M (q̇⁺ − q̇⁻) (N·s, or N·m·s for angles)
  double kinetic_energy_before = 0;    ///< T(q, q̇⁻) (J); ½ q̇ᵀMq̇ when the model gives L directly
  double kinetic_energy_after = 0;     ///< T(q, q̇⁺) (J)
};

namespace detail {
template <class M>
double kinetic_for_log(const M& model, const Workspace<coordinate_count_v<M>>& ws,
                       const Vec<double, coordinate_count_v<M>>& q,
                       const Vec<double, coordinate_count_v<M>>& qd, double t) {
  if constexpr (has_kinetic_potential_v<M>) {
    (void)ws;
    return model.kinetic(q, qd, t);
  } else {
    (void)model;
    (void)q;
    (void)t;
    return 0.5 * qd.dot(ws.mass * qd);
  }
}
}  // namespace detail

namespace detail {

/// apply_impact(); with `only_approaching` false the law is applied whatever
/// the sign of v⁻, which makes q̇ ↦ q̇⁺ one affine map everywhere (the
/// extrapolation of cycling impacts reads it off, integrate/detail/impact_cycle.hpp).
/// `solver`, of constraint_count(model) rows and columns, solves for the
/// impulses (a run passes the one its constraint workspace holds).
template <class M>
ImpactResult<coordinate_count_v<M>> restitution_impact(const M& model, Workspace<coordinate_count_v<M>>& ws,
                                                       const Vec<double, coordinate_count_v<M>>& q,
                                                       Vec<double, coordinate_count_v<M>>& qd, double t, int contact,
                                                       double e, bool only_approaching, MinNormSolver& solver) {
  static_assert(unilateral_count_v<M> != 0, "apply_impact needs a model with contacts (unilateral constraints)");
  constexpr int n = coordinate_count_v<M>;
  constexpr int c = constraint_count_v<M>;
  if (contact < 0 || contact >= unilateral_count(model))
    throw OptionError("apply_impact: contact index " + std::to_string(contact) + " is outside [0, " +
                      std::to_string(unilateral_count(model)) + ")");
  if (!(e >= 0.0 && e <= 1.0)) {
    std::ostringstream os;
    os.precision(17);
    os << "apply_impact: restitution e must be in [0, 1], got " << e;
    throw ParameterError(os.str());
  }
  ImpactResult<n> r;
  r.contact = contact;
  r.restitution = e;
  evaluate(model, ws, q, qd, t);
  detail::factor_mass_matrix(ws, q, qd, t);
  r.kinetic_energy_before = detail::kinetic_for_log(model, ws, q, qd, t);
  auto cs = constraint_state(model, q, qd, t);
  drop_inactive(model, cs, ActiveSet::only(contact));  // the bilateral rows and this contact's row
  const int row = holonomic_count(model) + contact;
  const double v_minus = cs.velocity[row];
  r.generalized_impulse = Vec<double, n>::Zero(q.size());
  if (only_approaching && !(v_minus < 0.0)) {
    r.kinetic_energy_after = r.kinetic_energy_before;
    r.separation_speed = v_minus;
    return r;
  }
  Vec<double, c> target = -cs.velocity;  // bilateral rows: restore C q̇ + c = 0
  target[row] = -(1.0 + e) * v_minus;
  const Eigen::Matrix<double, n, c> minv_kt = ws.cholesky.solve(cs.jacobian.transpose());
  const Mat<double, c> schur = cs.jacobian * minv_kt;
  const int rows = static_cast<int>(target.size());
  solver.factorize(schur.data(), rank_tolerance);
  Vec<double, c> mu(rows);
  solver.solve(target.data(), mu.data());
  const Vec<double, n> dqd = minv_kt * mu;
  qd += dqd;
  r.generalized_impulse = cs.jacobian.transpose() * mu;
  r.impulse = mu[row];
  r.approach_speed = -v_minus;
  r.separation_speed = v_minus + cs.jacobian.row(row).dot(dqd);
  r.kinetic_energy_after = detail::kinetic_for_log(model, ws, q, qd, t);
  return r;
}

}  // namespace detail

/// Applies Newton's law of restitution for contact `contact` at (q, t):
/// replaces q̇ by q̇⁺ (see the file comment) and returns the impulse and the
/// kinetic energies. Throws ParameterError unless e ∈ [0, 1] and
/// DynamicsError when M is singular. A contact that is not approaching
/// (v⁻ ≥ 0) is left unchanged (Λ = 0).
template <class M>
ImpactResult<coordinate_count_v<M>> apply_impact(const M& model, Workspace<coordinate_count_v<M>>& ws,
                                                 const Vec<double, coordinate_count_v<M>>& q,
                                                 Vec<double, coordinate_count_v<M>>& qd, double t, int contact,
                                                 double e) {
  detail::MinNormSolver solver(constraint_count(model), constraint_count(model));
  return detail::restitution_impact(model, ws, q, qd, t, contact, e, true, solver);
}

/// apply_impact() with its own workspace.
template <class M>
ImpactResult<coordinate_count_v<M>> apply_impact(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                                 Vec<double, coordinate_count_v<M>>& qd, double t,
                                  int contact, double e) {
  Workspace<coordinate_count_v<M>> ws(static_cast<int>(q.size()));
  return apply_impact(model, ws, q, qd, t, contact, e);
}

}  // namespace lagrangian
