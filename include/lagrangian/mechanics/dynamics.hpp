#pragma once
/// \file dynamics.hpp
/// Quantities derived from a model by automatic differentiation.
///
/// For L(q, q̇, t) = T − V the Euler–Lagrange equations
///   d/dt ∂L/∂q̇ − ∂L/∂q = Q
/// expand to
///   M(q, q̇, t) q̈ = ∂L/∂q − (∂²L/∂q̇∂q) q̇ − ∂²L/∂q̇∂t + Q,     M = ∂²L/∂q̇²,
/// where Q holds the non-conservative generalized forces, including
/// Q = −∂D/∂q̇ from a Rayleigh function D. Units: M in kg (or kg·m² for
/// angles), forces in N (or N·m), q̈ in m/s² (or rad/s²).
///
/// Everything comes from one forward-mode pass over T and V (or L) with
/// ad::EomJet numbers: the n velocity directions to second order (M), the
/// single path direction (δq, δt) = (q̇, 1) mixed with them (the term
/// (∂²L/∂q̇∂q) q̇ + ∂²L/∂q̇∂t, a directional derivative, never a third-order
/// tensor), and the n position directions to first order (∂L/∂q). The
/// number type skips the parts that are structurally zero (a function of q
/// alone has no velocity derivatives; a velocity is affine in q̇).
///
/// Every function takes a const model and (in the fast form) a Workspace
/// that the caller owns; nothing is allocated on the heap per call.

#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <string>

#include <Eigen/Core>

#include "lagrangian/ad.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/detail/inlining.hpp"
#include "lagrangian/mechanics/detail/mass_cholesky.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// Scratch space and results of one dynamics evaluation for a model with n
/// coordinates. Allocate one per thread and reuse it for every call; for a
/// run-time sized model (N = Dynamic) construct it with the size.
template <int N>
struct Workspace {
  Workspace()
    requires(N != Dynamic)
  = default;
  explicit Workspace(int n) { resize(n); }
  void resize(int n) {
    mass.resize(n, n);
    cholesky.resize(n);
    for (auto* v : {&momenta, &dL_dq, &mixed, &forces, &rhs, &accelerations, &scratch_q, &scratch_qd, &scratch_qdd})
      v->resize(n);
  }

  Mat<double, N> mass;                ///< M = ∂²L/∂q̇² (kg, kg·m, kg·m²)
  Vec<double, N> momenta;             ///< p = ∂L/∂q̇
  Vec<double, N> dL_dq;               ///< ∂L/∂q
  Vec<double, N> mixed;               ///< (∂²L/∂q̇∂q) q̇ + ∂²L/∂q̇∂t
  Vec<double, N> forces;              ///< Q, non-conservative generalized forces
  Vec<double, N> rhs;                 ///< ∂L/∂q − mixed + Q
  Vec<double, N> accelerations;       ///< q̈ = M⁻¹ rhs (from the reference-returning accelerations())
  detail::MassCholesky<N> cholesky;     ///< factorisation of M (n > 2, and constrained models)
  Vec<double, N> scratch_q, scratch_qd, scratch_qdd;  ///< buffers for run-time sized right-hand sides
};

/// Relative pivot below which the mass matrix is reported singular: with
/// the Cholesky pivots d_i (M = L D Lᵀ, L unit lower triangular),
/// min d / max d < 1e-14. A diagonal M (its pivots are the diagonal) is
/// divided out and systems with n ≤ 2 are solved in closed form, with the
/// same criterion; larger ones with the Cholesky factors L Lᵀ = M
/// (d_i = L_ii²).
inline constexpr double singular_mass_tolerance = 1e-14;

