#pragma once
/// \file sensitivity.hpp
/// How a motion depends on where it starts and on the model's parameters:
/// the sensitivities ∂x(t)/∂x(t0) and ∂x(t)/∂p by the variational equations.
///
/// With x = (q, q̇) and ẋ = f(x, t; p) = (q̇, q̈(q, q̇, t; p)), a column
/// s = ∂x(t)/∂θ, θ a component of the initial state or a parameter, evolves
/// by the forward sensitivity equations
///   ṡ = J(x, t) s + ∂f/∂θ,   J = ∂f/∂x = [[0, I], [∂q̈/∂q, ∂q̈/∂q̇]],
/// from s(t0) = e_θ for the initial state (∂f/∂θ = 0: these columns form the
/// state transition matrix Φ(t) = ∂x(t)/∂x(t0)) and from s(t0) = 0 for a
/// parameter. The columns are integrated beside the state by the one driver
/// (the tangent system of lyapunov.hpp), so the run's method and tolerances
/// control them too. J s and, for a parameter, J s + ∂q̈/∂p come from
/// automatic differentiation (tangent_flow.hpp, state_jvp()): L is evaluated
/// once per column on numbers that carry their derivative along the column
/// and, for a parameter, along δp = 1 in the model's parameter.
/// No finite differences; the result is exact to rounding and to the run's
/// tolerances.
///
/// Units: ∂x_i/∂θ in the unit of x_i (m, rad, m/s, rad/s) per unit of θ
/// (per m, rad, m/s, rad/s of the initial state; per kg, m, m/s², N/m, kg/s
/// of a parameter).
///
/// **Parameters.** Differentiating along a parameter needs the model's
/// parameters as numbers of another type. A model offers it by being a class
/// template over its parameters' type P that declares
///   template <class Q> using with_parameter_type = Model<Q>;  // itself, parameters of type Q
///   static constexpr std::array<P Model::*, np> parameter_members();
/// the members every energy, force, dissipation, constraint, gap and
/// restitution coefficient reads (pointers to data members, or accessors
/// `P& (*)(Model&)` for a parameter held deeper, as TwoBody's k in its
/// potential), in the order of
/// its `description` (model_description.hpp), of
/// `static constexpr std::array<std::string_view, np> parameter_names`, or
/// of `static std::string parameter_name(std::size_t i)` (for a model whose
/// number of parameters follows a template argument, as SpheresOnLine<N>'s
/// m1 … mN, r1 … rN, e);
/// Model<Q> must be default constructible (its parameters are then set from
/// the model's), and hold nothing computed from its parameters (a cached
/// m1 + m2 would keep its default). The built-in plane, double, spherical,
/// elastic and driven pendulums, the bead on a spinning hoop, the polar
/// Kepler problem, the pendulum on a cart, the harmonic oscillator, the
/// projectiles, the Atwood machine, the bead on a spinning wire, the
/// particle on a sphere, the Cartesian double pendulum, the knife edge, the
/// ball on a plane, two spheres (TwoSpheres), N spheres on a line
/// (SpheresOnLine), N discs in a box (SpheresInBox), the N-link pendulum
/// chain (PendulumChain) and the two-body models under Newtonian gravity
/// (TwoBody, RelativeMotion) are written so (models/pendulums.hpp,
/// models/projectile.hpp, models/constrained.hpp, models/impacts.hpp,
/// models/two_body.hpp).
///
/// Scope as tangent_flow.hpp: models with a fixed n ≤ 6 coordinates.
/// **Constraints.** A model with holonomic or Pfaffian constraints moves on
/// its manifold h = (g, ġ, φ) = 0, and only perturbations in its tangent
/// space keep the start on it: the d columns Φ B0 of an orthonormal basis B0
/// of that space at the start are integrated, and each sample holds the
/// 2n × 2n matrix Φ(t) P0, P0 = B0 B0ᵀ the orthogonal projector on it
/// (Φ(t) δx0 for an admissible δx0, the only use the matrix has: P0 is
/// orthogonal in the Euclidean metric of (q, q̇) in SI units, which mixes m
/// and m/s, so its part across the manifold means nothing physical beyond
/// "not admissible"). Nothing projects the state or the columns back onto
/// the manifold during the run: they drift off it by what the tolerances
/// let through. A manifold of dimension 0 (constraints that leave no
/// motion) is an AnalysisError. A parameter column s = ∂x/∂p of such a
/// model differentiates q̈ through the saddle-point system with the rows'
/// own derivatives along p (an incline's slope, a wire's rate of turn: C, γ and
/// their derivatives from the rows of the seeded model), from s(t0) = 0:
/// the start is the same for every p, so it must stay on the manifold when
/// p changes, ∂h/∂p = 0 at the start. A parameter that moves the manifold
/// past the start (h = (g, ġ, φ) changing by more than the 1e-9 the start is
/// held to when p changes by max(|p|, 1)) is refused with AnalysisError
/// naming it and the row. Along the motion s obeys ∂h/∂x s + ∂h/∂p = 0: it
/// leaves the tangent space where the rows depend on p.
/// **Contacts.** A model's contacts are crossed at their impacts by the
/// saltation matrix S (saltation.hpp). A parameter's column crosses as the
/// column of the state (x, p) with ṗ = 0: the impact comes at τ(p), where
/// the gap φ_j(q(τ), τ; p) = 0, so dτ/dp = −(G s_q + ∂φ_j/∂p)/v, and the
/// map R(x; p) moves with p, so
///   s⁺ = S s⁻ + R_p + a ∂φ_j/∂p / v,  R_p = (0, ∂q̇⁺/∂p),
///   a = f⁺ − R_x f⁻ − R_t  (S = R_x + a ∇ₓφᵀ / v),
/// with ∂q̇⁺/∂p and ∂φ_j/∂p from Newton's law evaluated on the seeded twin
/// (M, G, v and e carrying the derivative along p). A model offers this by
/// reading its parameters in unilateral() and giving restitution() as
/// numbers of its parameters' type (std::array<P, u>: e may be a
/// parameter); a model whose restitution() gives doubles whatever P is
/// refused parameter columns (AnalysisError), as its gaps and coefficients
/// may not follow its parameters. The type of restitution() is the only
/// mark the library can check: a model that gives it as P but reads a
/// cached double in unilateral() gets columns without that double's
/// derivative. Where a plain run lets a contact rest (lyapunov.hpp) the
/// impact that begins the rest is plastic (R_p with e = 0) and f⁺ is the
/// held motion's; while it rests the column follows that motion, q̈ along p
/// from the seeded twin holding the same contacts (a held gap that moves
/// with p moves the row); at its lift-off the rates agree and the column
/// crosses unchanged.
/// A model's watched events are not applied (a projectile flies on through
/// its landing plane).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/saltation.hpp"
#include "lagrangian/analysis/tangent_flow.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// True when M offers parameter sensitivities (see the file comment). A
/// model derived from one that offers them, without declaring its own
/// with_parameter_type, does not: its energies may differ from its base's.
template <class M>
inline constexpr bool has_parameter_type_v = requires {
  typename M::template with_parameter_type<double>;
  M::parameter_members();
  requires std::is_same_v<typename M::template with_parameter_type<double>, M>;
};

