#pragma once
/// \file text/text_model.hpp
/// A model stated as text: coordinates, T and V (and optionally generalized
/// forces Q and a Rayleigh dissipation D) as expressions of q, q̇, t and named
/// parameters (text/expression.hpp), read once when the model is built and
/// evaluated on the library's own number types, so p = ∂L/∂q̇, M, the mixed
/// term and q̈ come from the same automatic differentiation as for a C++
/// model. A text model is a run-time sized model (coordinate_count =
/// Dynamic) and works with simulate(), dof_report(), equilibria, modes and
/// the boundary-value problem like any other.
///
/// \code
/// lagrangian::text::Definition d;
/// d.coordinates = {"theta", "phi"};
/// d.kinetic = "0.5*m*l^2*(theta_dot^2 + sin(theta)^2*phi_dot^2)";
/// d.potential = "-m*g*l*cos(theta)";
/// d.parameters = {{"m", 1.0}, {"l", 1.0}, {"g", 9.81}};
/// const lagrangian::text::TextModel pendulum(d);
/// \endcode
///
/// Q and D are optional: a model whose definition gives neither runs as a
/// conservative model, its energy monitored, and pays for neither (the
/// library asks `uses_generalized_forces()` and `uses_dissipation()` at run
/// time).

#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/ad/eom_jet.hpp"
#include "lagrangian/integrate/detail/compiled_models.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/text/definition.hpp"
#include "lagrangian/text/evaluate.hpp"
#include "lagrangian/text/expression.hpp"

namespace lagrangian::text {

/// A definition read: its expressions parsed (as written, for display) and
/// bound to the parameter values (for evaluation).
struct Parsed {
  Definition definition;
  Symbols symbols;
  Expression kinetic, potential, dissipation;  ///< as written
  std::vector<Expression> forces;
  Expression kinetic_bound, potential_bound, dissipation_bound;  ///< parameters replaced by their values
  std::vector<Expression> forces_bound;
  std::vector<Expression> holonomic, pfaffian, gaps;                    ///< as written
  std::vector<Expression> holonomic_bound, pfaffian_bound, gaps_bound;  ///< parameters replaced by their values
  bool has_forces = false, has_dissipation = false;
  /// Each point's x, y and z, bound (functions of q and t).
  std::vector<std::array<Expression, 3>> points;
};

/// Reads and checks a definition: names (valid, distinct, not a function,
/// `t` or `pi`), units (none or one per coordinate), finite parameters, one
/// force per coordinate, V, D and the holonomic constraints free of q̇, D
/// free of t, each Pfaffian row affine in q̇, every expression well formed.
/// Throws ExpressionError naming the field.
std::shared_ptr<const Parsed> read(const Definition& d);

namespace detail {

/// This thread's slots for evaluating expressions on S (allocated once per
/// thread and number type, grown only for a longer expression).
template <class S>
std::vector<S>& slots() {
  struct Holder {
    std::vector<S> v;
    Holder() {
      if constexpr (requires { S::prepare_thread(); }) S::prepare_thread();
    }
  };
  thread_local Holder h;
  return h.v;
}

/// The values of the expressions `es` (a kind of constraint row: 0
/// holonomic, 1 contacts, 2 Pfaffian) at (q, q̇, t) on numbers S, into this
/// thread's vector for that kind, S and vector type QV: no allocation per
/// call; the values hold until the next call with the same kind, S and QV
/// on this thread. `parameters`, for expressions that keep parameters
/// (text::evaluate()): their values as numbers of type S.
template <class S, class QV, class P = double>
Eigen::Map<const Vec<S, Dynamic>> constraint_rows(int kind, const std::vector<Expression>& es, const QV& q,
                                                  const QV& qd, const S& t, const P* parameters = nullptr) {
  thread_local Vec<S, Dynamic> vectors[3];
  Vec<S, Dynamic>& out = vectors[kind];
  const int m = static_cast<int>(es.size());
  if (out.size() < m) out.resize(m);
  for (int i = 0; i < m; ++i) out[i] = evaluate(es[static_cast<std::size_t>(i)], q, qd, t, slots<S>(), parameters);
  return {out.data(), m};
}

}  // namespace detail

/// A model stated as text (see the file comment). Its constraints are
/// counted at run time (holonomic_count(), unilateral_count(),
/// pfaffian_count()); a definition without any runs as an unconstrained
/// model.
class TextModel {
 public:
  static constexpr int coordinate_count = Dynamic;
  /// Up to four coordinates, q̈ comes from passes of fixed width (the text
  /// model is compiled once, in the library).
  static constexpr bool fixed_width_passes = true;