namespace detail {

template <int N>
std::string describe_state(const Vec<double, N>& q, const Vec<double, N>& qd, double t) {
  std::ostringstream os;
  os.precision(17);
  os << "t = " << t << ", q = [";
  for (int i = 0; i < q.size(); ++i) os << (i ? ", " : "") << q[i];
  os << "], qd = [";
  for (int i = 0; i < qd.size(); ++i) os << (i ? ", " : "") << qd[i];
  os << "]";
  return os.str();
}

template <class M, class S>
S lagrangian_of(const M& model, const Vec<S, coordinate_count_v<M>>& q, const Vec<S, coordinate_count_v<M>>& qd,
                const S& t) {
  if constexpr (has_kinetic_for<M, S> && has_potential_for<M, S>) {
    S l = S(model.kinetic(q, qd, t));  // L = T − V, without a copy of T
    l -= S(model.potential(q, t));
    return l;
  } else if constexpr (has_lagrangian_for<M, S>) {
    return S(model.lagrangian(q, qd, t));
  } else {
    // Not a model for S: check_model<M>() has stopped compilation with its
    // sentence already; nothing more is said here.
    (void)model, (void)q, (void)qd, (void)t;
    return S(0.0);
  }
}

/// Per-thread vectors of n numbers of type J for the passes over run-time
/// sized models: allocated when a thread first needs them and again only
/// when n changes, never per call.
template <class J>
Vec<J, Dynamic>& jet_vector(int which, int n) {
  thread_local Vec<J, Dynamic> vectors[2];
  Vec<J, Dynamic>& v = vectors[which];
  if (v.size() != n) v.resize(n);
  return v;
}

/// Vectors of n numbers J: the per-thread ones of jet_vector() for
/// run-time sizes, `local` (emplaced on the caller's stack) for fixed sizes.
template <class J, int N>
Vec<J, N>& jet_storage(std::optional<Vec<J, N>>& local, int which, int n) {
  if constexpr (N == Dynamic) {
    return jet_vector<J>(which, n);
  } else {
    (void)which, (void)n;
    return local.emplace();
  }
}

/// The largest models (fixed n > kMaxSinglePassDof, run-time n >
/// kRunTimeCapacity): the same quantities from passes over pairs of
/// coordinate blocks (a, b) with numbers J of 2·kBlock directions, each
/// seeding the directions of the two blocks; the pass (a, b) gives the M
/// entries of rows a × columns b, the pass (a, a) also ∂L/∂q, p and the
/// mixed term of block a.
template <class J, class M>
void eom_pass_blocks(const M& model, Workspace<coordinate_count_v<M>>& ws, const Vec<double, coordinate_count_v<M>>& q,
                     const Vec<double, coordinate_count_v<M>>& qd, double t) {
  const int n = static_cast<int>(q.size());
  const int blocks = (n + kBlock - 1) / kBlock;
  std::optional<Vec<J, coordinate_count_v<M>>> local_q, local_qd;
  auto& qj = jet_storage<J>(local_q, 0, n);
  auto& qdj = jet_storage<J>(local_qd, 1, n);
  for (int a = 0; a < blocks; ++a) {
    for (int b = a; b < blocks; ++b) {
      for (int k = 0; k < n; ++k) {
        qj[k] = J::moving(q[k], qd[k]);  // the path direction moves every coordinate
        qdj[k] = J(qd[k]);
      }
      auto seed = [&](int block, int offset) {
        for (int k = block * kBlock; k < std::min(n, (block + 1) * kBlock); ++k) {
          const int local = offset + k - block * kBlock;
          qj[k] = J::position(q[k], qd[k], local);
          qdj[k] = J::velocity(qd[k], local);
        }
      };
      seed(a, 0);
      if (b != a) seed(b, kBlock);
      const J l = lagrangian_of(model, qj, qdj, J::time(t));
      for (int i = a * kBlock; i < std::min(n, (a + 1) * kBlock); ++i) {
        const int li = i - a * kBlock;
        if (b == a) {
          ws.dL_dq[i] = l.grad_q(li);
          ws.momenta[i] = l.grad_qd(li);
          ws.mixed[i] = l.mixed(li);
        }
        const int offset = b == a ? 0 : kBlock;
        for (int j = b * kBlock; j < std::min(n, (b + 1) * kBlock); ++j) {
          ws.mass(i, j) = l.hess(li, offset + j - b * kBlock);
          ws.mass(j, i) = ws.mass(i, j);
        }
      }
    }
  }
}

/// One pass with numbers J of n directions over the coordinate vectors qj,
/// qdj (of J): ∂L/∂q, p, M and the mixed term.
/// (Not always_inline: g++ does not flatten the body of an always_inline
/// callee into a `flatten` caller.)
template <class J, class M, class JVec>
inline void eom_single_pass(const M& model, Workspace<coordinate_count_v<M>>& ws, JVec& qj, JVec& qdj,
                            const Vec<double, coordinate_count_v<M>>& q, const Vec<double, coordinate_count_v<M>>& qd,
                            double t) {
  const int n = static_cast<int>(q.size());
  for (int k = 0; k < n; ++k) {
    qj[k] = J::position(q[k], qd[k], k);
    qdj[k] = J::velocity(qd[k], k);
  }
  J l = lagrangian_of(model, qj, qdj, J::time(t));
  for (int i = 0; i < n; ++i) {
    ws.dL_dq[i] = l.grad_q(i);
    ws.momenta[i] = l.grad_qd(i);
    ws.mixed[i] = l.mixed(i);
  }
  l.hessian_to(ws.mass);
}

/// eom_single_pass flattened on its own before eom_pass_inline takes it in:
/// the same operations inlined, in an order after which g++ emits faster
/// code for small models (measured in docs/performance.md).
template <class J, class M, class JVec>
LAGRANGIAN_FLATTEN inline void eom_single_pass_flat(const M& model, Workspace<coordinate_count_v<M>>& ws, JVec& qj,
                                                    JVec& qdj, const Vec<double, coordinate_count_v<M>>& q,
                                                    const Vec<double, coordinate_count_v<M>>& qd, double t) {
  eom_single_pass<J>(model, ws, qj, qdj, q, qd, t);
}

/// The pass of a fixed-size model with inline Hessians (n ≤ 12):
/// `flatten`ed, every EomJet operation of T and V inlined into it.
template <class M>
LAGRANGIAN_FLATTEN void eom_pass_inline(const M& model, Workspace<coordinate_count_v<M>>& ws,
                                        const Vec<double, coordinate_count_v<M>>& q,
                                        const Vec<double, coordinate_count_v<M>>& qd, double t) {
  using J = ad::EomJet<coordinate_count_v<M>>;
  Vec<J, coordinate_count_v<M>> qj, qdj;
  eom_single_pass_flat<J>(model, ws, qj, qdj, q, qd, t);
}

/// The pass of a run-time sized model of n ≤ K coordinates with numbers of
/// fixed width K: K = n (fixed_width_passes_v), or K = kPaddedWidth, whose
/// directions n … K − 1 are never seeded and stay zero.
template <int K, class M>
void eom_pass_fixed_width(const M& model, Workspace<Dynamic>& ws, const Vec<double, Dynamic>& q,
                          const Vec<double, Dynamic>& qd, double t) {
  using J = ad::EomJet<K>;
  const int n = static_cast<int>(q.size());
  eom_single_pass<J>(model, ws, jet_vector<J>(0, n), jet_vector<J>(1, n), q, qd, t);
}

/// The pass of a larger fixed-size model (pooled Hessians) or of a run-time
/// sized one. Not flattened: an operation costs O(n) and more here, so a
/// call per operation is cheap, while inlining every one of them into one
/// function would cost the user's compile seconds per model.
template <class M>
LAGRANGIAN_NOINLINE void eom_pass_large(const M& model, Workspace<coordinate_count_v<M>>& ws,
                                        const Vec<double, coordinate_count_v<M>>& q,
                                        const Vec<double, coordinate_count_v<M>>& qd, double t) {
  constexpr int n = coordinate_count_v<M>;
  if constexpr (n == Dynamic) {
    using J = EomJet<M>;  // run-time width
    const int size = static_cast<int>(q.size());
    if constexpr (fixed_width_passes_v<M>) {
      static_assert(kSmallFixedWidths == 4);
      switch (size) {
        case 1: return eom_pass_fixed_width<1>(model, ws, q, qd, t);
        case 2: return eom_pass_fixed_width<2>(model, ws, q, qd, t);
        case 3: return eom_pass_fixed_width<3>(model, ws, q, qd, t);
        case 4: return eom_pass_fixed_width<4>(model, ws, q, qd, t);
        default: break;
      }
    }
    static_assert(kPaddedWidth <= ad::EomJet<1>::kInlineHessianMax);
    if (size <= kPaddedWidth) return eom_pass_fixed_width<kPaddedWidth>(model, ws, q, qd, t);
    if (size > kRunTimeCapacity) {
      ad::WidthScope width(2 * kBlock);
      eom_pass_blocks<J>(model, ws, q, qd, t);
    } else {
      ad::WidthScope width(size);
      eom_single_pass<J>(model, ws, jet_vector<J>(0, size), jet_vector<J>(1, size), q, qd, t);
    }
  } else if constexpr (uses_block_passes<M>) {
    ad::WidthScope width(2 * kBlock);
    eom_pass_blocks<EomJet<M>>(model, ws, q, qd, t);
  } else {
    using J = ad::EomJet<n>;
    Vec<J, n> qj, qdj;
    eom_single_pass<J>(model, ws, qj, qdj, q, qd, t);
  }
}

/// The Euler–Lagrange pass: ∂L/∂q, p, M and the mixed term from one
/// evaluation of T and V (or L) on ad::EomJet numbers (block passes for
/// the largest models). L's own value is not kept: q̈ does not need it, and
/// with it unused g++ drops the cosines that only V's value takes (cos θ of
/// a pendulum's height), leaving sin θ for ∂V/∂θ: a double pendulum's pass
/// then calls one sincos and two sin instead of three sincos.
template <class M>
LAGRANGIAN_ALWAYS_INLINE void eom_pass(const M& model, Workspace<coordinate_count_v<M>>& ws,
                                       const Vec<double, coordinate_count_v<M>>& q,
                                       const Vec<double, coordinate_count_v<M>>& qd, double t) {
  constexpr int n = coordinate_count_v<M>;
  if constexpr (n != Dynamic && n <= ad::EomJet<1>::kInlineHessianMax) {
    eom_pass_inline(model, ws, q, qd, t);
  } else {
    eom_pass_large(model, ws, q, qd, t);
  }
}

/// Q = generalized forces − ∂D/∂q̇.
template <class M>
LAGRANGIAN_FLATTEN void force_pass(const M& model, Workspace<coordinate_count_v<M>>& ws,
                                   const Vec<double, coordinate_count_v<M>>& q,
                                   const Vec<double, coordinate_count_v<M>>& qd, double t) {
  constexpr int n = coordinate_count_v<M>;
  if constexpr (has_generalized_forces_v<M>) {
    if (uses_generalized_forces(model)) {
      ws.forces = model.generalized_forces(q, qd, t);
    } else {
      ws.forces.setZero(q.size());
    }
  } else {
    ws.forces.setZero(q.size());
  }
  if constexpr (has_dissipation_v<M>) {
    if (!uses_dissipation(model)) return;
    // ∂D/∂q̇ in blocks of the Jet's width (one block when n is fixed).
    constexpr int w = ad_directions<M>;
    using J = ad::Jet<double, w, 1>;
    const int size = static_cast<int>(q.size());
    std::optional<Vec<J, n>> local_q, local_qd;
    Vec<J, n>& qj = jet_storage<J>(local_q, 0, size);
    Vec<J, n>& qdj = jet_storage<J>(local_qd, 1, size);
    qj = q.template cast<J>();
    qdj = qd.template cast<J>();
    for (int start = 0; start < size; start += w) {
      for (int k = start; k < std::min(size, start + w); ++k) qdj[k] = J::variable(qd[k], k - start);
      const J d = J(model.dissipation(qj, qdj));
      for (int k = start; k < std::min(size, start + w); ++k) {
        ws.forces[k] -= d.g[k - start];
        qdj[k] = J(qd[k]);
      }
    }
  }
}

template <int N>
[[noreturn]] void singular_mass_failure(const Workspace<N>& ws, const Vec<double, N>& q, const Vec<double, N>& qd,
                                        double t) {
  std::ostringstream os;
  os.precision(17);
  os << "mass matrix M = d2L/dqd2 is singular or not positive definite at " << describe_state(q, qd, t) << "; M = [";
  for (int i = 0; i < ws.mass.rows(); ++i)
    for (int j = 0; j < ws.mass.cols(); ++j) os << (i || j ? (j ? ", " : "; ") : "") << ws.mass(i, j);
  os << "]";
  // A coordinate that carries no kinetic energy (a zero row and column of M).
  const double big = ws.mass.cwiseAbs().maxCoeff();
  for (int i = 0; i < ws.mass.rows(); ++i)
    if (!(ws.mass.row(i).cwiseAbs().maxCoeff() > 1e-14 * big))
      os << "; coordinate q[" << i << "] has no inertia here (row " << i
         << " of M is zero): a coordinate singularity (as at a pole of spherical coordinates: choose other "
            "coordinates) or a massless coordinate (an ideal pulley's angle: not supported, even where constraints "
            "would determine it; eliminate it through its constraint, or give it a small mass)";
  throw DynamicsError(os.str());
}

/// Factorises ws.mass into ws.cholesky; throws DynamicsError naming the
/// state unless the Cholesky pivots d_i = L_ii² are positive with
/// min d / max d ≥ singular_mass_tolerance.
template <int N>
void factor_mass_matrix(Workspace<N>& ws, const Vec<double, N>& q, const Vec<double, N>& qd, double t) {
  if (!ws.cholesky.compute(ws.mass, singular_mass_tolerance)) singular_mass_failure(ws, q, qd, t);
}

}  // namespace detail

