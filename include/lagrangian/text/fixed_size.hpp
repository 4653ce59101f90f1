#pragma once
/// \file text/fixed_size.hpp
/// A text model of N coordinates seen as a model with coordinate_count = N:
/// the same expressions (T, V, and Q and D when the definition gives them),
/// evaluated on vectors of N numbers. What is derived only for models of a
/// fixed size — the tangent flow of analysis/tangent_flow.hpp, and with it
/// Lyapunov exponents, Floquet multipliers and sensitivities — then applies
/// to a text model whose size is known once it is read (text/tangent_flow.hpp
/// picks N from the model's size).
///
/// \code
/// const lagrangian::text::TextModel pendulum(definition);  // two coordinates
/// const lagrangian::text::FixedSizeModel<2> fixed(pendulum);
/// lagrangian::state_jacobian(fixed, q, qd, t, qdd, jacobian);
/// \endcode
///
/// Constraints and contacts are not carried over: a FixedSizeModel is built
/// only from a text model that declares none (AnalysisError otherwise).

#include <string>
#include <vector>

#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/text/evaluate.hpp"
#include "lagrangian/text/text_model.hpp"

namespace lagrangian::text {

/// The text model `model` (which must outlive this view) as a model of N
/// coordinates: T (J), V (J), Q (N or N·m per coordinate) and D (W) are the
/// model's expressions.
template <int N>
class FixedSizeModel {
 public:
  static_assert(N >= 1, "text::FixedSizeModel: at least one coordinate");
  static constexpr int coordinate_count = N;

  /// AnalysisError unless `model` has N coordinates and neither constraints
  /// nor contacts.
  explicit FixedSizeModel(const TextModel& model) : p_(&model.parsed()) {
    if (model.size() != N)
      throw AnalysisError("text::FixedSizeModel<" + std::to_string(N) + ">: the text model has " +
                          std::to_string(model.size()) + " coordinates");
    const int rows = model.holonomic_count() + model.pfaffian_count();
    if (rows > 0 || model.unilateral_count() > 0)
      throw AnalysisError("text::FixedSizeModel: the text model declares " + std::to_string(rows) +
                          " constraint rows and " + std::to_string(model.unilateral_count()) +
                          " contacts; only an unconstrained model is seen at a fixed size");
  }

  std::string name() const { return p_->definition.name; }
  const std::vector<std::string>& coordinate_names() const { return p_->definition.coordinates; }

  /// T (J).
  template <class S>
  S kinetic(const Vec<S, N>& q, const Vec<S, N>& qd, const S& t) const {
    return evaluate(p_->kinetic_bound, q, qd, t, detail::slots<S>());
  }
  /// V (J).
  template <class S>
  S potential(const Vec<S, N>& q, const S& t) const {
    return evaluate(p_->potential_bound, q, q, t, detail::slots<S>());
  }
  /// Whether the definition gives Q and D (as TextModel).
  bool uses_generalized_forces() const { return p_->has_forces; }
  bool uses_dissipation() const { return p_->has_dissipation; }
  /// Q (N or N·m per coordinate); zero when the definition gives none.
  template <class S>
  Vec<S, N> generalized_forces(const Vec<S, N>& q, const Vec<S, N>& qd, const S& t) const {
    Vec<S, N> out;
    for (int i = 0; i < N; ++i)
      out[i] = p_->has_forces ? evaluate(p_->forces_bound[static_cast<std::size_t>(i)], q, qd, t, detail::slots<S>())
                              : S(0.0);
    return out;
  }
  /// Rayleigh D (W); zero when the definition gives none.
  template <class S>
  S dissipation(const Vec<S, N>& q, const Vec<S, N>& qd) const {
    return evaluate(p_->dissipation_bound, q, qd, S(0.0), detail::slots<S>());
  }

 private:
  const Parsed* p_;
};

}  // namespace lagrangian::text
