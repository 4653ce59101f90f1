#pragma once
/// \file model.hpp
/// What a user writes: a model in generalized coordinates.
///
/// A model is a plain struct with
///  - `static constexpr int coordinate_count` — the number n of generalized
///    coordinates (the older spelling `dof` is still read, but for a
///    constrained model n is not its number of degrees of freedom; see
///    dof_report() for that);
///  - `S kinetic(const Vec<S, n>& q, const Vec<S, n>& qd, const S& t) const`
///    — kinetic energy T(q, q̇, t) in J, and
///    `S potential(const Vec<S, n>& q, const S& t) const` — potential V(q, t)
///    in J; or instead a direct `S lagrangian(q, qd, t) const` (L = T − V);
///  - optionally `Vec<S, n> generalized_forces(q, qd, t) const` — the
///    non-conservative generalized forces Q (N or N·m per coordinate),
///    `S dissipation(q, qd) const` — the Rayleigh function D with
///    Q = −∂D/∂q̇ (W), with `bool uses_generalized_forces() const` and
///    `bool uses_dissipation() const` when only the run knows whether they
///    are in effect (see uses_generalized_forces()), `coordinate_names()`
///    returning n names,
///    `coordinate_units()` returning their n SI units ("m", "rad"; shown in
///    CSV headers and inspections), `name()`,
///    hand-coded `accelerations(q, qd, t, qdd)` (see
///    has_explicit_accelerations_v), and `static constexpr bool
///    constant_mass_matrix = true` when T depends on q̇ alone, at most
///    quadratically (see constant_mass_matrix_v).
/// Every function is a template on the scalar type S so that the same code
/// runs on `double` and on AD scalars. Write ordinary C++: `S x = 0`, `auto`
/// locals, `pow`, `abs`, `using std::cos; cos(x)` all work.
/// The functions must depend only on their arguments and the model's state:
/// simulate() may evaluate a copy of a trivially copyable model (so that its
/// parameters stay in registers through the run loop).
///
/// \code
/// struct Pendulum {
///   static constexpr int coordinate_count = 1;
///   double m = 1, l = 1, g = 9.81;
///   template <class S> S kinetic(const lagrangian::Vec<S, 1>&, const lagrangian::Vec<S, 1>& qd, const S&) const {
///     return 0.5 * m * l * l * qd[0] * qd[0];
///   }
///   template <class S> S potential(const lagrangian::Vec<S, 1>& q, const S&) const {
///     using std::cos; return -m * g * l * cos(q[0]);
///   }
/// };
/// \endcode

#include <array>
#include <concepts>
#include <iterator>
#include <string>
#include <type_traits>
#include <typeinfo>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/ad.hpp"

