#pragma once
/// \file constraint_state.hpp
/// The velocity-level constraint data at a state (C, g, ġ, γ) by AD, and
/// the rows of inactive contacts left out.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/ad.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/active_set.hpp"
#include "lagrangian/mechanics/constraint_counts.hpp"
#include "lagrangian/mechanics/constraint_names.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// The velocity-level constraint data at a state, for m = mh + mp rows.
template <int N, int C>
struct ConstraintState {
  Eigen::Matrix<double, C, N> jacobian;  ///< C: rows ∂g/∂q (holonomic) then A = ∂φ/∂q̇ (Pfaffian)
  Vec<double, C> position;               ///< g(q, t) for holonomic rows, 0 for Pfaffian rows
  Vec<double, C> velocity;               ///< ġ = G q̇ + ∂g/∂t, and φ = A q̇ + a
  Vec<double, C> gamma;                  ///< γ: C q̈ + γ = 0
};

namespace detail {
/// The rows of one constraint function, checked against the model's count.
template <class R>
void check_rows(const R& rows, int expected, const char* function) {
  if constexpr (std::decay_t<R>::RowsAtCompileTime != Dynamic) return;  // (the type says it)
  if (static_cast<int>(rows.size()) != expected)
    throw ConstraintError(std::string(function) + " returned " + std::to_string(rows.size()) + " values for " +
                          std::to_string(expected) + " constraints");
}
}  // namespace detail

namespace detail {

/// Position-level rows `offset` … `offset + rows` (holonomic or unilateral,
/// given by `fn(q, t)`, named `function` in messages) into `cs`: g and
/// G = ∂g/∂q from first-order passes, ġ and γ from one second-order pass
/// along (q̇, 1).
template <class M, class CS, class Fn>
void position_rows_into(const Vec<double, coordinate_count_v<M>>& q, const Vec<double, coordinate_count_v<M>>& qd,
                        double t, CS& cs, int offset, int rows, const char* function, Fn&& fn) {
  constexpr int n = coordinate_count_v<M>;
  const int size = static_cast<int>(q.size());
  if constexpr (n == Dynamic) {
    using J1 = detail::FirstOrderJet<M>;
    constexpr int w = detail::ad_directions<M>;
    auto& qj = detail::jet_vector<J1>(0, size);
    for (int k = 0; k < size; ++k) qj[k] = J1(q[k]);
    for (int start = 0; start < std::max(size, 1); start += w) {
      const int end = std::min(size, start + w);
      for (int k = start; k < end; ++k) qj[k] = J1::variable(q[k], k - start);
      const auto g1 = fn(qj, J1(t));
      detail::check_rows(g1, rows, function);
      for (int i = 0; i < rows; ++i) {
        cs.position[offset + i] = g1[i].v;
        for (int k = start; k < end; ++k) cs.jacobian(offset + i, k) = g1[i].g[k - start];
      }
      for (int k = start; k < end; ++k) qj[k] = J1(q[k]);
    }
  } else {
    using J1 = ad::Jet<double, n, 1>;
    Vec<J1, n> qj;
    for (int k = 0; k < n; ++k) qj[k] = J1::variable(q[k], k);
    const auto g1 = fn(qj, J1(t));
    for (int i = 0; i < rows; ++i) {
      cs.position[offset + i] = g1[i].v;
      for (int k = 0; k < n; ++k) cs.jacobian(offset + i, k) = g1[i].g[k];
    }
  }
  // Path derivatives: a second-order Jet in the single direction (q̇, 1).
  using J2 = ad::Jet<double, 1, 2>;
  std::optional<Vec<J2, n>> local;
  auto& qp = detail::jet_storage<J2>(local, 0, size);
  J2 tp;
  ad::along_path(q, qd, t, qp, tp);
  const auto g2 = fn(qp, tp);
  detail::check_rows(g2, rows, function);
  for (int i = 0; i < rows; ++i) {
    cs.velocity[offset + i] = g2[i].g[0];
    cs.gamma[offset + i] = g2[i].hess(0, 0);
  }
}

/// The `mp` Pfaffian rows φ = A q̇ + a from row `mpos` on into `cs`: φ,
/// A = ∂φ/∂q̇ and γ = ∂φ/∂q q̇ + ∂φ/∂t at fixed q̇.
template <class M, class CS>
void pfaffian_rows_into(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                        const Vec<double, coordinate_count_v<M>>& qd, double t, CS& cs, int mpos, int mp) {
  constexpr int n = coordinate_count_v<M>;
  const int size = static_cast<int>(q.size());
  if constexpr (n == Dynamic) {
    // A = ∂φ/∂q̇ (and φ) by first-order passes over blocks of q̇ ...
    using J1 = detail::FirstOrderJet<M>;
    constexpr int w = detail::ad_directions<M>;
    auto& qj = detail::jet_vector<J1>(0, size);
    auto& qdj = detail::jet_vector<J1>(1, size);
    for (int k = 0; k < size; ++k) {
      qj[k] = J1(q[k]);
      qdj[k] = J1(qd[k]);
    }
    for (int start = 0; start < std::max(size, 1); start += w) {
      const int end = std::min(size, start + w);
      for (int k = start; k < end; ++k) qdj[k] = J1::variable(qd[k], k - start);
      const auto phi = model.pfaffian(qj, qdj, J1(t));
      detail::check_rows(phi, mp, "pfaffian()");
      for (int i = 0; i < mp; ++i) {
        cs.velocity[mpos + i] = phi[i].v;
        for (int k = start; k < end; ++k) cs.jacobian(mpos + i, k) = phi[i].g[k - start];
      }
      for (int k = start; k < end; ++k) qdj[k] = J1(qd[k]);
    }
    // ... and γ = ∂φ/∂q q̇ + ∂φ/∂t at fixed q̇ by one pass along (q̇, 1).
    using J = ad::Jet<double, 1, 1>;
    auto& qp = detail::jet_vector<J>(0, size);
    auto& qdp = detail::jet_vector<J>(1, size);
    for (int k = 0; k < size; ++k) qdp[k] = J(qd[k]);
    J tp;
    ad::along_path(q, qd, t, qp, tp);
    const auto phi = model.pfaffian(qp, qdp, tp);
    detail::check_rows(phi, mp, "pfaffian()");
    for (int i = 0; i < mp; ++i) cs.gamma[mpos + i] = phi[i].g[0];
  } else {
    using J = ad::EomJet<n>;
    Vec<J, n> qj, qdj;
    for (int k = 0; k < n; ++k) {
      qj[k] = J::position(q[k], qd[k], k);
      qdj[k] = J::velocity(qd[k], k);
    }
    const auto phi = model.pfaffian(qj, qdj, J::time(t));
    detail::check_rows(phi, mp, "pfaffian()");
    for (int i = 0; i < mp; ++i) {
      if (phi[i].level == 2) {
        throw ConstraintError("Pfaffian constraint " + constraint_names(model)[static_cast<std::size_t>(mpos + i)] +
                              " is not affine in the velocities (A(q, t) qd + a(q, t) is required)");
      }
      cs.velocity[mpos + i] = phi[i].v;
      for (int k = 0; k < n; ++k) cs.jacobian(mpos + i, k) = phi[i].grad_qd(k);
      cs.gamma[mpos + i] = phi[i].d;  // ∂φ/∂q q̇ + ∂φ/∂t at fixed q̇
    }
  }
}

}  // namespace detail

