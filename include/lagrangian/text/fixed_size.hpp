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
#include <type_traits>
#include <vector>

#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/text/evaluate.hpp"
#include "lagrangian/text/text_model.hpp"

namespace lagrangian::text {

/// The text model `model` (which must outlive this view) as a model of N
/// coordinates: T (J), V (J), Q (N or N·m per coordinate) and D (W) are the
/// model's expressions. With P = ad::Jet<double, K, 1> (with_parameter_type,
/// the seeded twin of analysis/sensitivity.hpp) the parameters are numbers
/// of type P carrying derivatives along K directions, set by seed().
template <int N, class P = double>
class FixedSizeModel {
 public:
  static_assert(N >= 1, "text::FixedSizeModel: at least one coordinate");
  static constexpr int coordinate_count = N;
  template <class Q>
  using with_parameter_type = FixedSizeModel<N, Q>;

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
    if constexpr (!std::is_same_v<P, double>)
      for (const auto& [name, value] : p_->definition.parameters) parameters_.push_back(P(value));
  }

  std::string name() const { return p_->definition.name; }
  const std::vector<std::string>& coordinate_names() const { return p_->definition.coordinates; }
  /// The parameters' names, in the definition's order.
  std::vector<std::string> parameter_names() const {
    std::vector<std::string> out;
    for (const auto& [name, value] : p_->definition.parameters) out.push_back(name);
    return out;
  }
  /// Parameter number `i` as a number of type P, its derivatives along the
  /// directions set (seeded twin only).
  P& parameter(int i)
    requires(!std::is_same_v<P, double>)
  {
    return parameters_[static_cast<std::size_t>(i)];
  }

  /// T (J).
  template <class S>
  S kinetic(const Vec<S, N>& q, const Vec<S, N>& qd, const S& t) const {
    return value(p_->kinetic, p_->kinetic_bound, q, qd, t);
  }
  /// V (J).
  template <class S>
  S potential(const Vec<S, N>& q, const S& t) const {
    return value(p_->potential, p_->potential_bound, q, q, t);
  }
  /// Whether the definition gives Q and D (as TextModel).
  bool uses_generalized_forces() const { return p_->has_forces; }
  bool uses_dissipation() const { return p_->has_dissipation; }
  /// Q (N or N·m per coordinate); zero when the definition gives none.
  template <class S>
  Vec<S, N> generalized_forces(const Vec<S, N>& q, const Vec<S, N>& qd, const S& t) const {
    Vec<S, N> out;
    for (int i = 0; i < N; ++i) {
      const std::size_t k = static_cast<std::size_t>(i);
      out[i] = p_->has_forces ? value(p_->forces[k], p_->forces_bound[k], q, qd, t) : S(0.0);
    }
    return out;
  }
  /// Rayleigh D (W); zero when the definition gives none.
  template <class S>
  S dissipation(const Vec<S, N>& q, const Vec<S, N>& qd) const {
    return value(p_->dissipation, p_->dissipation_bound, q, qd, S(0.0));
  }

 private:
  /// The expression on S: bound to the parameters' values (P = double), or
  /// as written with the parameters as numbers of type S (their values and
  /// derivatives along the directions lifted into S).
  template <class S, class QVec>
  S value(const Expression& written, const Expression& bound, const QVec& q, const QVec& qd, const S& t) const {
    if constexpr (std::is_same_v<P, double>) {
      (void)written;
      return evaluate(bound, q, qd, t, detail::slots<S>());
    } else {
      (void)bound;
      thread_local std::vector<S> lifted;
      lifted.resize(parameters_.size());
      using B = typename S::value_type;
      for (std::size_t i = 0; i < parameters_.size(); ++i) {
        lifted[i] = S(B(parameters_[i].v));
        for (int c = 0; c < P::directions; ++c) lifted[i].g[static_cast<std::size_t>(c)] = B(parameters_[i].g[c]);
      }
      return evaluate(written, q, qd, t, detail::slots<S>(), lifted.data());
    }
  }

  const Parsed* p_;
  std::vector<P> parameters_;  // (seeded twin only)
};

}  // namespace lagrangian::text