namespace lagrangian {

/// `coordinate_count` of a model whose number of coordinates is known only
/// at run time; such a model also has `int size() const`.
inline constexpr int Dynamic = Eigen::Dynamic;

namespace detail {
/// M::coordinate_count, or the older spelling M::dof, or 0 when the model
/// declares neither (check_model() then says so).
template <class M>
constexpr int declared_coordinate_count() {
  if constexpr (requires { { M::coordinate_count } -> std::convertible_to<int>; }) {
    return M::coordinate_count;
  } else if constexpr (requires { { M::dof } -> std::convertible_to<int>; }) {
    return M::dof;
  } else {
    return 0;
  }
}
}  // namespace detail

/// The number n of generalized coordinates a model declares
/// (`coordinate_count`, or `dof`), Dynamic for a run-time sized model.
template <class M>
inline constexpr int coordinate_count_v = detail::declared_coordinate_count<M>();

/// Column vector of n scalars (generalized coordinates, velocities, forces).
template <class S, int N>
using Vec = Eigen::Matrix<S, N, 1>;

/// n×n matrix (mass matrix).
template <class S, int N>
using Mat = Eigen::Matrix<S, N, N>;

namespace detail {

template <class M>
concept declares_coordinate_count =
    coordinate_count_v<M> >= 1 || (coordinate_count_v<M> == Dynamic && requires(const M& m) {
      { m.size() } -> std::convertible_to<int>;
    });

/// Coordinates per block in the block-wise derivative passes used for
/// the largest models (each pass seeds two blocks).
inline constexpr int kBlock = 4;
/// Largest fixed n whose equations of motion come from one pass with
/// ad::EomJet<n>. Above 12 coordinates such a number keeps its n × n
/// velocity Hessian in a pooled block, not in itself, so the vectors of n
/// numbers the pass hands to T and V grow as n², not n³; Eigen refuses
/// fixed-size objects above 128 kB, which a vector of 73 numbers would be.
/// Larger models take the block passes with ad::EomJet<4 kBlock, true>
/// numbers at width 2 kBlock (about 0.4 kB each: up to about 300
/// coordinates).
inline constexpr int kMaxSinglePassDof = 64;
/// Largest run-time size whose equations of motion come from one pass:
/// run-time sized models above kPaddedWidth coordinates take
/// ad::EomJet<kRunTimeCapacity, true>, numbers with room for this many
/// directions of which they use n (their width, set for the pass); larger
/// ones take the block passes with the same numbers at width 2 kBlock.
inline constexpr int kRunTimeCapacity = 64;
/// Run-time sizes up to this many take, for a model that opts in (below),
/// a pass with numbers of that fixed width, ad::EomJet<n>, as a fixed-size
/// model does.
inline constexpr int kSmallFixedWidths = 4;
/// Run-time sizes up to this many (above kSmallFixedWidths for a model
/// that opts in to fixed widths, below) take one pass with numbers of this
/// fixed width, ad::EomJet<kPaddedWidth>: their Hessians live in the
/// numbers, not in pooled blocks, and their loops have a fixed length; the
/// directions past the model's size stay zero. A run-time sized model's T
/// and V are so compiled for two number types, this one and
/// ad::EomJet<kRunTimeCapacity, true>.
inline constexpr int kPaddedWidth = 12;
/// True when a run-time sized model opts in to fixed-width passes for its
/// small sizes by declaring `static constexpr bool fixed_width_passes =
/// true;`: its T and V are then compiled for ad::EomJet<1> … <4> too, which
/// costs compile time once (a model compiled in the library, such as a text
/// model) and makes q̈ of a small model several times cheaper.
template <class M>
inline constexpr bool fixed_width_passes_v = requires {
  requires M::fixed_width_passes;
} && coordinate_count_v<M> == Dynamic;
/// True when a fixed-size model's derivatives come from passes over pairs
/// of coordinate blocks (n > kMaxSinglePassDof).
template <class M>
inline constexpr bool uses_block_passes = coordinate_count_v<M> != Dynamic && coordinate_count_v<M> > kMaxSinglePassDof;
/// Number of first-order AD directions for a model: n, or two blocks for
/// run-time sized models and block passes.
template <class M>
inline constexpr int ad_directions =
    coordinate_count_v<M> == Dynamic || uses_block_passes<M> ? 2 * kBlock : coordinate_count_v<M>;

/// R is a result a model function may give for scalar type S: convertible
/// to S and, when S is an AD number, not a plain arithmetic type (a double
/// would have dropped the derivatives S carries).
template <class R, class S>
concept scalar_result_for =
    std::convertible_to<R, S> && (std::is_arithmetic_v<S> || !std::is_arithmetic_v<std::remove_cvref_t<R>>);

// T, V and L callable on an object of type Obj (const M& as the library
// calls them, or M& to diagnose a missing const) with K-vectors of S:
// `..._callable` with any result, `..._for_object` with a result for S.
template <class Obj, class S, int K>
concept kinetic_callable = requires(Obj m, const Vec<S, K>& q, const S& t) { m.kinetic(q, q, t); };
template <class Obj, class S, int K>
concept potential_callable = requires(Obj m, const Vec<S, K>& q, const S& t) { m.potential(q, t); };
template <class Obj, class S, int K>
concept lagrangian_callable = requires(Obj m, const Vec<S, K>& q, const S& t) { m.lagrangian(q, q, t); };
template <class Obj, class S, int K>
concept kinetic_for_object = requires(Obj m, const Vec<S, K>& q, const S& t) {
  { m.kinetic(q, q, t) } -> scalar_result_for<S>;
};
template <class Obj, class S, int K>
concept potential_for_object = requires(Obj m, const Vec<S, K>& q, const S& t) {
  { m.potential(q, t) } -> scalar_result_for<S>;
};
template <class Obj, class S, int K>
concept lagrangian_for_object = requires(Obj m, const Vec<S, K>& q, const S& t) {
  { m.lagrangian(q, q, t) } -> scalar_result_for<S>;
};

template <class M, class S>
concept has_kinetic_for = kinetic_for_object<const M&, S, coordinate_count_v<M>>;
template <class M, class S>
concept has_potential_for = potential_for_object<const M&, S, coordinate_count_v<M>>;
template <class M, class S>
concept has_lagrangian_for = lagrangian_for_object<const M&, S, coordinate_count_v<M>>;

// The AD scalars the dynamics instantiates model functions with.
template <class M>
using EomJet = std::conditional_t<
    coordinate_count_v<M> == Dynamic, ad::EomJet<kRunTimeCapacity, true>,
    std::conditional_t<uses_block_passes<M>, ad::EomJet<4 * kBlock, true>, ad::EomJet<ad_directions<M>>>>;
template <class M>
using FirstOrderJet = ad::Jet<double, ad_directions<M>, 1>;

template <class M, class S>
concept energies_for = (has_kinetic_for<M, S> && has_potential_for<M, S>) || has_lagrangian_for<M, S>;

// What check_model() asks only once a model has failed energies_for, to
// name the mistake (so a valid model pays nothing for them).

/// T and V (or L) callable with S and n-vectors, but only on a non-const model.
template <class M, class S>
concept energies_need_mutable_model =
    (kinetic_callable<M&, S, coordinate_count_v<M>> && potential_callable<M&, S, coordinate_count_v<M>>) ||
    lagrangian_callable<M&, S, coordinate_count_v<M>>;

/// True when some of T, V, L takes vectors of a size K other than the
/// model's n (K = 1 … 16, or Dynamic).
template <class M, int... K>
constexpr bool energies_take_other_size(std::integer_sequence<int, K...>) {
  constexpr int n = coordinate_count_v<M>;
  auto takes = []<int Size>(std::integral_constant<int, Size>) {
    return Size != n && (kinetic_callable<M&, double, Size> || potential_callable<M&, double, Size> ||
                         lagrangian_callable<M&, double, Size>);
  };
  return (takes(std::integral_constant<int, K + 1>{}) || ...) || takes(std::integral_constant<int, Dynamic>{});
}

/// T and V (or L) callable with the AD number S but giving a plain number.
template <class M, class S>
concept energies_return_plain_number =
    (kinetic_callable<const M&, S, coordinate_count_v<M>> &&
     potential_callable<const M&, S, coordinate_count_v<M>>) ||
    lagrangian_callable<const M&, S, coordinate_count_v<M>>;

}  // namespace detail

/// A model giving T and V (or L) for double and for the AD scalars.
template <class M>
concept Model = detail::declares_coordinate_count<M> && detail::energies_for<M, double> &&
                detail::energies_for<M, detail::EomJet<M>> && detail::energies_for<M, detail::FirstOrderJet<M>>;

/// True when the model gives T and V separately (so T + V can be reported).
template <class M>
inline constexpr bool has_kinetic_potential_v =
    detail::has_kinetic_for<M, double> && detail::has_potential_for<M, double>;

/// True when the model declares `static constexpr bool constant_mass_matrix
/// = true`: its kinetic energy depends on the velocities alone, at most
/// quadratically, T = ½ q̇ᵀ M q̇ + bᵀ q̇ + c with M (kg, kg·m, kg·m²), b and c
/// constant, as in Cartesian coordinates of particles. The Euler–Lagrange
/// equations are then M q̈ = −∂V/∂q + Q − ∂D/∂q̇: simulate() checks the
/// declaration and factors M once, at the run's start (T's q-derivatives
/// and mixed term zero and M unchanged at two velocities and two
/// configurations; a DynamicsError names the term otherwise), and each
/// right-hand side then takes only V's gradient and the forces, not M.
/// Used by unconstrained models and, between contacts, by models whose only
/// constraints are contacts (others solve with M each step).
template <class M>
inline constexpr bool constant_mass_matrix_v = requires { requires M::constant_mass_matrix; };

/// False when the model declares `static constexpr bool inline_passes =
/// false`: its T and V are evaluated by an interpreter of expressions (a
/// text model seen at a fixed size, text/fixed_size.hpp), so the tangent
/// flow's pass calls their operations instead of inlining all of them into
/// one function (`flatten`), which for an interpreter costs minutes of
/// compile time and gigabytes. True for every other model.
template <class M>
inline constexpr bool inline_passes_v = !requires { requires !M::inline_passes; };

/// True when the model gives non-conservative generalized forces Q(q, q̇, t).
template <class M>
inline constexpr bool has_generalized_forces_v =
    requires(const M& m, const Vec<double, coordinate_count_v<M>>& q, double t) {
      { m.generalized_forces(q, q, t) } -> std::convertible_to<Vec<double, coordinate_count_v<M>>>;
    };

/// True when the model gives a Rayleigh dissipation function D(q, q̇).
template <class M>
inline constexpr bool has_dissipation_v = requires(const M& m,
                                                   const Vec<detail::FirstOrderJet<M>, coordinate_count_v<M>>& q) {
  { m.dissipation(q, q) } -> std::convertible_to<detail::FirstOrderJet<M>>;
};

/// True when the model's generalized forces are in effect: it declares them
/// and, if it says at run time which of its declared parts it uses
/// (`bool uses_generalized_forces() const`, as models read from text do),
/// it uses them. A declared part that is not used costs one branch per
/// right-hand side and leaves the run conservative.
template <class M>
bool uses_generalized_forces(const M& model) {
  if constexpr (!has_generalized_forces_v<M>) {
    (void)model;
    return false;
  } else if constexpr (requires { { model.uses_generalized_forces() } -> std::convertible_to<bool>; }) {
    return model.uses_generalized_forces();
  } else {
    (void)model;
    return true;
  }
}

/// True when the model's dissipation function is in effect (as
/// uses_generalized_forces(), with `bool uses_dissipation() const`).
template <class M>
bool uses_dissipation(const M& model) {
  if constexpr (!has_dissipation_v<M>) {
    (void)model;
    return false;
  } else if constexpr (requires { { model.uses_dissipation() } -> std::convertible_to<bool>; }) {
    return model.uses_dissipation();
  } else {
    (void)model;
    return true;
  }
}

/// True when the model also supplies hand-coded equations of motion
/// `void accelerations(const Vec<double, n>& q, const Vec<double, n>& qd, double t, Vec<double, n>& qdd) const`.
/// simulate() then integrates those instead of the AD-derived ones (energies,
/// momenta and reports still come from T and V). Meant for checking a
/// hand derivation against the Lagrangian and for measuring the driver's own
/// overhead; the AD path is the default and the reference.
template <class M>
inline constexpr bool has_explicit_accelerations_v =
    requires(const M& m, const Vec<double, coordinate_count_v<M>>& q, double t,
             Vec<double, coordinate_count_v<M>>& out) {
      m.accelerations(q, q, t, out);
    };

/// True when the model names its coordinates.
template <class M>
inline constexpr bool has_coordinate_names_v = requires(const M& m) {
  { m.coordinate_names() };
};

/// True when the model gives its coordinates' units.
template <class M>
inline constexpr bool has_coordinate_units_v = requires(const M& m) {
  { m.coordinate_units() };
};

/// True when the model has a name for reports (`std::string name() const`).
template <class M>
inline constexpr bool has_name_v = requires(const M& m) {
  { m.name() } -> std::convertible_to<std::string>;
};

/// A point mass of a particle system: its mass (kg) and the indices of the
/// generalized coordinates that are its Cartesian x, y, z (m); −1 for an
/// absent axis (planar or linear systems). A model that is a particle system
/// in Cartesian coordinates may declare
///   std::vector<Particle> particles() const;   (or any range of Particle)
/// and its runs report the total linear momentum P = Σ m v and the angular
/// momentum L = Σ m (r − r₀) × v about a point and their drift.
struct Particle {
  double mass = 0;
  std::array<int, 3> axes{-1, -1, -1};
};

/// True when the model declares its particles.
template <class M>
inline constexpr bool has_particles_v = requires(const M& m) {
  { *std::begin(m.particles()) } -> std::convertible_to<Particle>;
};

/// A point mass placed by a function r(q, t) of the coordinates, along a
/// path (q + δq s + ½ δ²q s², t + δt s) at s = 0: its mass (kg), r (m), and
/// dr/ds and d²r/ds². With (δq, δ²q, δt) = (q̇, q̈, 1) those are the point's
/// velocity (m/s) and acceleration (m/s²); with (u, 0, 0) dr/ds = (∂r/∂q) u.
struct PointMotion {
  double mass = 0;
  std::array<double, 3> r{}, v{}, a{};
};

/// A model whose bodies are point masses placed by functions of its
/// coordinates (a text model's [[model.points]] with a mass; the Cartesian
/// particles() above are the special case r = q) may declare
///   int mass_point_count() const;
///   void mass_points(const double* q, const double* dq, const double* ddq,
///                    double t, double dt, PointMotion* out) const;
/// (n values in each array, mass_point_count() results). When it has at
/// least one, its runs report P = Σ m v and L = Σ m (r − r₀) × v of the
/// points, which components the forces and contacts conserve, and their
/// drift, as for particles.
template <class M>
inline constexpr bool has_mass_points_v = requires(const M& m, const double* x, PointMotion* out) {
  { m.mass_point_count() } -> std::convertible_to<int>;
  m.mass_points(x, x, x, 0.0, 0.0, out);
};

/// Checks a model and stops compilation with one sentence naming what is
/// missing or wrong: no coordinate_count; no T and V (or L); T, V or L not
/// const, taking a Vec of another size than n, returning double, or not a
/// template on the scalar. Called by every public entry point that takes a
/// model.
template <class M>
constexpr void check_model() {
  static_assert(detail::declares_coordinate_count<M>,
                "lagrangian: a model must declare `static constexpr int coordinate_count = n;` (n >= 1 generalized "
                "coordinates), or `coordinate_count = lagrangian::Dynamic` together with `int size() const`");
  // At most one sentence: the first mistake found, most specific first.
  if constexpr (!detail::declares_coordinate_count<M>) {
    return;  // said above
  } else if constexpr (constexpr bool callable = detail::energies_for<M, double>; !callable) {
    if constexpr (detail::energies_need_mutable_model<M, double>) {
      static_assert(callable,
                    "lagrangian: the model's kinetic/potential/lagrangian must be const member functions: add `const` "
                    "after the parameter list, `S kinetic(...) const` (the library calls them on a const model)");
    } else if constexpr (detail::energies_take_other_size<M>(std::make_integer_sequence<int, 16>{})) {
      static_assert(callable,
                    "lagrangian: the model's kinetic/potential/lagrangian take a Vec<S, k> whose size k is not the "
                    "model's coordinate_count n: declare the parameters as `const Vec<S, n>&` with n = "
                    "coordinate_count");
    } else {
      static_assert(callable,
                    "lagrangian: a model must define `template <class S> S kinetic(const Vec<S, n>& q, const Vec<S, "
                    "n>& qd, const S& t) const` and `template <class S> S potential(const Vec<S, n>& q, const S& t) "
                    "const`, or a direct `lagrangian(q, qd, t)`; none was found callable with double");
    }
  } else if constexpr (constexpr bool differentiable = detail::energies_for<M, detail::EomJet<M>> &&
                                                      detail::energies_for<M, detail::FirstOrderJet<M>>;
                       !differentiable) {
    if constexpr (detail::energies_return_plain_number<M, detail::EomJet<M>> ||
                  detail::energies_return_plain_number<M, detail::FirstOrderJet<M>>) {
      static_assert(differentiable,
                    "lagrangian: the model's kinetic/potential/lagrangian must return the scalar type S, not double: "
                    "write `template <class S> S kinetic(...) const` (with automatic-differentiation scalars a "
                    "double result would drop the derivatives)");
    } else {
      static_assert(differentiable,
                    "lagrangian: the model's kinetic/potential/lagrangian must be templates on the scalar type S "
                    "(they are called with automatic-differentiation scalars, not only with double)");
    }
  }
}

/// Number of coordinates of a model: coordinate_count_v, or `size()` for a run-time sized model.
template <class M>
int model_size(const M& model) {
  if constexpr (coordinate_count_v<M> == Dynamic) {
    return static_cast<int>(model.size());
  } else {
    (void)model;
    return coordinate_count_v<M>;
  }
}

/// Names of the coordinates of a model: the model's own, or q0, q1, ….
template <class M>
std::vector<std::string> coordinate_names(const M& model) {
  std::vector<std::string> names;
  if constexpr (has_coordinate_names_v<M>) {
    for (const auto& s : model.coordinate_names()) names.emplace_back(s);
  } else {
    for (int i = 0; i < model_size(model); ++i) names.push_back("q" + std::to_string(i));
  }
  return names;
}

/// Units of the coordinates of a model: the model's own, or "" for each
/// (not known).
template <class M>
std::vector<std::string> coordinate_units(const M& model) {
  std::vector<std::string> units;
  if constexpr (has_coordinate_units_v<M>) {
    for (const auto& s : model.coordinate_units()) units.emplace_back(s);
  } else {
    units.resize(static_cast<std::size_t>(model_size(model)));
  }
  return units;
}

namespace detail {
/// The C++ type's name as written, without its namespaces ("MyPendulum",
/// "PendulumChain<10>"), from the compiler's type information
/// (src/core/type_name.cpp).
std::string type_display_name(const std::type_info& type);
}  // namespace detail

/// Name of a model for reports: the model's own name(), or else its C++
/// type's name without namespaces.
template <class M>
std::string model_name(const M& model) {
  if constexpr (has_name_v<M>) {
    return model.name();
  } else {
    return detail::type_display_name(typeid(M));
  }
}

/// Placeholder for an absent optional member (of a LambdaModel, make_model.hpp,
/// and of the library's own per-model state).
struct None {};

/// True when the model opts in to the structure-preserving method of
/// simulate() that is compiled per model: `variational`, the variational
/// integrator, which works on L itself (a second-order AD pass over the
/// discrete Lagrangian, fixed-size Newton solves), about 60 % of a model's
/// compile time and growing as (2n)² (docs/performance.md); so it is
/// compiled for a model only when the model asks for it. Every other method
/// runs in the driver compiled once in the library and needs no opt-in (the
/// symplectic steppers included: they need only q̈). Three ways:
/// \code
/// struct MyModel { static constexpr bool structure_preserving = true; ... };
/// auto m = lagrangian::with_structure_preserving(make_model<1>(...));
/// template <> inline constexpr bool lagrangian::structure_preserving_v<Other> = true;
/// \endcode
/// The built-in models opt in inside the library (integrate/detail/compiled_models.hpp).
/// Choosing one of these methods for a model that did not opt in is an
/// OptionError that says how to opt in.
template <class M>
inline constexpr bool structure_preserving_v = requires { requires M::structure_preserving; };

/// A model M that opts in to the structure-preserving methods; see
/// with_structure_preserving().
template <class M>
struct StructurePreserving : M {
  static constexpr bool structure_preserving = true;
  explicit StructurePreserving(M model) : M(std::move(model)) {}
};

/// The model, opted in to the structure-preserving methods of simulate()
/// (see structure_preserving_v).
template <class M>
StructurePreserving<M> with_structure_preserving(M model) {
  return StructurePreserving<M>(std::move(model));
}

/// True when M is a model wrapped by lagrangian::inlined() (inlined.hpp):
/// simulate() then runs the explicit methods compiled for M with its q̈
/// inlined into the stepper's stages, instead of the loops compiled once in
/// the library.
template <class M>
inline constexpr bool inline_rhs_v = requires { typename M::inlined_model; };

/// A state of a model with n coordinates: positions q and velocities q̇,
/// zero-initialised. Run-time sized states are built with State(n).
template <int N>
struct State {
  Vec<double, N> q;   ///< generalized coordinates
  Vec<double, N> qd;  ///< generalized velocities
  State()
    requires(N != Dynamic)
      : q(Vec<double, N>::Zero()), qd(Vec<double, N>::Zero()) {}
  explicit State(int n) : q(Vec<double, N>::Zero(n)), qd(Vec<double, N>::Zero(n)) {}
};

/// True when the model knows its motion in closed form:
///   State<n> reference(const State<n>& initial, double t) const;
/// gives the exact state at time t of the motion that starts from `initial`
/// at t0 = 0; runs then report their true error against it.
template <class M>
inline constexpr bool has_reference_v = requires(const M& m, const State<coordinate_count_v<M>>& s) {
  { m.reference(s, 0.0) } -> std::convertible_to<State<coordinate_count_v<M>>>;
};


namespace detail {
// Which constraint functions a model declares (their rows are counted in
// constraints.hpp; dynamics.hpp needs only whether there are any).
template <class M>
concept has_holonomic_c = requires(const M& m, const Vec<double, coordinate_count_v<M>>& q, double t) {
  { m.holonomic(q, t) };
};
template <class M>
concept has_pfaffian_c = requires(const M& m, const Vec<double, coordinate_count_v<M>>& q, double t) {
  { m.pfaffian(q, q, t) };
};
template <class M>
concept has_unilateral_c = requires(const M& m, const Vec<double, coordinate_count_v<M>>& q, double t) {
  { m.unilateral(q, t) };
};
template <class M>
concept declares_constraints_c = has_holonomic_c<M> || has_pfaffian_c<M> || has_unilateral_c<M>;
/// A model that counts its constraints at run time (constraints.hpp) and
/// may have none.
template <class M>
concept counts_constraints_at_run_time_c = requires(const M& m) { m.holonomic_count(); } ||
                                           requires(const M& m) { m.pfaffian_count(); } ||
                                           requires(const M& m) { m.unilateral_count(); };
/// The constraint rows such a model has now.
template <class M>
int run_time_constraint_rows(const M& m) {
  int rows = 0;
  if constexpr (requires { m.holonomic_count(); }) rows += m.holonomic_count();
  if constexpr (requires { m.pfaffian_count(); }) rows += m.pfaffian_count();
  if constexpr (requires { m.unilateral_count(); }) rows += m.unilateral_count();
  return rows;
}
}  // namespace detail

}  // namespace lagrangian

// Quick models from generic lambdas: make_model(), with_forces(), with_dissipation().
#include "lagrangian/make_model.hpp"