  /// Reads `d` (throws ExpressionError naming the field).
  explicit TextModel(const Definition& d) : TextModel(read(d)) {}
  explicit TextModel(std::shared_ptr<const Parsed> p) : p_(std::move(p)) {}

  int size() const { return static_cast<int>(p_->definition.coordinates.size()); }
  std::string name() const { return p_->definition.name; }
  const std::vector<std::string>& coordinate_names() const { return p_->definition.coordinates; }
  std::vector<std::string> coordinate_units() const {
    return p_->definition.units.empty() ? std::vector<std::string>(p_->definition.coordinates.size())
                                        : p_->definition.units;
  }
  /// The definition as read.
  const Parsed& parsed() const { return *p_; }
  /// The same, shared (a view that must not outlive it holds this).
  const std::shared_ptr<const Parsed>& shared_parsed() const { return p_; }

  /// T (J).
  template <class S>
  S kinetic(const Vec<S, Dynamic>& q, const Vec<S, Dynamic>& qd, const S& t) const {
    return evaluate(p_->kinetic_bound, q, qd, t, detail::slots<S>());
  }
  /// V (J).
  template <class S>
  S potential(const Vec<S, Dynamic>& q, const S& t) const {
    return evaluate(p_->potential_bound, q, q, t, detail::slots<S>());
  }

  /// Whether the definition gives Q and D: a run of a model without them
  /// skips both passes and is conservative (see uses_generalized_forces()).
  bool uses_generalized_forces() const { return p_->has_forces; }
  bool uses_dissipation() const { return p_->has_dissipation; }
  /// Q (N or N·m per coordinate), into a per-thread vector (no allocation
  /// per call); zero when the definition gives none.
  Eigen::Map<const Eigen::VectorXd> generalized_forces(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                                      double t) const {
    thread_local Eigen::VectorXd out;
    const int n = size();
    if (out.size() < n) out.resize(n);
    for (int i = 0; i < n; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      out[i] = p_->has_forces ? evaluate(p_->forces_bound[k], q, qd, t, detail::slots<double>()) : 0.0;
    }
    return {out.data(), n};
  }
  /// Holonomic constraints g(q, t) = 0 and their count; the values go to a
  /// per-thread vector (no allocation per call).
  int holonomic_count() const { return static_cast<int>(p_->holonomic_bound.size()); }
  template <class S>
  Eigen::Map<const Vec<S, Dynamic>> holonomic(const Vec<S, Dynamic>& q, const S& t) const {
    return detail::constraint_rows<S>(0, p_->holonomic_bound, q, q, t);
  }
  /// Contacts: gaps φ(q, t) ≥ 0, their count and restitution coefficients.
  int unilateral_count() const { return static_cast<int>(p_->gaps_bound.size()); }
  template <class S>
  Eigen::Map<const Vec<S, Dynamic>> unilateral(const Vec<S, Dynamic>& q, const S& t) const {
    return detail::constraint_rows<S>(1, p_->gaps_bound, q, q, t);
  }
  std::vector<double> restitution() const {
    std::vector<double> e;
    for (const Contact& c : p_->definition.contacts) e.push_back(c.restitution);
    return e;
  }
  std::vector<std::string> unilateral_names() const {
    std::vector<std::string> out;
    const auto& contacts = p_->definition.contacts;
    for (std::size_t j = 0; j < contacts.size(); ++j)
      out.push_back(contacts[j].name.empty() ? "u" + std::to_string(j) : contacts[j].name);
    return out;
  }
  /// The constraints' names (given, or g0, …, a0, …) and units ("" when none given).
  std::vector<std::string> holonomic_names() const { return names(0, holonomic_count(), "g"); }
  std::vector<std::string> pfaffian_names() const { return names(holonomic_count(), pfaffian_count(), "a"); }
  /// In the library's order: holonomic, contacts, Pfaffian.
  std::vector<std::string> constraint_units() const {
    const Definition& d = p_->definition;
    auto given = [&](std::size_t i) { return d.constraint_units.empty() ? std::string() : d.constraint_units[i]; };
    std::vector<std::string> out;
    for (std::size_t i = 0; i < d.holonomic.size(); ++i) out.push_back(given(i));
    for (const Contact& c : d.contacts) out.push_back(c.unit);
    for (std::size_t i = 0; i < d.pfaffian.size(); ++i) out.push_back(given(d.holonomic.size() + i));
    return out;
  }
  /// Pfaffian constraints φ(q, q̇, t) = A q̇ + a = 0 and their count.
  int pfaffian_count() const { return static_cast<int>(p_->pfaffian_bound.size()); }
  template <class S>
  Eigen::Map<const Vec<S, Dynamic>> pfaffian(const Vec<S, Dynamic>& q, const Vec<S, Dynamic>& qd, const S& t) const {
    return detail::constraint_rows<S>(2, p_->pfaffian_bound, q, qd, t);
  }

