#pragma once
/// \file properties.hpp
/// Properties of a model read off its Lagrangian at sampled states: cyclic
/// coordinates (conserved momenta), autonomy (∂L/∂t = 0), separability (what
/// the symplectic steppers need) and workless constraints.

#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// Indices of coordinates whose momenta are conserved: cyclic (∂L/∂q_i = 0,
/// Q_i = 0) and, for constrained models, untouched by every constraint (the
/// column i of the constraint Jacobian is zero), at the given state and time
/// and at three nearby states at later times (a fixed, deterministic
/// perturbation). This is
/// a sampled check: a coordinate that drops out of L only on those states
/// would be misreported, which is why the run reports the momentum drift so
/// the claim can be seen to hold.
template <class M>
std::vector<int> cyclic_coordinates(const M& model, const State<coordinate_count_v<M>>& s, double t = 0.0);

/// True when ∂L/∂t = 0 at the given (state, t) and at three nearby states and
/// later times (sampled check, same caveat as cyclic_coordinates()).
template <class M>
bool is_autonomous(const M& model, const State<coordinate_count_v<M>>& s, double t = 0.0);

/// True when the model declares `static constexpr bool separable`.
template <class M>
concept declares_separable = requires {
  { M::separable } -> std::convertible_to<bool>;
};

/// Why the model is not separable, or an empty string when it is: the
/// symplectic steppers need L = ½ q̇ᵀ M q̇ − V(q) with a constant mass matrix
/// M, no constraints, no generalized forces or dissipation and ∂L/∂t = 0.
/// A model may declare `static constexpr bool separable = true;` (trusted)
/// or `false`; otherwise the property is checked at the given state and at
/// three nearby states (M equal to 1e-12 relative, p = M q̇ to 1e-12
/// relative: no velocity-linear terms; sampled, like cyclic_coordinates()).
template <class M>
std::string separability_problem(const M& model, const State<coordinate_count_v<M>>& s, double t = 0.0);

namespace detail {

/// The sampled states used by cyclic_coordinates() and is_autonomous().
template <int N>
std::array<State<N>, 4> probe_states(const State<N>& s) {
  std::array<State<N>, 4> out{s, s, s, s};
  std::uint64_t lcg = 0x9E3779B97F4A7C15ull;
  auto next = [&lcg]() {
    lcg = lcg * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(lcg >> 11) * 0x1.0p-53 - 0.5;  // in [-0.5, 0.5)
  };
  for (int k = 1; k < 4; ++k) {
    out[k] = s;
    for (int i = 0; i < s.q.size(); ++i) {
      out[k].q[i] += 0.1 * next() * (1.0 + std::abs(s.q[i]));
      out[k].qd[i] += 0.1 * next() * (1.0 + std::abs(s.qd[i]));
    }
  }
  return out;
}

/// True when every constraint is scleronomic and workless: C q̇ + c has
/// c = 0 (no ∂g/∂t, no a(q, t)) at the sampled states and times.
template <class M>
bool constraints_workless(const M& model, const State<coordinate_count_v<M>>& s, double t) {
  if constexpr (!has_constraints_v<M>) {
    (void)model;
    (void)s;
    (void)t;
    return true;
  } else {
    const auto probes = probe_states(s);
    for (std::size_t k = 0; k < probes.size(); ++k) {
      const double tk = t + 0.37 * static_cast<double>(k) * (1.0 + std::abs(t));
      const auto cs =
          constraint_state(model, probes[k].q, Vec<double, coordinate_count_v<M>>::Zero(s.q.size()).eval(), tk);
      if (!cs.velocity.isZero(0.0)) return false;
    }
    return true;
  }
}
}  // namespace detail

template <class M>
std::vector<int> cyclic_coordinates(const M& model, const State<coordinate_count_v<M>>& s, double t) {
  check_model<M>();
  constexpr int n = coordinate_count_v<M>;
  const int size = static_cast<int>(s.q.size());
  std::vector<bool> cyclic(static_cast<std::size_t>(size), true);
  Workspace<n> ws(size);
  const auto probes = detail::probe_states(s);
  for (std::size_t k = 0; k < probes.size(); ++k) {
    // Later times too: a moving constraint (a rotating wire) may leave q_i
    // alone at t only.
    const State<n>& p = probes[k];
    const double tk = t + 0.37 * static_cast<double>(k) * (1.0 + std::abs(t));
    detail::eom_pass(model, ws, p.q, p.qd, tk);
    detail::force_pass(model, ws, p.q, p.qd, tk);
    for (int i = 0; i < size; ++i)
      cyclic[static_cast<std::size_t>(i)] = cyclic[static_cast<std::size_t>(i)] && ws.dL_dq[i] == 0.0 && ws.forces[i] == 0.0;
    if constexpr (has_constraints_v<M>) {
      // A constraint force along q_i changes p_i: conserved only if no constraint involves q_i.
      const auto cs = constraint_state(model, p.q, p.qd, tk);
      for (int i = 0; i < size; ++i)
        cyclic[static_cast<std::size_t>(i)] = cyclic[static_cast<std::size_t>(i)] && cs.jacobian.col(i).isZero(0.0);
    }
  }
  std::vector<int> out;
  for (int i = 0; i < size; ++i)
    if (cyclic[static_cast<std::size_t>(i)]) out.push_back(i);
  return out;
}

template <class M>
std::string separability_problem(const M& model, const State<coordinate_count_v<M>>& s, double t) {
  check_model<M>();
  if constexpr (declares_separable<M>) {
    (void)s, (void)t;
    return M::separable ? std::string() : model_name(model) + " declares separable = false";
  } else if constexpr (has_constraints_v<M> && !runtime_constraint_counts_v<M>) {
    (void)model, (void)s, (void)t;
    return "it has constraints";
  } else {
    if (has_constraints(model)) return "it has constraints";
    if (uses_generalized_forces(model) || uses_dissipation(model)) return "it has generalized forces or dissipation";
    if (!is_autonomous(model, s, t)) return "L depends explicitly on time";
    const auto m0 = mass_matrix(model, s.q, s.qd, t);
    const double scale = m0.template lpNorm<Eigen::Infinity>();
    for (const State<coordinate_count_v<M>>& p : detail::probe_states(s)) {
      const auto mp = mass_matrix(model, p.q, p.qd, t);
      if ((mp - m0).template lpNorm<Eigen::Infinity>() > 1e-12 * scale) {
        std::ostringstream os;
        os.precision(6);
        os << "the mass matrix d2L/dqd2 depends on the state (entry max change "
           << (mp - m0).template lpNorm<Eigen::Infinity>() << " of " << scale << ")";
        return os.str();
      }
      const auto mom = momenta(model, p.q, p.qd, t);
      const auto expected = (m0 * p.qd).eval();
      if ((mom - expected).template lpNorm<Eigen::Infinity>() > 1e-12 * (1.0 + expected.template lpNorm<Eigen::Infinity>()))
        return "the momenta dL/dqd are not M qd (terms linear in the velocities)";
    }
    return {};
  }
}

template <class M>
bool is_autonomous(const M& model, const State<coordinate_count_v<M>>& s, double t) {
  const auto probes = detail::probe_states(s);
  for (std::size_t k = 0; k < probes.size(); ++k) {
    const double tk = t + 0.37 * static_cast<double>(k) * (1.0 + std::abs(t));
    if (lagrangian_time_derivative(model, probes[k].q, probes[k].qd, tk) != 0.0) return false;
  }
  return true;
}

}  // namespace lagrangian
