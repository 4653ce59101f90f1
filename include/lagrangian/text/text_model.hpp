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
#include "lagrangian/detail/compiled_models.hpp"
#include "lagrangian/dynamics.hpp"
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
  bool has_forces = false, has_dissipation = false;
  /// Each point's x, y and z, bound (functions of q and t).
  std::vector<std::array<Expression, 3>> points;
};

/// Reads and checks a definition: names (valid, distinct, not a function,
/// `t` or `pi`), units (none or one per coordinate), finite parameters, one
/// force per coordinate, V and D free of q̇ and D free of t, every
/// expression well formed. Throws ExpressionError naming the field.
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

}  // namespace detail

/// A model stated as text (see the file comment).
class TextModel {
 public:
  static constexpr int coordinate_count = Dynamic;

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
  /// Rayleigh D (W); zero when the definition gives none.
  template <class S>
  S dissipation(const Vec<S, Dynamic>& q, const Vec<S, Dynamic>& qd) const {
    return evaluate(p_->dissipation_bound, q, qd, S(0.0), detail::slots<S>());
  }

 private:
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