  /// The points of [[model.points]] with a mass, in their order: what the
  /// momentum monitor sums (model.hpp, has_mass_points_v). mass_points()
  /// writes each one's mass, r(q, t) and the first and second derivatives
  /// of r along (q + dq s + ½ ddq s², t + dt s) at s = 0 (ddq null for
  /// zero), from one second-order pass in one direction (src/text/points.cpp).
  int mass_point_count() const;
  void mass_points(const double* q, const double* dq, const double* ddq, double t, double dt,
                   PointMotion* out) const;

  /// Rayleigh D (W); zero when the definition gives none.
  template <class S>
  S dissipation(const Vec<S, Dynamic>& q, const Vec<S, Dynamic>& qd) const {
    return evaluate(p_->dissipation_bound, q, qd, S(0.0), detail::slots<S>());
  }

 private:
  std::vector<std::string> names(int from, int count, const char* prefix) const {
    const auto& given = p_->definition.constraint_names;
    std::vector<std::string> out;
    for (int i = 0; i < count; ++i)
      out.push_back(given.empty() ? prefix + std::to_string(i) : given[static_cast<std::size_t>(from + i)]);
    return out;
  }
  std::shared_ptr<const Parsed> p_;
};

}  // namespace lagrangian::text

// simulate() and the Euler–Lagrange pass of the text models are compiled
// once, in the library (src/text/).
#define LAGRANGIAN_TEXT_EOM_PASS(...)                                                               \
  void lagrangian::detail::eom_pass_large<__VA_ARGS__>(                                                    \
      const __VA_ARGS__&, ::lagrangian::Workspace<::lagrangian::Dynamic>&,                                 \
      const ::lagrangian::Vec<double, ::lagrangian::Dynamic>&, const ::lagrangian::Vec<double, ::lagrangian::Dynamic>&, \
      double);
#if !(defined(LAGRANGIAN_TRAP_FE_INVALID) && LAGRANGIAN_TRAP_FE_INVALID)
extern template LAGRANGIAN_TEXT_EOM_PASS(lagrangian::text::TextModel)
#endif
LAGRANGIAN_EXTERN_SIMULATE(lagrangian::text::TextModel)