/// Evaluates M, p, ∂L/∂q, Q and the right-hand side of M q̈ = rhs into `ws`
/// without solving for q̈.
template <class M>
void evaluate(const M& model, Workspace<coordinate_count_v<M>>& ws, const Vec<double, coordinate_count_v<M>>& q,
              const Vec<double, coordinate_count_v<M>>& qd,
              double t) {
  check_model<M>();
  detail::eom_pass(model, ws, q, qd, t);
  detail::force_pass(model, ws, q, qd, t);
  ws.rhs = ws.dL_dq - ws.mixed + ws.forces;
}

namespace detail {
/// True when M's entries below the diagonal (those the Cholesky
/// factorisation reads) are all zero.
template <int N>
bool diagonal_mass(const Mat<double, N>& mass) {
  for (int j = 0; j < mass.cols(); ++j)
    for (int i = j + 1; i < mass.rows(); ++i)
      if (mass(i, j) != 0) return false;
  return true;
}

/// Throws (singular_mass_failure) unless the pivots of a diagonal ws.mass,
/// its diagonal entries, are positive with min / max ≥
/// singular_mass_tolerance.
template <int N>
void check_diagonal_pivots(const Workspace<N>& ws, const Vec<double, N>& q, const Vec<double, N>& qd, double t) {
  const auto d = ws.mass.diagonal();
  double lo = d[0], hi = d[0];
  for (int i = 1; i < d.size(); ++i) {
    lo = std::min(lo, d[i]);
    hi = std::max(hi, d[i]);
  }
  if (!(std::isfinite(lo) && std::isfinite(hi) && lo > 0 && lo >= singular_mass_tolerance * hi))
    singular_mass_failure(ws, q, qd, t);
}

/// det M of a 2 × 2 ws.mass, after checking its pivots d_0 = M00,
/// d_1 = det / M00 as check_diagonal_pivots() does (singular_mass_failure
/// otherwise).
template <int N>
double checked_determinant_2x2(const Workspace<N>& ws, const Vec<double, N>& q, const Vec<double, N>& qd, double t) {
  const double a = ws.mass(0, 0), b = ws.mass(0, 1), c = ws.mass(1, 1);
  const double det = a * c - b * b;
  const double d1 = det / a;
  if (!(std::isfinite(det) && a > 0 && d1 > 0 && std::min(a, d1) >= singular_mass_tolerance * std::max(a, d1)))
    singular_mass_failure(ws, q, qd, t);
  return det;
}

/// Cramer's rule for the 2 × 2 system M x = rhs with det M given.
template <int N>
void solve_2x2(const Mat<double, N>& mass, double det, const Vec<double, N>& rhs, Vec<double, N>& out) {
  out[0] = (mass(1, 1) * rhs[0] - mass(0, 1) * rhs[1]) / det;
  out[1] = (mass(0, 0) * rhs[1] - mass(0, 1) * rhs[0]) / det;
}

/// q̈ of the model's Lagrangian and forces alone, M q̈ = rhs, any constraints
/// left out (the free motion of a contact model whose contacts are open).
/// Inlined into its callers (the adapter's right-hand side among them), so
/// that an evaluation is one call below the stepper's, into eom_pass.
template <class M>
LAGRANGIAN_ALWAYS_INLINE void free_accelerations(const M& model, Workspace<coordinate_count_v<M>>& ws,
                                                 const Vec<double, coordinate_count_v<M>>& q,
                                                 const Vec<double, coordinate_count_v<M>>& qd, double t,
                                                 Vec<double, coordinate_count_v<M>>& out) {
  evaluate(model, ws, q, qd, t);
  constexpr int n = coordinate_count_v<M>;  // Dynamic (-1) takes the general branches
  // Cholesky pivots d_i (M = L D Lᵀ with unit L, d_i = L_chol,ii²) must be
  // positive with min d / max d ≥ singular_mass_tolerance.
  if constexpr (n == 1) {
    const double m = ws.mass(0, 0);
    if (!(std::isfinite(m) && m > 0)) detail::singular_mass_failure(ws, q, qd, t);
    out[0] = ws.rhs[0] / m;
  } else if (diagonal_mass(ws.mass)) {
    // Cartesian coordinates of particles, among others (and every 1 × 1 M):
    // the pivots are the diagonal, q̈_i = rhs_i / M_ii, each rounded once.
    check_diagonal_pivots(ws, q, qd, t);
    out = ws.rhs.cwiseQuotient(ws.mass.diagonal());
  } else if constexpr (n == 2) {
    solve_2x2(ws.mass, checked_determinant_2x2(ws, q, qd, t), ws.rhs, out);
  } else {
    if constexpr (n == Dynamic) {
      // Cramer's rule for a run-time size of 2 too (a text model's double
      // pendulum), as for a fixed one.
      if (ws.mass.rows() == 2) return solve_2x2(ws.mass, checked_determinant_2x2(ws, q, qd, t), ws.rhs, out);
    }
    detail::factor_mass_matrix(ws, q, qd, t);
    if constexpr (n == Dynamic) out.resize(ws.rhs.size());  // (nothing allocated when it has that size)
    ws.cholesky.solve(ws.rhs.data(), out.data());
  }
}
}  // namespace detail