/// The names of M's parameters in the order of M::parameter_members().
template <class M>
  requires has_parameter_type_v<M>
std::vector<std::string> parameter_names_of() {
  constexpr std::size_t count = M::parameter_members().size();
  std::vector<std::string> out;
  if constexpr (requires { M::description.parameters; }) {
    static_assert(M::description.parameters.size() == count,
                  "parameter_members() and the model's description list different numbers of parameters");
    for (std::size_t i = 0; i < count; ++i) out.emplace_back(M::description.parameters[i].name);
  } else if constexpr (requires { M::parameter_name(std::size_t{0}); }) {
    for (std::size_t i = 0; i < count; ++i) out.emplace_back(M::parameter_name(i));
  } else {
    static_assert(M::parameter_names.size() == count, "parameter_names and parameter_members() differ in length");
    for (std::string_view name : M::parameter_names) out.emplace_back(name);
  }
  return out;
}

/// What sensitivities() computes and how.
struct SensitivityOptions {
  /// Method, tolerances, t0 and t_end (s). output_interval > 0 adds the
  /// sensitivities at t0 + k·output_interval; otherwise only at t0 and t_end.
  SimulationOptions run;
  /// The 2n columns ∂x(t)/∂x(t0) (the state transition matrix).
  bool initial_state = true;
  /// The parameters p_j, by name, whose columns ∂x(t)/∂p_j follow.
  std::vector<std::string> parameters;
};

