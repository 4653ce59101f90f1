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
/// Constraints are carried over, counted at run time as the text model
/// counts them: holonomic and Pfaffian rows (the tangent flow keeps to
/// their manifold, analysis/lyapunov.hpp) and contacts (their gaps, names,
/// units and restitution coefficients: the tangent flow crosses their
/// impacts, analysis/saltation.hpp, and holds a contact shut where a plain
/// run lets it rest: hold()).

#include <algorithm>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "lagrangian/analysis/tangent_flow.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/text/evaluate.hpp"
#include "lagrangian/text/text_model.hpp"

namespace lagrangian::text {

namespace detail {
/// (q, q̇) of the text model `parsed` projected onto its constraints
/// (src/text/tangent_flow.cpp).
void project_state(const std::shared_ptr<const Parsed>& parsed, double* q, double* qd, double t);
}  // namespace detail

/// The text model `model` as a model of N coordinates: T (J), V (J), Q (N
/// or N·m per coordinate), D (W) and the constraint rows are the model's
/// expressions, bound to its parameters' values. With
/// P = ad::Jet<double, K, 1> (with_parameter_type: the seeded twin of
/// analysis/sensitivity.hpp), one parameter is a number of type P, carrying
/// derivatives along K directions, and every expression is bound to the
/// others only: a parameter that moves the holonomic or Pfaffian rows (an
/// incline's slope, a wire's rate) is differentiated through them too (the
/// rows of a model counted at run time take one direction at a time, so
/// there K = 1: analysis/tangent_flow.hpp).
template <int N, class P = double>
class FixedSizeModel {
 public:
  static_assert(N >= 1, "text::FixedSizeModel: at least one coordinate");
  static constexpr int coordinate_count = N;
  /// Its expressions are interpreted: the tangent pass calls them (model.hpp).
  static constexpr bool inline_passes = false;
  template <class Q>
  using with_parameter_type = FixedSizeModel<N, Q>;

  /// AnalysisError unless `model` has N coordinates.
  explicit FixedSizeModel(const TextModel& model)
    requires std::is_same_v<P, double>
      : p_(checked(model)) {}
  /// The twin whose parameter number `parameter` (in the definition's
  /// order) is `value`, a number of type P.
  FixedSizeModel(const TextModel& model, int parameter, const P& value)
    requires(!std::is_same_v<P, double>)
      : p_(checked(model)), parameter_(parameter), value_(value) {
    std::vector<double> values;
    for (const auto& [name, v] : p_->definition.parameters) values.push_back(v);
    kinetic_ = bind_parameters(p_->kinetic, values, parameter);
    potential_ = bind_parameters(p_->potential, values, parameter);
    dissipation_ = bind_parameters(p_->dissipation, values, parameter);
    for (const Expression& f : p_->forces) forces_.push_back(bind_parameters(f, values, parameter));
    for (const Expression& g : p_->holonomic) holonomic_.push_back(bind_parameters(g, values, parameter));
    for (const Expression& a : p_->pfaffian) pfaffian_.push_back(bind_parameters(a, values, parameter));
    for (const Expression& g : p_->gaps) gaps_.push_back(bind_parameters(g, values, parameter));
  }

  std::string name() const { return p_->definition.name; }
  const std::vector<std::string>& coordinate_names() const { return p_->definition.coordinates; }
  /// The parameters' names, in the definition's order.
  std::vector<std::string> parameter_names() const {
    std::vector<std::string> out;
    for (const auto& [name, value] : p_->definition.parameters) out.push_back(name);
    return out;
  }

  /// T (J).
  template <class S>
  S kinetic(const Vec<S, N>& q, const Vec<S, N>& qd, const S& t) const {
    return value(kinetic_, p_->kinetic_bound, q, qd, t);
  }
  /// V (J).
  template <class S>
  S potential(const Vec<S, N>& q, const S& t) const {
    return value(potential_, p_->potential_bound, q, q, t);
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
      out[i] = p_->has_forces ? value(seeded ? forces_[k] : p_->forces_bound[k], p_->forces_bound[k], q, qd, t)
                              : S(0.0);
    }
    return out;
  }
  /// Rayleigh D (W); zero when the definition gives none.
  template <class S>
  S dissipation(const Vec<S, N>& q, const Vec<S, N>& qd) const {
    return value(dissipation_, p_->dissipation_bound, q, qd, S(0.0));
  }