/// Generalized accelerations q̈ (m/s² or rad/s²) at (q, q̇, t), written into
/// caller storage `out` (the hot-path form: no heap, no copy). Throws
/// DynamicsError naming the state when M is singular or not positive
/// definite. A model with constraints does not compile here: its q̈ comes
/// from constrained_accelerations(); one that counts its constraints at run
/// time (a text model) throws DynamicsError when it has any.
template <class M>
void accelerations(const M& model, Workspace<coordinate_count_v<M>>& ws, const Vec<double, coordinate_count_v<M>>& q,
                   const Vec<double, coordinate_count_v<M>>& qd, double t, Vec<double, coordinate_count_v<M>>& out) {
  static_assert(!detail::declares_constraints_c<M> || detail::counts_constraints_at_run_time_c<M>,
                "lagrangian: accelerations() would ignore this model's constraints; use "
                "constrained_accelerations(model, ws, cw, q, qd, t, qdd) with a ConstraintWorkspaceFor<M> cw "
                "(lagrangian/mechanics/constraints.hpp), or simulate()");
  if constexpr (detail::counts_constraints_at_run_time_c<M>) {
    if (const int rows = detail::run_time_constraint_rows(model); rows > 0)
      throw DynamicsError("accelerations() would ignore this model's " + std::to_string(rows) +
                          " constraints; use constrained_accelerations(), or simulate()");
  }
  if constexpr (!detail::declares_constraints_c<M> || detail::counts_constraints_at_run_time_c<M>)
    detail::free_accelerations(model, ws, q, qd, t, out);
}

