#pragma once
/// \file make_model.hpp
/// Quick models from generic lambdas: make_model() builds a model from T
/// and V written as `const auto&` lambdas, with_forces() and
/// with_dissipation() add Q and D. Included by model.hpp.

#include <array>
#include <string>
#include <type_traits>
#include <utility>

#include "lagrangian/model.hpp"

namespace lagrangian {

/// A model assembled from generic lambdas; see make_model().
template <int N, class Kinetic, class Potential, class Forces = None, class Dissipation = None>
struct LambdaModel {
  static constexpr int coordinate_count = N;
  std::string model_name;
  std::array<std::string, N> names;
  Kinetic kinetic_fn;
  Potential potential_fn;
  [[no_unique_address]] Forces forces_fn{};
  [[no_unique_address]] Dissipation dissipation_fn{};

  std::string name() const { return model_name; }
  const std::array<std::string, N>& coordinate_names() const { return names; }

  template <class S>
  S kinetic(const Vec<S, N>& q, const Vec<S, N>& qd, const S& t) const {
    return kinetic_fn(q, qd, t);
  }
  template <class S>
  S potential(const Vec<S, N>& q, const S& t) const {
    return potential_fn(q, t);
  }
  template <class S>
    requires(!std::is_same_v<Forces, None>)
  Vec<S, N> generalized_forces(const Vec<S, N>& q, const Vec<S, N>& qd, const S& t) const {
    return forces_fn(q, qd, t);
  }
  template <class S>
    requires(!std::is_same_v<Dissipation, None>)
  S dissipation(const Vec<S, N>& q, const Vec<S, N>& qd) const {
    return dissipation_fn(q, qd);
  }
};

/// Builds a model from generic lambdas `kinetic(q, qd, t)` and
/// `potential(q, t)`; the lambdas take `const auto&` arguments.
/// \code
/// auto pendulum = lagrangian::make_model<1>("pendulum", {"theta"},
///     [](const auto& q, const auto& qd, const auto& t) { return 0.5 * qd[0] * qd[0]; },
///     [](const auto& q, const auto& t) { using std::cos; return -9.81 * cos(q[0]); });
/// \endcode
template <int N, class Kinetic, class Potential>
LambdaModel<N, Kinetic, Potential> make_model(std::string name, std::array<std::string, N> names, Kinetic kinetic,
                                              Potential potential) {
  return {std::move(name), std::move(names), std::move(kinetic), std::move(potential)};
}

/// Adds generalized forces Q(q, qd, t) (a generic lambda returning Vec<S, N>).
template <int N, class K, class V, class F, class D, class NewForces>
LambdaModel<N, K, V, NewForces, D> with_forces(LambdaModel<N, K, V, F, D> m, NewForces forces) {
  return {std::move(m.model_name), std::move(m.names), std::move(m.kinetic_fn), std::move(m.potential_fn),
          std::move(forces), std::move(m.dissipation_fn)};
}

/// Adds a Rayleigh dissipation function D(q, qd) (generic lambda), Q = −∂D/∂q̇.
template <int N, class K, class V, class F, class D, class NewDissipation>
LambdaModel<N, K, V, F, NewDissipation> with_dissipation(LambdaModel<N, K, V, F, D> m, NewDissipation d) {
  return {std::move(m.model_name), std::move(m.names), std::move(m.kinetic_fn), std::move(m.potential_fn),
          std::move(m.forces_fn), std::move(d)};
}

}  // namespace lagrangian