  /// The text model's constraints, each kind's values into a per-thread
  /// vector (one per kind and number type S: no allocation per call; the
  /// values hold until the next call of the same kind with the same S on
  /// this thread). Holonomic g(q, t) = 0 (m for lengths, rad for angles):
  /// (after them the gaps of the contacts held shut, hold()):
  int holonomic_count() const { return static_cast<int>(holonomic_rows().size()); }
  template <class S>
  Eigen::Map<const Vec<S, Dynamic>> holonomic(const Vec<S, N>& q, const S& t) const {
    return rows(0, holonomic_rows(), holonomic_rows(), q, q, t);
  }
  /// Pfaffian φ(q, q̇, t) = A q̇ + a = 0 (m/s or rad/s):
  int pfaffian_count() const { return static_cast<int>(p_->pfaffian_bound.size()); }
  template <class S>
  Eigen::Map<const Vec<S, Dynamic>> pfaffian(const Vec<S, N>& q, const Vec<S, N>& qd, const S& t) const {
    return rows(2, pfaffian_, p_->pfaffian_bound, q, qd, t);
  }
  /// Contacts, gaps φ(q, t) ≥ 0 (m or rad), with their restitution
  /// coefficients (numbers, as numbers of type P for the twin: its gaps
  /// follow its parameter, so its parameter columns cross impacts):
  int unilateral_count() const { return static_cast<int>(p_->gaps_bound.size()); }
  template <class S>
  Eigen::Map<const Vec<S, Dynamic>> unilateral(const Vec<S, N>& q, const S& t) const {
    return rows(1, gaps_, p_->gaps_bound, q, q, t);
  }
  std::vector<P> restitution() const {
    const std::vector<double> e = TextModel(p_).restitution();
    if constexpr (seeded) {
      return std::vector<P>(e.begin(), e.end());
    } else {
      return e;
    }
  }
  /// Moves (q, q̇) onto the holonomic constraints and then onto the
  /// velocity rows, as a run of the text model projects its state (through
  /// the text model itself, compiled once in the library).
  void project_state(double* q, double* qd, double t) const { detail::project_state(p_, q, qd, t); }

  /// Contact j held shut (`shut`): its gap φ_j(q, t) = 0 becomes a holonomic
  /// row after the declared ones, so the passes give the motion that keeps
  /// it shut (the tangent flow's resting contacts, analysis/lyapunov.hpp);
  /// or opened again. The seeded twin holds its own gap, which carries the
  /// parameter (a parameter's column through a rest).
  void hold(int j, bool shut) const {
    const auto at = std::find(held_.begin(), held_.end(), j);
    if (shut == (at != held_.end())) return;
    if (shut) {
      held_.push_back(j);
    } else {
      held_.erase(at);
    }
    const std::vector<Expression>& gaps = seeded ? gaps_ : p_->gaps_bound;
    held_rows_ = seeded ? holonomic_ : p_->holonomic_bound;
    for (int k : held_) held_rows_.push_back(gaps[static_cast<std::size_t>(k)]);
  }
  /// Rows of held contacts among holonomic_count()'s.
  int held_count() const { return static_cast<int>(held_.size()); }

  /// Names and units, as the text model's (a held contact's row by its name).
  std::vector<std::string> holonomic_names() const {
    std::vector<std::string> names = TextModel(p_).holonomic_names();
    const std::vector<std::string> contacts = TextModel(p_).unilateral_names();
    for (int k : held_) names.push_back(contacts[static_cast<std::size_t>(k)]);
    return names;
  }
  std::vector<std::string> pfaffian_names() const { return TextModel(p_).pfaffian_names(); }
  std::vector<std::string> unilateral_names() const { return TextModel(p_).unilateral_names(); }
  std::vector<std::string> constraint_units() const { return TextModel(p_).constraint_units(); }