/// q̈ written into ws.accelerations and returned by reference.
template <class M>
const Vec<double, coordinate_count_v<M>>& accelerations(const M& model, Workspace<coordinate_count_v<M>>& ws,
                                                        const Vec<double, coordinate_count_v<M>>& q,
                                         const Vec<double, coordinate_count_v<M>>& qd, double t) {
  accelerations(model, ws, q, qd, t, ws.accelerations);
  return ws.accelerations;
}

/// Convenience form of accelerations() that allocates its own workspace.
template <class M>
Vec<double, coordinate_count_v<M>> accelerations(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                                 const Vec<double, coordinate_count_v<M>>& qd,
                                  double t = 0.0) {
  Workspace<coordinate_count_v<M>> ws(static_cast<int>(q.size()));
  return accelerations(model, ws, q, qd, t);
}

/// Generalized momenta p = ∂L/∂q̇ (kg·m/s, or kg·m²/s for angles).
template <class M>
Vec<double, coordinate_count_v<M>> momenta(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                           const Vec<double, coordinate_count_v<M>>& qd,
                            double t = 0.0) {
  check_model<M>();
  constexpr int n = coordinate_count_v<M>;
  if constexpr (n == Dynamic || detail::uses_block_passes<M>) {
    Workspace<n> ws(static_cast<int>(q.size()));
    detail::eom_pass(model, ws, q, qd, t);
    return ws.momenta;
  } else {
    using J = ad::Jet<double, n, 1>;
    Vec<J, n> qj = q.template cast<J>();
    Vec<J, n> qdj;
    for (int k = 0; k < n; ++k) qdj[k] = J::variable(qd[k], k);
    const J l = detail::lagrangian_of(model, qj, qdj, J(t));
    Vec<double, n> p;
    for (int i = 0; i < n; ++i) p[i] = l.g[i];
    return p;
  }
}