/// Evaluates g, G, ġ, γ (holonomic) and φ, A, β (Pfaffian) by AD into `cs`,
/// sized to the model's rows (nothing allocated when `cs` has those sizes
/// already). For a run-time sized model (n = Dynamic) the Jacobians come
/// from first-order passes over blocks of coordinates, and a Pfaffian
/// row's affinity in q̇ is the model's to ensure (a text model checks it
/// when read); a fixed-size model's is checked here.
template <class M, class CS>
void constraint_state_into(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                           const Vec<double, coordinate_count_v<M>>& qd, double t, CS& cs) {
  const int size = static_cast<int>(q.size());
  const int mh = holonomic_count(model);
  const int mu = unilateral_count(model);
  const int mp = pfaffian_count(model);
  const int mpos = mh + mu;
  cs.jacobian.setZero(mpos + mp, size);
  cs.position.setZero(mpos + mp);
  cs.velocity.resize(mpos + mp);
  cs.gamma.resize(mpos + mp);
  if constexpr (holonomic_count_v<M> != 0) {
    if (mh > 0)
      detail::position_rows_into<M>(q, qd, t, cs, 0, mh, "holonomic()",
                                    [&](const auto& qq, const auto& tt) { return model.holonomic(qq, tt); });
  }
  if constexpr (unilateral_count_v<M> != 0) {
    if (mu > 0)
      detail::position_rows_into<M>(q, qd, t, cs, mh, mu, "unilateral()",
                                    [&](const auto& qq, const auto& tt) { return model.unilateral(qq, tt); });
  }
  if constexpr (pfaffian_count_v<M> != 0) {
    if (mp > 0) detail::pfaffian_rows_into(model, q, qd, t, cs, mpos, mp);
  }
}

/// Evaluates g, G, ġ, γ (holonomic) and φ, A, β (Pfaffian) by AD.
template <class M>
ConstraintState<coordinate_count_v<M>, constraint_count_v<M>> constraint_state(const M& model,
                                                                               const Vec<double, coordinate_count_v<M>>& q,
                                                                               const Vec<double, coordinate_count_v<M>>& qd,
                                                                               double t) {
  ConstraintState<coordinate_count_v<M>, constraint_count_v<M>> cs;
  constraint_state_into(model, q, qd, t, cs);
  return cs;
}

/// Zeroes the rows of inactive unilateral constraints, which then carry no
/// force (their multipliers come out zero).
template <class M, class CS>
void drop_inactive(const M& model, CS& cs, const ActiveSet& active) {
  if constexpr (unilateral_count_v<M> != 0) {
    const int mh = holonomic_count(model), mu = unilateral_count(model);
    for (int j = 0; j < mu; ++j) {
      if (!active.contains(j)) {
        const int r = mh + j;
        cs.jacobian.row(r).setZero();
        cs.position[r] = cs.velocity[r] = cs.gamma[r] = 0.0;
      }
    }
  } else {
    (void)model, (void)cs, (void)active;
  }
}
/// The same for a model whose constraint counts are known at compile time.
template <class M, class CS>
void drop_inactive(CS& cs, const ActiveSet& active) {
  static_assert(!runtime_constraint_counts_v<M>, "lagrangian: use drop_inactive(model, cs, active)");
  if constexpr (unilateral_count_v<M> > 0) {
    for (int j = 0; j < unilateral_count_v<M>; ++j) {
      if (!active.contains(j)) {
        const int r = holonomic_count_v<M> + j;
        cs.jacobian.row(r).setZero();
        cs.position[r] = cs.velocity[r] = cs.gamma[r] = 0.0;
      }
    }
  } else {
    (void)cs, (void)active;
  }
}

}  // namespace lagrangian