 private:
  static constexpr bool seeded = !std::is_same_v<P, double>;

  /// The holonomic rows now: the declared ones, then the held gaps (the
  /// twin's own expressions, or the bound ones for P = double).
  const std::vector<Expression>& holonomic_rows() const {
    if (!held_.empty()) return held_rows_;
    return seeded ? holonomic_ : p_->holonomic_bound;
  }

  static std::shared_ptr<const Parsed> checked(const TextModel& model) {
    if (model.size() != N)
      throw AnalysisError("text::FixedSizeModel<" + std::to_string(N) + ">: the text model has " +
                          std::to_string(model.size()) + " coordinates");
    return model.shared_parsed();
  }

  /// `own` (the twin's expression, its parameter kept) with that parameter
  /// as a number of type S (lifted()), or `bound` (P = double).
  template <class S, class QVec>
  S value(const Expression& own, const Expression& bound, const QVec& q, const QVec& qd, const S& t) const {
    if constexpr (!seeded) {
      (void)own;
      return evaluate(bound, q, qd, t, detail::slots<S>());
    } else {
      (void)bound;
      return evaluate(own, q, qd, t, detail::slots<S>(), lifted<S>());
    }
  }

  /// The rows of one kind (text_model.hpp's constraint_rows()): `own` (the
  /// twin's, on q as a vector of any length, so the interpreter is compiled
  /// once per number type, not per N) or `bound` (P = double).
  template <class S>
  Eigen::Map<const Vec<S, Dynamic>> rows(int kind, const std::vector<Expression>& own,
                                         const std::vector<Expression>& bound, const Vec<S, N>& q,
                                         const Vec<S, N>& qd, const S& t) const {
    if constexpr (!seeded) {
      (void)own;
      return detail::constraint_rows<S>(kind, bound, q, qd, t);
    } else {
      (void)bound;
      using V = Eigen::Map<const Vec<S, Dynamic>>;
      return detail::constraint_rows<S>(kind, own, V(q.data(), N), V(qd.data(), N), t, lifted<S>());
    }
  }

  /// This thread's parameter values as numbers of type S, only the twin's
  /// parameter's entry set: value_ with its derivatives at the level of S
  /// that carries the K directions — S itself (S = P), the value of each of
  /// S's parts (S a Jet over P: the constraint rows' numbers, whose own
  /// derivatives are along q or the path) or S's derivatives (S a Jet over
  /// the Euler–Lagrange numbers along the directions, the tangent pass).
  template <class S>
  const S* lifted() const {
    thread_local std::vector<S> values;
    const std::size_t at = static_cast<std::size_t>(parameter_);
    if (values.size() <= at) values.resize(at + 1);
    S& x = values[at];
    if constexpr (std::is_same_v<S, P>) {
      x = value_;
    } else if constexpr (std::is_same_v<typename S::value_type, P>) {
      x = S(value_);
    } else {
      static_assert(S::directions >= P::directions, "text::FixedSizeModel: the parameter's directions are S's");
      using B = typename S::value_type;
      x = S(B(value_.v));
      for (int c = 0; c < P::directions; ++c) x.g[static_cast<std::size_t>(c)] = B(value_.g[c]);
    }
    return values.data();
  }

  std::shared_ptr<const Parsed> p_;
  // The twin's parameter, its value and the expressions bound to the others
  // (empty for P = double).
  int parameter_ = -1;
  P value_{};
  Expression kinetic_, potential_, dissipation_;
  std::vector<Expression> forces_, holonomic_, pfaffian_, gaps_;
  // Contacts held shut (hold()) and the rows with their gaps.
  mutable std::vector<int> held_;
  mutable std::vector<Expression> held_rows_;
};

}  // namespace lagrangian::text