/// Mass matrix M = ∂²L/∂q̇² (kg, kg·m, kg·m²).
template <class M>
Mat<double, coordinate_count_v<M>> mass_matrix(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                               const Vec<double, coordinate_count_v<M>>& qd,
                                double t = 0.0) {
  check_model<M>();
  Workspace<coordinate_count_v<M>> ws(static_cast<int>(q.size()));
  detail::eom_pass(model, ws, q, qd, t);
  return ws.mass;
}

/// The Lagrangian L(q, q̇, t) = T − V (J).
template <class M>
double lagrangian_value(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                        const Vec<double, coordinate_count_v<M>>& qd,
                        double t = 0.0) {
  check_model<M>();
  return detail::lagrangian_of(model, q, qd, t);
}

/// ∂L/∂t at (q, q̇, t) (W). Zero for all states ⇔ the Jacobi integral is conserved.
template <class M>
double lagrangian_time_derivative(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                  const Vec<double, coordinate_count_v<M>>& qd,
                                  double t) {
  check_model<M>();
  using J = ad::Jet<double, 1, 1>;
  const Vec<J, coordinate_count_v<M>> qj = q.template cast<J>();
  const Vec<J, coordinate_count_v<M>> qdj = qd.template cast<J>();
  return detail::lagrangian_of(model, qj, qdj, J::variable(t, 0)).g[0];
}

