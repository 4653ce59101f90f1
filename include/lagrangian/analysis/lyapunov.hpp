#pragma once
/// \file lyapunov.hpp
/// Lyapunov exponents of a motion: how fast nearby motions separate.
///
/// Beside the state x = (q, q̇) the run integrates k tangent vectors
/// δx_1 … δx_k by the variational equations δẋ = J(x, t) δx, with J from
/// automatic differentiation (tangent_flow.hpp), in the one driver: the
/// augmented system has the n(1 + k) coordinates (q, δq_1, …, δq_k) and
/// their rates (q̇, δq̇_1, …, δq̇_k), so its accuracy is controlled by the
/// run's method and tolerances like any run's. Benettin's method, in the
/// canonical coordinates (q, p), p = ∂L/∂q̇: at the end of an accepted step
/// the tangent matrix Z = P W (2n × k), W = [δx_1 … δx_k] and
/// P = [[I, 0], [∂p/∂q, ∂p/∂q̇]] (momentum_jacobian()), may be factored
/// Z = Q R (Householder, R_jj > 0), log R_jj added to the sum of exponent
/// j and the tangent vectors restarted as W = P⁻¹ Q; they start as the
/// first k canonical unit vectors. In (q, p) a Hamiltonian flow keeps
/// phase-space volume exactly (Liouville), so the exponents of the whole
/// spectrum sum to zero at every time, not only as T → ∞ as in (q, q̇),
/// where the volume changes by det M(q(0)) / det M(q(T)).
/// Over the run of length T = t_end − t0
///   λ_j = (1/T) Σ_renormalisations log R_jj    (1/s),
/// the finite-time exponents, reported largest first; with k = 2n the
/// whole spectrum, whose sum is (1/T) log det ∂(q, p)(T)/∂(q, p)(0)
/// (0 for a Hamiltonian flow, −2b/m for a particle under linear drag b in
/// the plane). k = 1 gives the largest exponent alone, at less cost: its
/// one tangent vector needs J δx along one direction (state_jvp()), not J.
///
/// MEGNO (Cincotta & Simó 2000, A&AS 147, 205): with ℓ(t) = ln |δx_1(t)|
/// of the first tangent vector (in (q, q̇), as if never renormalised: a
/// renormalisation only scales it) and s = t − t0,
///   Y(t) = (2/s) ∫₀ˢ s' dℓ(s'),   ⟨Y⟩(t) = (1/s) ∫₀ˢ Y ds'.
/// ⟨Y⟩ → 0 for an isochronous centre (the harmonic oscillator), → 2 for
/// regular motion with shear (|δx| ∝ t: a pendulum below the separatrix,
/// Kepler orbits), and grows as λ_1 s / 2 for chaotic motion. The integral
/// is taken at every accepted step (Simpson's rule with ℓ at the step's
/// interpolated midpoint; ⟨Y⟩ by the trapezoid rule).
///
/// The renormalisation interval is chosen by the code unless given: a
/// renormalisation follows the first step after which a tangent vector's
/// length (in (q, q̇)) has changed by more than a factor e since the last
/// one, or T/100 after it (`interval`, when given, replaces T/100), so that
/// the vectors keep their orthogonality in double precision; the result
/// reports the shortest and longest interval taken. A renormalisation moves
/// the state, so the stepper restarts after it, as after an impact. A
/// model's watched events (a projectile's landing) are not applied: the
/// exponents are those of its equations of motion.
///
/// A model with contacts (and restitution coefficients) has its impacts
/// located and resolved in the tangent run as in a plain one, and every
/// tangent vector crosses an impact by its saltation matrix S
/// (saltation.hpp); the exponents' sum then includes (1/T) Σ ln |det S| of
/// the impacts (2 ln e per bounce of a ball on a floor). Impacts are located
/// by the plain run's rules (integrate/detail/contact_rules.hpp). Where a
/// plain run lets a contact rest (its Zeno rule, a plastic impact) the model
/// may hold it shut (TangentModel::rest: particle scenes, text models and,
/// through detail::HoldingContacts, C++ models whose only constraints are
/// contacts do): the last
/// impact, with e = 0, is crossed by its saltation matrix into the motion
/// with φ_j = 0 held, which removes two directions, δφ_j and δφ̇_j: every
/// neighbouring motion comes to rest on the same contact, so the flow's
/// Jacobian loses rank 2 there and two exponents of the whole spectrum are
/// −∞ (the sum too); a resting contact lifts off where its multiplier λ_j
/// falls through 0, where both motions' rates agree, so the tangent vectors
/// cross it unchanged. Asked for fewer than all exponents, a run in which
/// the rest removes one of its vectors (a start along the gap's own
/// directions, δφ_j, of a motion whose other coordinates do not mix into
/// them) stops with SimulationError: those are not the largest. A touch not
/// faster than contact_touch_speed, a rest on a model without
/// TangentModel::rest, an impact while another contact rests, a grazing
/// contact (no saltation matrix) and two contacts closing or touching at one
/// instant stop the run with SimulationError: the tangent flow through them
/// is not derived.
///
/// A model with holonomic or Pfaffian constraints moves on its constraint
/// manifold h = (g, ġ, φ) = 0 in the state space, of dimension
/// d = 2n − rank ∂h/∂(q, q̇) (2 per degree of freedom of a holonomic
/// system), and so do its tangent vectors: they start as the first k vectors
/// of a basis of the manifold's tangent space, and there are d exponents
/// (k ≤ d; 0 asks for all d). They are measured and factored in the
/// reduced canonical coordinates (Uᵀδq, Uᵀδp), U an orthonormal basis of
/// ker ∂g/∂q: Darboux coordinates of the symplectic form restricted to the
/// manifold of a holonomic system, in which a Hamiltonian spectrum sums to
/// zero at every time. J is that of the
/// constrained motion (tangent_flow.hpp); the state integrates the
/// constrained equations without stabilisation, and at every
/// renormalisation the state is projected onto the manifold (the model's
/// project_positions() and project_velocities()) and the tangent vectors
/// onto its tangent space (W ← W − H⁺ H W, H = ∂h/∂(q, q̇)), which takes off
/// the drift the integration left (a projection that fails stops the run
/// with SimulationError). A start off the manifold (beyond the plain run's
/// 1e-9) is a ConstraintError; a manifold of dimension 0 (constraints that
/// leave no motion) an AnalysisError.