/// The sensitivities at the sample times, and what they cost.
struct SensitivityResult {
  std::vector<std::string> parameters;  ///< the parameter columns' names, in order
  int state_columns = 0;                ///< 2n with initial_state, else 0
  std::vector<double> times;            ///< sample times (s), t0 first and t_end last
  std::vector<Eigen::VectorXd> states;  ///< x = (q, q̇) at each time
  /// At each time the 2n × (state_columns + parameters) matrix
  /// [∂x(t)/∂x(t0) | ∂x(t)/∂p_1 … ∂x(t)/∂p_P] (on a constraint manifold
  /// Φ(t) P0 in place of ∂x(t)/∂x(t0): see the file comment).
  std::vector<Eigen::MatrixXd> sensitivities;
  std::uint64_t steps = 0;            ///< accepted steps
  std::uint64_t rhs_evaluations = 0;  ///< right-hand sides of the whole system
  double seconds = 0;                 ///< wall time (s)
  int impacts = 0;                    ///< impacts crossed (saltation.hpp)
};

namespace detail {

/// The parameter of `m` that `member` names: a pointer to a data member of
/// M, or an accessor P& (*)(M&) (sensitivity.hpp's file comment).
template <class M, class A>
auto& parameter_of(M& m, A member) {
  if constexpr (std::is_member_object_pointer_v<A>) {
    return m.*member;
  } else {
    return member(m);
  }
}
template <class M, class A>
const auto& parameter_of(const M& m, A member) {
  if constexpr (std::is_member_object_pointer_v<A>) {
    return m.*member;
  } else {
    return member(const_cast<M&>(m));  // read only
  }
}

/// The model with parameters of type ad::Jet<double, 1, 1>, the parameter
/// number `parameter` carrying the derivative 1.
template <class M>
typename M::template with_parameter_type<ad::Jet<double, 1, 1>> seeded_twin(const M& m, int parameter) {
  using I = ad::Jet<double, 1, 1>;
  using E = typename M::template with_parameter_type<I>;
  constexpr auto from = M::parameter_members();
  constexpr auto to = E::parameter_members();
  static_assert(from.size() == to.size(), "with_parameter_type<Q> lists other parameters than the model");
  E seeded;
  for (std::size_t i = 0; i < from.size(); ++i) parameter_of(seeded, to[i]) = I(parameter_of(m, from[i]));
  parameter_of(seeded, to[static_cast<std::size_t>(parameter)]).g[0] = 1.0;
  return seeded;
}

/// q̈ and J v + ∂q̈/∂p_parameter (n values) at (q, q̇, t) for v = (δq, δq̇)
/// (2n values): state_jvp() with K = 1 on the model with its parameter
/// seeded.
template <class M>
void evaluate_parameter_direction(const void* model, const double* q, const double* qd, double t, const double* v,
                                  int parameter, double* qdd, double* jv) {
  const M& m = model_at<M>(model);
  const auto seeded = seeded_twin(m, parameter);
  if constexpr (held_by_wrapper<M>) {
    // A model whose tangent flow holds its resting contacts through
    // HoldingContacts (lyapunov.hpp): the twin holds the same ones, so the
    // column follows the held motion, whose rows carry ∂/∂p too.
    const auto& holding = *static_cast<const HoldingContacts<M>*>(model);
    if (holding.held_count() > 0) {
      const HoldingContacts<std::remove_cvref_t<decltype(seeded)>> held(seeded);
      held.held_like(holding);
      jvp_along(holding, q, qd, t, v, qdd, jv, &held);
      return;
    }
  }
  jvp_along(m, q, qd, t, v, qdd, jv, &seeded);
}

/// TangentModel::parameter_manifold of a model with holonomic or Pfaffian
/// rows: ∂h/∂p on its seeded twin; returns p.
template <class M>
double evaluate_parameter_manifold(const void* model, const double* q, const double* qd, double t, int parameter,
                                   double* out) {
  constexpr int n = coordinate_count_v<M>;
  const M& m = model_at<M>(model);
  manifold_rows_along_parameter<n>(seeded_twin(m, parameter), q, qd, t, out);
  return parameter_of(m, M::parameter_members()[static_cast<std::size_t>(parameter)]);
}

/// True when the twin of M with parameters of type ad::Jet<double, 1, 1>
/// gives its restitution coefficients as such numbers: the mark of a model
/// whose contacts (gaps and coefficients) follow its parameters.
template <class M>
inline constexpr bool restitution_follows_parameters_v =
    requires(const typename M::template with_parameter_type<ad::Jet<double, 1, 1>>& twin) {
      requires std::is_same_v<std::remove_cvref_t<decltype(twin.restitution()[0])>, ad::Jet<double, 1, 1>>;
    };

/// ∂q̇⁺/∂p (n values into `dqd_plus`) and, returned, ∂φ_j/∂p at an impact
/// of contact j at (q, q̇⁻, t): Newton's law (saltation.hpp) on the seeded
/// twin `seeded` (parameters of type ad::Jet<double, 1, 1>), every input a
/// constant and the parameter carrying δp = 1; with the contact's own e, or
/// e = 0 when `plastic` (the impact that begins a rest: e does not enter).
template <int n, class E>
double impact_along_parameter(const E& seeded, const double* q, const double* qd, double t, int contact, bool plastic,
                              double* dqd_plus) {
  using I = ad::Jet<double, 1, 1>;
  Vec<I, n> qx, qdx;
  for (int k = 0; k < n; ++k) {
    qx[k] = I(q[k]);
    qdx[k] = I(qd[k]);
  }
  const I e = plastic ? I(0.0) : I(seeded.restitution()[static_cast<std::size_t>(contact)]);
  const ImpactLaw<I, n> law = impact_law(seeded, qx, qdx, I(t), contact, e);
  for (int i = 0; i < n; ++i) dqd_plus[i] = law.plus[i].g[0];
  return law.gap.g[0];
}

/// TangentModel::parameter_impact of a model offering parameter types.
template <class M>
double evaluate_parameter_impact(const void* model, const double* q, const double* qd, double t, int contact,
                                 int parameter, bool plastic, double* dqd_plus) {
  return impact_along_parameter<coordinate_count_v<M>>(seeded_twin(model_at<M>(model), parameter), q, qd,
                                                       t, contact, plastic, dqd_plus);
}

/// The sensitivities over a TangentModel (src/analysis/sensitivity.cpp);
/// `parameters` are indices into the model's parameters, `names` theirs.
SensitivityResult sensitivities(const TangentModel& model, const double* q0, const double* qd0,
                                const std::vector<int>& parameters, const std::vector<std::string>& names,
                                const SensitivityOptions& options);

/// The indices of `wanted` among `available`; OptionError naming an unknown
/// or repeated one.
std::vector<int> parameter_indices(const std::vector<std::string>& wanted, const std::vector<std::string>& available);

}  // namespace detail