/// The energy function (Jacobi integral) h = p·q̇ − L (J). Conserved when
/// ∂L/∂t = 0 and Q = 0, even when T + V is not (moving constraints).
template <class M>
double energy_function(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                       const Vec<double, coordinate_count_v<M>>& qd,
                       double t = 0.0) {
  check_model<M>();
  const Vec<double, coordinate_count_v<M>> p = momenta(model, q, qd, t);
  return p.dot(qd) - lagrangian_value(model, q, qd, t);
}

/// Kinetic energy T (J); only for models that give T and V separately.
template <class M>
  requires has_kinetic_potential_v<M>
double kinetic_energy(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                      const Vec<double, coordinate_count_v<M>>& qd, double t = 0.0) {
  return model.kinetic(q, qd, t);
}

/// Potential energy V (J); only for models that give T and V separately.
template <class M>
  requires has_kinetic_potential_v<M>
double potential_energy(const M& model, const Vec<double, coordinate_count_v<M>>& q, double t = 0.0) {
  return model.potential(q, t);
}

/// Total mechanical energy T + V (J); only for models that give T and V.
template <class M>
  requires has_kinetic_potential_v<M>
double total_energy(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                    const Vec<double, coordinate_count_v<M>>& qd, double t = 0.0) {
  return model.kinetic(q, qd, t) + model.potential(q, t);
}

/// Non-conservative generalized forces Q = Q_model − ∂D/∂q̇ at a state.
template <class M>
Vec<double, coordinate_count_v<M>> nonconservative_forces(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                           const Vec<double, coordinate_count_v<M>>& qd, double t = 0.0) {
  check_model<M>();
  Workspace<coordinate_count_v<M>> ws(static_cast<int>(q.size()));
  detail::force_pass(model, ws, q, qd, t);
  return ws.forces;
}

}  // namespace lagrangian