#include <algorithm>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "lagrangian/analysis/detail/holding_contacts.hpp"
#include "lagrangian/analysis/saltation.hpp"
#include "lagrangian/analysis/tangent_flow.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/mechanics/projection.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// What lyapunov_spectrum() computes and how.
struct LyapunovOptions {
  /// The run: method, tolerances, t0 and t_end (s). Its output settings
  /// are not used.
  SimulationOptions run;
  /// Exponents wanted, k in [1, d] (d = 2n, or the dimension of the
  /// constraint manifold's tangent space); 0 asks for all d.
  int exponents = 0;
  /// Longest time between renormalisations (s); 0 takes T/100. Shorter
  /// intervals come from the tangent vectors' growth (above).
  double interval = 0.0;
};

/// Finite-time Lyapunov exponents and what they cost.
struct LyapunovResult {
  std::vector<double> spectrum;      ///< λ_1 ≥ … ≥ λ_k (1/s)
  double sum = 0;                    ///< Σ λ_i (1/s)
  double t_final = 0;                ///< end of the run (s)
  int renormalisations = 0;          ///< QR factorisations, the last at t_final included
  double interval_min = 0;           ///< shortest interval taken (s)
  double interval_max = 0;           ///< longest interval taken (s)
  std::uint64_t steps = 0;           ///< accepted steps of the augmented system
  std::uint64_t rhs_evaluations = 0; ///< evaluations of q̈ with its derivatives along the k vectors
  double seconds = 0;                ///< wall time of the run (s)
  int impacts = 0;                   ///< impacts crossed (saltation.hpp); 0 for a model without contacts
  int rests = 0;                     ///< contacts that came to rest (a plastic impact or the Zeno rule)
  int releases = 0;                  ///< resting contacts that lifted off (their multiplier reached 0)
  std::vector<double> q_final, qd_final;  ///< the state at t_final
  /// MEGNO Y(T) of the first tangent vector and its time mean ⟨Y⟩(T)
  /// (dimensionless; see the file comment).
  double megno = 0, megno_mean = 0;
};