/// ∂x(t)/∂x(t0) and ∂x(t)/∂p of the motion of `model` from `initial` at
/// options.run.t0 (see the file comment). Throws OptionError for a bad
/// option or an unknown parameter (naming it), ConstraintError for a start
/// off a constraint manifold, AnalysisError for parameters a model does not
/// offer (has_parameter_type_v), parameters of a model whose contacts do not
/// follow its parameters (restitution_follows_parameters_v) or
/// parameters that move the constraint manifold past the start, more than
/// kMaxRuntimeBilateralRows constraint rows counted at run time, or
/// constraints that leave no motion, SimulationError when the run fails.
template <class M>
SensitivityResult sensitivities(const M& model, const State<coordinate_count_v<M>>& initial,
                                const SensitivityOptions& options) {
  constexpr int n = coordinate_count_v<M>;
  static_assert(n != Dynamic, "sensitivities: the tangent flow is derived for models with a fixed coordinate_count");
  detail::TangentModel tm = detail::tangent_model_of(model, "sensitivity: ");
  std::vector<int> indices;
  std::vector<std::string> names;
  if (!options.parameters.empty()) {
    if constexpr (has_parameter_type_v<M>) {
      names = parameter_names_of<M>();
      indices = detail::parameter_indices(options.parameters, names);
      tm.evaluate_parameter = &detail::evaluate_parameter_direction<M>;
      if constexpr (detail::bilateral_rows_v<M> != 0) {
        if (tm.manifold > 0) tm.parameter_manifold = &detail::evaluate_parameter_manifold<M>;
      }
      if constexpr (unilateral_count_v<M> != 0) {
        if (tm.contacts > 0) {
          if constexpr (detail::restitution_follows_parameters_v<M>) {
            tm.parameter_impact = &detail::evaluate_parameter_impact<M>;
            tm.rest_holds_parameters = detail::held_by_wrapper<M>;
          } else {
            throw AnalysisError(
                "sensitivity: model '" + model_name(model) +
                "' has contacts whose gaps and restitution coefficients do not follow its parameters (its "
                "restitution() gives doubles for every parameter type), so parameter columns cannot cross its "
                "impacts; ask for the initial state's columns only");
          }
        }
      }
    } else {
      throw AnalysisError("sensitivity: model '" + model_name(model) +
                          "' does not offer parameter sensitivities: its parameters are not of a template type "
                          "(declare with_parameter_type and parameter_members(); see analysis/sensitivity.hpp)");
    }
  }
  return detail::sensitivities(tm, initial.q.data(), initial.qd.data(), indices, names, options);
}

}  // namespace lagrangian