namespace detail {

/// A model reached through one function: q̈ and the n × 2n Jacobian
/// ∂q̈/∂(q, q̇) (column-major) at (q, q̇, t).
struct TangentModel {
  const void* model = nullptr;
  /// What `model` points to when the TangentModel owns it (a model seen
  /// through HoldingContacts, tangent_model_of()); null otherwise.
  std::shared_ptr<const void> owner;
  void (*evaluate)(const void* model, const double* q, const double* qd, double t, double* qdd, double* jacobian) =
      nullptr;
  /// ∂p/∂(q, q̇) at (q, q̇, t) (n × 2n, column-major; momentum_jacobian())
  /// and, unless `dl_dq` is null, ∂L/∂q (n values; a particle scene gives
  /// its force kernels' forces, drag included, which only a scene without
  /// drag has as −∂V/∂q).
  void (*momentum)(const void* model, const double* q, const double* qd, double t, double* out,
                   double* dl_dq) = nullptr;
  int n = 0;
  /// q̈ and (∂q̈/∂(q, q̇)) v along one direction v (2n values) at (q, q̇, t),
  /// without the whole Jacobian (state_jvp() with K = 1): what one tangent
  /// vector needs.
  void (*evaluate_direction)(const void* model, const double* q, const double* qd, double t, const double* v,
                             double* qdd, double* jv) = nullptr;
  /// q̈ and (∂q̈/∂(q, q̇)) v + ∂q̈/∂p for the model's parameter number
  /// `parameter` (sensitivity.hpp); null unless parameters were asked for.
  void (*evaluate_parameter)(const void* model, const double* q, const double* qd, double t, const double* v,
                             int parameter, double* qdd, double* jv) = nullptr;
  /// For a model with holonomic or Pfaffian rows and parameters asked for:
  /// ∂h/∂p of the manifold's rows h = (g, ġ, φ) along the parameter number
  /// `parameter` at (q, q̇, t) (`manifold` values into `out`,
  /// manifold_rows_along_parameter()); it returns the parameter's value.
  double (*parameter_manifold)(const void* model, const double* q, const double* qd, double t, int parameter,
                               double* out) = nullptr;
  /// The model's contacts, crossed at their impacts by the saltation
  /// matrix (saltation.hpp): their number (0 for none), names and
  /// restitution coefficients, their gaps φ_j(q, t) and rates φ̇_j
  /// (`contacts` values each, contact_gaps()) and the impact map of contact
  /// j with coefficient e at (q, q̇⁻, t): q̇⁺ (n values), ∂q̇⁺/∂(q, q̇, t)
  /// (n × (2n + 1), column-major), G = ∂φ_j/∂q (n values) and γ (the gap's
  /// acceleration is G q̈ + γ); it returns the approach speed
  /// v = G q̇⁻ + ∂φ_j/∂t.
  int contacts = 0;
  std::vector<std::string> contact_names;
  std::vector<double> restitution;
  void (*gaps)(const void* model, const double* q, const double* qd, double t, double* gap, double* rate) = nullptr;
  double (*impact)(const void* model, const double* q, const double* qd, double t, int contact, double e,
                   double* qd_plus, double* jacobian, double* gap_gradient, double* gamma) = nullptr;
  /// For a model with contacts and parameters asked for: the impact map of
  /// contact j at (q, q̇⁻, t) along the model's parameter number
  /// `parameter`, with the contact's own restitution coefficient or, when
  /// `plastic`, e = 0 (the impact that begins a rest): ∂q̇⁺/∂p (n values
  /// into `dqd_plus`); it returns ∂φ_j/∂p. Null for a model whose contacts
  /// do not follow its parameters (sensitivity.hpp): its parameter columns
  /// are refused.
  double (*parameter_impact)(const void* model, const double* q, const double* qd, double t, int contact,
                             int parameter, bool plastic, double* dqd_plus) = nullptr;
  /// Resting contacts, for a model that can hold a contact shut as a plain
  /// run does (after its Zeno rule or a plastic impact): rest(model, j,
  /// true) makes φ_j = 0 a holonomic row of the motion from then on, so that
  /// evaluate() and evaluate_direction() give q̈ and its derivatives of
  ///   M q̈ = r + G_jᵀ λ_j,   G_j q̈ + γ_j = 0,
  /// and rest(model, j, false) opens it again (the tangent run finds the
  /// multipliers from the other hooks: tangent_system.hpp). Null for a model
  /// whose tangent flow through a resting contact is not derived: such a
  /// rest stops the tangent run.
  void (*rest)(const void* model, int contact, bool shut) = nullptr;
  /// True when rest() holds the contact shut in the models that
  /// evaluate_parameter() evaluates too (a text model's seeded twins; a C++
  /// model's twin, held through HoldingContacts as the model is), so that a
  /// parameter's column follows the held motion through a rest; false: a
  /// rest stops a run with parameter columns.
  bool rest_holds_parameters = false;
  /// True when impact() and parameter_impact() give Newton's law of their
  /// contact alone while other contacts rest, as a plain run applies it
  /// (the resting contacts are rows of the motion, not of the law): an
  /// impact whose impulse leaves every resting contact's rate unchanged (a
  /// wall's normal orthogonal in M⁻¹ to a floor's) then crosses by the
  /// usual saltation matrix with those contacts still held; one that lifts
  /// a resting contact off (separating faster than contact_touch_speed)
  /// releases it at the impact, as a plain run does; one that sets it
  /// approaching is refused (impacts in sequence at one instant, in a
  /// plain run). False: the law keeps the held
  /// contacts as its rows (a text model's), so the tangent run opens the
  /// other resting contacts through rest() while it evaluates impact() and
  /// parameter_impact(), and holds them again after: the same law.
  bool impact_alone_while_resting = false;
  /// The constraint manifold of a model with holonomic or Pfaffian rows:
  /// the number of its rows h = (g, ġ, φ) (2 mh + mp; 0 for a model
  /// without such constraints), mh and the rows' names, h and ∂h/∂(q, q̇) at
  /// (q, q̇, t) (manifold_rows() of tangent_solve.hpp), and the projection of
  /// a state onto it (project_positions(), then project_velocities()).
  int manifold = 0, manifold_holonomic = 0;
  std::vector<std::string> manifold_names;
  void (*manifold_rows)(const void* model, const double* q, const double* qd, double t, double* residual,
                        double* jacobian) = nullptr;
  void (*project)(const void* model, double* q, double* qd, double t) = nullptr;
};

/// Benettin's method over a TangentModel (src/analysis/lyapunov.cpp).
LyapunovResult lyapunov_spectrum(const TangentModel& model, const double* q0, const double* qd0,
                                 const LyapunovOptions& options);

/// The model a TangentModel of M points to (tangent_model_of()), as an M:
/// for a model held through HoldingContacts, the copy's base.
template <class M>
const M& model_at(const void* model) {
  if constexpr (held_by_wrapper<M>) {
    return *static_cast<const HoldingContacts<M>*>(model);
  } else {
    return *static_cast<const M*>(model);
  }
}

template <class M>
void evaluate_tangent(const void* model, const double* q, const double* qd, double t, double* qdd,
                      double* jacobian) {
  constexpr int n = coordinate_count_v<M>;
  Vec<double, n> a;
  Eigen::Matrix<double, n, 2 * n> j;
  state_jacobian(model_at<M>(model), Eigen::Map<const Vec<double, n>>(q),
                 Eigen::Map<const Vec<double, n>>(qd), t, a, j);
  Eigen::Map<Vec<double, n>> qdd_out(qdd);
  Eigen::Map<Eigen::Matrix<double, n, 2 * n>> jacobian_out(jacobian);
  qdd_out = a;
  jacobian_out = j;
}

/// state_jvp() along one direction v (2n values) on raw arrays, on the
/// model itself or on its `seeded` twin (sensitivity.hpp).
template <class M, class E = M>
void jvp_along(const M& model, const double* q, const double* qd, double t, const double* v, double* qdd, double* jv,
               const E* seeded = nullptr) {
  constexpr int n = coordinate_count_v<M>;
  Vec<double, n> a;
  Eigen::Matrix<double, n, 1> d;
  state_jvp<1>(model, Eigen::Map<const Vec<double, n>>(q), Eigen::Map<const Vec<double, n>>(qd), t,
               Eigen::Map<const Eigen::Matrix<double, 2 * n, 1>>(v), a, d, seeded);
  Eigen::Map<Vec<double, n>> qdd_out(qdd), jv_out(jv);
  qdd_out = a;
  jv_out = d;
}

template <class M>
void evaluate_tangent_direction(const void* model, const double* q, const double* qd, double t, const double* v,
                                double* qdd, double* jv) {
  jvp_along(model_at<M>(model), q, qd, t, v, qdd, jv);
}

template <class M>
void evaluate_momentum(const void* model, const double* q, const double* qd, double t, double* out,
                       double* dl_dq) {
  constexpr int n = coordinate_count_v<M>;
  Eigen::Matrix<double, n, 2 * n> j;
  Vec<double, n> gradient;
  momentum_jacobian(model_at<M>(model), Eigen::Map<const Vec<double, n>>(q),
                    Eigen::Map<const Vec<double, n>>(qd), t, j, &gradient);
  Eigen::Map<Eigen::Matrix<double, n, 2 * n>> out_map(out);
  out_map = j;
  if (dl_dq != nullptr) std::copy(gradient.data(), gradient.data() + n, dl_dq);
}

template <class M>
void evaluate_gaps(const void* model, const double* q, const double* qd, double t, double* gap, double* rate) {
  constexpr int n = coordinate_count_v<M>, u = unilateral_count_v<M>;
  const M& m = model_at<M>(model);
  const int count = unilateral_count(m);
  thread_local Vec<double, u> g, r;  // sized once per thread for a run-time count
  if (g.size() != count) g.resize(count), r.resize(count);
  contact_gaps(m, Eigen::Map<const Vec<double, n>>(q), Eigen::Map<const Vec<double, n>>(qd), t, g, r);
  std::copy(g.data(), g.data() + count, gap);
  std::copy(r.data(), r.data() + count, rate);
}

template <class M>
double evaluate_impact(const void* model, const double* q, const double* qd, double t, int contact, double e,
                       double* qd_plus, double* jacobian, double* gap_gradient, double* gamma) {
  constexpr int n = coordinate_count_v<M>;
  const ImpactMap<n> map = impact_map_with(model_at<M>(model), Eigen::Map<const Vec<double, n>>(q),
                                           Eigen::Map<const Vec<double, n>>(qd), t, contact, e);
  *gamma = map.gamma;
  Eigen::Map<Vec<double, n>> plus_out(qd_plus), gradient_out(gap_gradient);
  Eigen::Map<Eigen::Matrix<double, n, 2 * n + 1>> jacobian_out(jacobian);
  plus_out = map.qd_plus;
  jacobian_out = map.jacobian;
  gradient_out = map.gap_gradient;
  return map.approach;
}

template <class M>
void evaluate_manifold(const void* model, const double* q, const double* qd, double t, double* residual,
                       double* jacobian) {
  constexpr int n = coordinate_count_v<M>;
  manifold_rows(model_at<M>(model), Eigen::Map<const Vec<double, n>>(q),
                Eigen::Map<const Vec<double, n>>(qd), t, residual, jacobian);
}

template <class M>
void evaluate_projection(const void* model, double* q, double* qd, double t) {
  constexpr int n = coordinate_count_v<M>;
  const M& m = model_at<M>(model);
  const int size = model_size(m);
  Vec<double, n> qv = Eigen::Map<const Vec<double, n>>(q, size), qdv = Eigen::Map<const Vec<double, n>>(qd, size);
  // The manifold is the holonomic and Pfaffian rows' alone: no contact is
  // held shut (ActiveSet{}); the contacts act only at their impacts.
  const ActiveSet bilateral_only;
  project_positions(m, qv, t, 1e-12, 20, bilateral_only);  // ‖g‖∞ ≤ 1e-12 (1 + ‖q‖∞)
  Workspace<n> ws(size);
  project_velocities(m, ws, qv, qdv, t, bilateral_only);
  Eigen::Map<Vec<double, n>> q_out(q, size), qd_out(qd, size);
  q_out = qv;
  qd_out = qdv;
}

/// A model that projects a state onto its constraints itself
/// (`void project_state(double* q, double* qd, double t) const`, as
/// evaluate_projection() does: positions onto g = 0, then velocities).
template <class M>
concept projects_own_state = requires(const M& m, double* x, double t) { m.project_state(x, x, t); };

template <class M>
void evaluate_own_projection(const void* model, double* q, double* qd, double t) {
  model_at<M>(model).project_state(q, qd, t);
}

/// A model that holds its contacts shut itself (`void hold(int contact,
/// bool shut) const`): a held contact's gap is a holonomic row of its
/// passes, counted at run time (text::FixedSizeModel).
template <class M>
concept holds_contacts = requires(const M& m) { m.hold(0, true); };

template <class M>
void evaluate_hold(const void* model, int contact, bool shut) {
  model_at<M>(model).hold(contact, shut);
}

/// The TangentModel of `model`: AnalysisError (`prefix` starting its
/// message) for constraints the tangent flow is not derived for
/// (require_tangent_flow_constraints()) and for contacts without
/// restitution coefficients. A model with contacts and no other rows
/// (held_by_wrapper) has its q̈ and J from a copy of it that can hold its
/// contacts shut (HoldingContacts, owned by the result: `model` points to
/// it, and model_at() gives the model back to the other hooks), so the
/// tangent run carries it through a rest.
template <class M>
TangentModel tangent_model_of(const M& model, const std::string& prefix) {
  require_tangent_flow_constraints(model, prefix);
  TangentModel tm;
  tm.model = &model;
  tm.evaluate = &evaluate_tangent<M>;
  tm.momentum = &evaluate_momentum<M>;
  tm.n = coordinate_count_v<M>;
  tm.evaluate_direction = &evaluate_tangent_direction<M>;
  if constexpr (held_by_wrapper<M>) {
    // q̈ and its derivatives from the copy's passes, whose rows are the held
    // gaps; the other hooks are the model's own (model_at()). Also for a
    // run-time number of contacts that is 0: model_at() expects the copy.
    using H = HoldingContacts<M>;
    auto holding = std::make_shared<const H>(model);
    tm.model = holding.get();
    tm.owner = std::move(holding);
    tm.evaluate = &evaluate_tangent<H>;
    tm.evaluate_direction = &evaluate_tangent_direction<H>;
  }
  if constexpr (bilateral_rows_v<M> != 0) {
    const int mh = holonomic_count(model), mp = pfaffian_count(model);
    if (mh + mp > 0) {
      tm.manifold = 2 * mh + mp;
      tm.manifold_holonomic = mh;
      const auto names = constraint_names(model);  // holonomic, contacts, Pfaffian
      const int first_pfaffian = mh + unilateral_count(model);
      for (int i = 0; i < mh; ++i) tm.manifold_names.push_back(names[static_cast<std::size_t>(i)]);
      for (int i = 0; i < mh; ++i) tm.manifold_names.push_back(names[static_cast<std::size_t>(i)] + " (rate)");
      for (int i = 0; i < mp; ++i) tm.manifold_names.push_back(names[static_cast<std::size_t>(first_pfaffian + i)]);
      tm.manifold_rows = &evaluate_manifold<M>;
      if constexpr (projects_own_state<M>) {
        tm.project = &evaluate_own_projection<M>;
      } else {
        tm.project = &evaluate_projection<M>;
      }
    }
  }
  if constexpr (unilateral_count_v<M> != 0) {
    const int count = unilateral_count(model);
    if (count > 0) {
      (void)restitution_of(model, 0, prefix);  // AnalysisError without restitution()
      const auto e = restitution_coefficients(model);
      tm.restitution.assign(e.begin(), e.end());
      tm.contacts = count;
      const auto names = constraint_names(model);
      const auto first = names.begin() + holonomic_count(model);
      tm.contact_names.assign(first, first + count);
      tm.gaps = &evaluate_gaps<M>;
      tm.impact = &evaluate_impact<M>;
      // (With holonomic or Pfaffian rows too, a rest stops the run: the
      // held gap would change the manifold its vectors are kept on.)
      if constexpr (holds_contacts<M>) {
        if (tm.manifold == 0) tm.rest = &evaluate_hold<M>;
      } else if constexpr (held_by_wrapper<M>) {
        tm.rest = &evaluate_hold<HoldingContacts<M>>;
        // The impact hooks are the model's own (model_at()): Newton's law
        // of the closing contact alone, as a plain run's.
        tm.impact_alone_while_resting = true;
      }
    }
  }
  return tm;
}

}  // namespace detail

/// The Lyapunov exponents of the motion of `model` from `initial` at
/// options.run.t0 to options.run.t_end (see the file comment). Throws
/// OptionError for a bad option (naming it and its value), AnalysisError
/// for constraints the tangent flow is not derived for (more holonomic and
/// Pfaffian rows counted at run time than it takes), ConstraintError for a
/// start off the constraint manifold, SimulationError when the run fails.
template <class M>
LyapunovResult lyapunov_spectrum(const M& model, const State<coordinate_count_v<M>>& initial,
                                 const LyapunovOptions& options) {
  constexpr int n = coordinate_count_v<M>;
  static_assert(n != Dynamic, "lyapunov_spectrum: the tangent flow is derived for models with a fixed coordinate_count");
  const detail::TangentModel tm = detail::tangent_model_of(model, "lyapunov: ");
  return detail::lyapunov_spectrum(tm, initial.q.data(), initial.qd.data(), options);
}

}  // namespace lagrangian
