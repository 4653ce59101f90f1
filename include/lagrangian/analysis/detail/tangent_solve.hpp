#pragma once
// Internal: the last step of the tangent pass (tangent_flow.hpp): q̈ and its
// derivatives along K directions from M, r and their derivatives, for a
// free model (M q̈ = r) and for one with holonomic and Pfaffian constraints
// (the saddle-point system of constrained_accelerations.hpp, differentiated);
// and the rows of the constraint manifold in the state space.
//
// With bilateral constraints C q̈ + γ = 0 (C = ∂g/∂q for holonomic rows
// g(q, t) = 0, γ = q̇ᵀ ∂²g/∂q² q̇ + 2 ∂²g/∂q∂t q̇ + ∂²g/∂t²; C = A for
// Pfaffian rows φ = A(q, t) q̇ + a(q, t) = 0, γ = (∂φ/∂q) q̇ + ∂φ/∂t at
// fixed q̇) the motion is
//   M q̈ = r + Cᵀλ,   C q̈ = −γ,
// and its derivative along a direction δ of the state
//   M δq̈ = δr − δM q̈ + δCᵀ λ + Cᵀ δλ,   C δq̈ = −δγ − δC q̈,
// both solved through the Schur complement S = C M⁻¹ Cᵀ by its
// minimum-norm pseudo-inverse (redundant rows: λ is not unique, q̈ and δq̈
// are), as the run solves the first. C and γ along the directions come
// from the constraint functions on ad::Jets of ad::Jets: no finite
// differences. Rows counted at run time (models stated as text) take
// matrices of a fixed capacity, kMaxRuntimeBilateralRows.

#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/ad.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/constraint_counts.hpp"
#include "lagrangian/mechanics/detail/mass_cholesky.hpp"
#include "lagrangian/mechanics/detail/min_norm_solver.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian::detail {

/// The holonomic and Pfaffian rows of M when both counts are known at
/// compile time; Dynamic otherwise.
template <class M>
inline constexpr int bilateral_rows_v = holonomic_count_v<M> == Dynamic || pfaffian_count_v<M> == Dynamic
                                            ? Dynamic
                                            : holonomic_count_v<M> + pfaffian_count_v<M>;

/// Most holonomic and Pfaffian rows the tangent flow takes from a model that
/// counts them at run time (its matrices then have this capacity, on the
/// stack: no allocation per call).
inline constexpr int kMaxRuntimeBilateralRows = 8;

/// The row capacity of the tangent pass's constraint matrices for `rows`
/// (a fixed count, or Dynamic).
constexpr int bilateral_capacity(int rows) { return rows == Dynamic ? kMaxRuntimeBilateralRows : rows; }

/// An R × C matrix of S with room for MR × MC (R or C Dynamic up to that),
/// in the storage order Eigen requires for its shape.
template <class S, int R, int C, int MR, int MC>
using CappedMatrix =
    Eigen::Matrix<S, R, C, (MR == 1 && MC != 1) ? Eigen::RowMajor : Eigen::ColMajor, MR, MC>;

/// q and q̇ as first-order Jets along the K directions V: the derivatives
/// of q_k are the row k of V, those of q̇_k the row n + k.
template <int K, int n>
void along_directions(const Vec<double, n>& q, const Vec<double, n>& qd, const Eigen::Matrix<double, 2 * n, K>& v,
                      Vec<ad::Jet<double, K, 1>, n>& qi, Vec<ad::Jet<double, K, 1>, n>& qdi) {
  for (int k = 0; k < n; ++k) {
    qi[k] = ad::Jet<double, K, 1>(q[k]);
    qdi[k] = ad::Jet<double, K, 1>(qd[k]);
    for (int c = 0; c < K; ++c) {
      qi[k].g[c] = v(k, c);
      qdi[k].g[c] = v(n + k, c);
    }
  }
}

/// ∂M along the directions c = 0 … K − 1 of a tangent pass, as a callable
/// that does not make the linear algebra below a template on it: M's
/// derivative along direction c is at(c).
template <int n>
class MassDerivatives {
 public:
  /// Refers to `f` (f(c) returns ∂M along c), which must outlive this.
  template <class F>
  explicit MassDerivatives(const F& f)
      : f_(&f), at_([](const void* g, int c) -> const Mat<double, n>& { return (*static_cast<const F*>(g))(c); }) {}
  const Mat<double, n>& operator()(int c) const { return at_(f_, c); }

 private:
  const void* f_;
  const Mat<double, n>& (*at_)(const void*, int);
};

/// The Cholesky factors L Lᵀ = M of a tangent pass's mass matrix
/// (MassCholesky), and solves with them. Compiled once per n = 1 …
/// kMaxTangentFlowCoordinates (src/analysis/tangent_solve.cpp): a model's
/// own file instantiates none of it.
template <int n>
class TangentCholesky {
 public:
  /// Factors M (its lower triangle); DynamicsError naming the state (q, q̇,
  /// t) when M is not positive definite, relative to its largest diagonal
  /// factor (singular_mass_tolerance).
  void factor(const Mat<double, n>& mass, const Vec<double, n>& q, const Vec<double, n>& qd, double t);
  /// x = M⁻¹ b for `columns` right-hand sides of n rows each, stored one
  /// column after the other; x may be b.
  void solve(const double* b, double* x, int columns = 1) const { llt_.solve(b, x, columns); }

 private:
  MassCholesky<n> llt_;
};

/// q̈ = M⁻¹ r₀ and (J V)_c = M⁻¹ (r_{c+1} − ∂M_c q̈) for c = 0 … k − 1, the
/// derivative of M q̈ = r along direction c; r is n × (k + 1) and jv n × k,
/// column-major; DynamicsError when M is not positive definite
/// (TangentCholesky). Compiled once per n (src/analysis/tangent_solve.cpp),
/// not once per model and width.
template <int n>
void solve_tangent_columns(const Mat<double, n>& mass, const double* r, int k, MassDerivatives<n> dmass,
                           const Vec<double, n>& q, const Vec<double, n>& qd, double t, Vec<double, n>& qdd,
                           double* jv);

/// q̈ = M⁻¹ r and JV = M⁻¹ (dR − dM_c q̈)_c from M, r (column 0 of R) and
/// their derivatives along the K directions (R's columns 1 … K, dmass(c)).
template <int n, int K, class DMass>
void solve_tangent(const Mat<double, n>& mass, const Eigen::Matrix<double, n, K + 1>& r, const DMass& dmass,
                   const Vec<double, n>& q, const Vec<double, n>& qd, double t, Vec<double, n>& qdd,
                   Eigen::Matrix<double, n, K>& jv) {
  // One row or column-major: both store column c of an n-row matrix at c n.
  solve_tangent_columns<n>(mass, r.data(), K, MassDerivatives<n>(dmass), q, qd, t, qdd, jv.data());
}

/// C (m × n) and γ of the holonomic rows, then the Pfaffian rows, of
/// `model` at (q, q̇, t), on numbers D that carry derivatives (the
/// directions of the tangent pass, or the state itself); m counted at
/// compile time or, for a model that counts its rows at run time, at most
/// the capacity of `c` and `gamma`, which are sized here. C's columns are
/// taken Wq at a time (Wq = n: in one evaluation of the rows).
template <int Wq, class M, class D, int n, class CM, class GV>
void bilateral_rows_on(const M& model, const Vec<D, n>& q, const Vec<D, n>& qd, const D& t, CM& c, GV& gamma) {
  const int mh = holonomic_count(model), mp = pfaffian_count(model);
  if constexpr (CM::RowsAtCompileTime == Dynamic) {
    c.resize(mh + mp, n);
    gamma.resize(mh + mp);
  }
  using J1 = ad::Jet<D, Wq, 1>;  // first order in Wq of the q (holonomic) or q̇ (Pfaffian)
  // x as J1 numbers whose directions are x_first … x_{first+Wq−1}.
  const auto seed = [](const Vec<D, n>& x, int first, Vec<J1, n>& out) {
    for (int k = 0; k < n; ++k) {
      out[k] = J1(x[k]);
      if (k >= first && k < first + Wq) out[k].g[k - first] = D(1.0);
    }
  };
  if constexpr (holonomic_count_v<M> != 0) {
    for (int first = 0; first < n; first += Wq) {
      Vec<J1, n> qj;
      seed(q, first, qj);
      const auto g1 = model.holonomic(qj, J1(t));
      for (int i = 0; i < mh; ++i)
        for (int k = first; k < std::min(n, first + Wq); ++k) c(i, k) = g1[i].g[k - first];
    }
    // γ = d²g/ds² along the path (q + s q̇, t + s).
    using J2 = ad::Jet<D, 1, 2>;
    Vec<J2, n> qp;
    J2 tp;
    ad::along_path(q, qd, t, qp, tp);
    const auto g2 = model.holonomic(qp, tp);
    for (int i = 0; i < mh; ++i) gamma[i] = g2[i].hess(0, 0);
  }
  if constexpr (pfaffian_count_v<M> != 0) {
    for (int first = 0; first < n; first += Wq) {
      Vec<J1, n> qj, qdj;
      for (int k = 0; k < n; ++k) qj[k] = J1(q[k]);
      seed(qd, first, qdj);
      const auto phi = model.pfaffian(qj, qdj, J1(t));
      for (int i = 0; i < mp; ++i)
        for (int k = first; k < std::min(n, first + Wq); ++k) c(mh + i, k) = phi[i].g[k - first];
    }
    // γ = (∂φ/∂q) q̇ + ∂φ/∂t at fixed q̇.
    using P = ad::Jet<D, 1, 1>;
    Vec<P, n> qp, qdp;
    for (int k = 0; k < n; ++k) qdp[k] = P(qd[k]);
    P tp;
    ad::along_path(q, qd, t, qp, tp);
    const auto phi2 = model.pfaffian(qp, qdp, tp);
    for (int i = 0; i < mp; ++i) gamma[mh + i] = phi2[i].g[0];
  }
}

/// How many directions one evaluation of a model's constraint rows
/// carries, out of `all`: all of them for rows counted at compile time (one
/// evaluation, compiled code); one for rows counted at run time (a model
/// stated as text: its expressions are then interpreted on a few number
/// types per size, not on more for each width of the tangent pass).
template <class M>
constexpr int rows_directions(int all) {
  return bilateral_rows_v<M> == Dynamic ? 1 : all;
}

/// A matrix of type X, of rows × cols when its size is chosen at run time
/// (within its capacity: nothing allocated); the values are left unset.
template <class X>
X sized(int rows, int cols) {
  X x;
  if constexpr (X::RowsAtCompileTime == Dynamic || X::ColsAtCompileTime == Dynamic) x.resize(rows, cols);
  (void)rows, (void)cols;
  return x;
}

/// This thread's minimum-norm solver for Schur complements of m × m, mc
/// the rows counted at compile time (or Dynamic: the solver is made again
/// when a model of another row count comes).
template <int mc>
MinNormSolver& schur_solver(int m) {
  if constexpr (mc != Dynamic) {
    (void)m;
    thread_local MinNormSolver solver(mc, mc);
    return solver;
  } else {
    thread_local MinNormSolver solver(m, m);
    thread_local int rows = m;
    if (rows != m) solver = MinNormSolver(m, m), rows = m;
    return solver;
  }
}

/// solve_tangent() for a model with holonomic or Pfaffian constraints (the
/// file comment): C, γ and their derivatives along the K directions V from
/// the constraint functions on first-order Jets along V. Rows counted at
/// run time take matrices of capacity kMaxRuntimeBilateralRows
/// (require_tangent_flow_constraints() refuses more).
template <int n, int K, class M, class DMass>
void solve_constrained_tangent(const M& model, const Mat<double, n>& mass, const Eigen::Matrix<double, n, K + 1>& r,
                               DMass&& dmass, const Vec<double, n>& q, const Vec<double, n>& qd, double t,
                               const Eigen::Matrix<double, 2 * n, K>& v, Vec<double, n>& qdd,
                               Eigen::Matrix<double, n, K>& jv) {
  constexpr int mc = bilateral_rows_v<M>, cap = bilateral_capacity(mc);
  static_assert(mc == Dynamic || mc > 0, "solve_constrained_tangent: a model with holonomic or Pfaffian rows");
  const int m = holonomic_count(model) + pfaffian_count(model);
  constexpr int W = rows_directions<M>(K);  // directions per evaluation of the rows
  using D = ad::Jet<double, W, 1>;
  using RowsD = CappedMatrix<D, mc, n, cap, n>;
  using RowsV = CappedMatrix<double, mc, n, cap, n>;
  using Multipliers = CappedMatrix<double, mc, 1, cap, 1>;
  RowsD cd;
  CappedMatrix<D, mc, 1, cap, 1> gd;
  // C and γ with their derivatives along the directions first … first + W − 1.
  const auto rows_along = [&](int first) {
    Vec<D, n> qi, qdi;
    along_directions<W, n>(q, qd, v.template middleCols<W>(first), qi, qdi);
    bilateral_rows_on<rows_directions<M>(n)>(model, qi, qdi, D(t), cd, gd);
  };
  rows_along(0);
  RowsV c = sized<RowsV>(m, n);
  Multipliers gamma = sized<Multipliers>(m, 1);
  for (int i = 0; i < m; ++i) {
    gamma[i] = gd[i].v;
    for (int k = 0; k < n; ++k) c(i, k) = cd(i, k).v;
  }
  TangentCholesky<n> llt;
  llt.factor(mass, q, qd, t);
  // M⁻¹ Cᵀ, column by column (one row or column-major: column j at j n).
  CappedMatrix<double, n, mc, n, cap> minv_ct = c.transpose();
  llt.solve(minv_ct.data(), minv_ct.data(), m);
  const CappedMatrix<double, mc, mc, cap, cap> schur = c * minv_ct;
  MinNormSolver& solver = schur_solver<mc>(m);
  solver.factorize(schur.data());
  // δq̈ = M⁻¹ (a + Cᵀ δλ), δλ = S⁺ (b − C M⁻¹ a), for (a, b) the right-hand
  // sides of the two equations.
  const auto solve = [&](const Vec<double, n>& a, const Multipliers& b, Vec<double, n>& out,
                         Multipliers& multipliers) {
    Vec<double, n> free;
    llt.solve(a.data(), free.data());
    const Multipliers target = b - c * free;
    solver.solve(target.data(), multipliers.data());
    out = free + minv_ct * multipliers;
  };
  Multipliers lambda = sized<Multipliers>(m, 1), dlambda = lambda;
  solve(r.col(0), -gamma, qdd, lambda);
  for (int col = 0; col < K; ++col) {
    if (col % W == 0 && col > 0) rows_along(col);
    RowsV dc = sized<RowsV>(m, n);
    Multipliers dgamma = sized<Multipliers>(m, 1);
    for (int i = 0; i < m; ++i) {
      dgamma[i] = gd[i].g[col % W];
      for (int k = 0; k < n; ++k) dc(i, k) = cd(i, k).g[col % W];
    }
    const Vec<double, n> a = r.col(col + 1) - dmass(col) * qdd + dc.transpose() * lambda;
    const Multipliers b = -dgamma - dc * qdd;
    Vec<double, n> out;
    solve(a, b, out, dlambda);
    jv.col(col) = out;
  }
}

/// The last step of the tangent pass of `model`: solve_constrained_tangent()
/// when it has holonomic or Pfaffian rows, solve_tangent() otherwise.
/// `model` is the one the pass evaluated L on: along a parameter, its
/// seeded twin, whose rows then carry their derivative along it too.
template <int n, int K, class M, class DMass>
void finish_tangent(const M& model, const Mat<double, n>& mass, const Eigen::Matrix<double, n, K + 1>& r,
                    DMass&& dmass, const Vec<double, n>& q, const Vec<double, n>& qd, double t,
                    const Eigen::Matrix<double, 2 * n, K>& v, Vec<double, n>& qdd, Eigen::Matrix<double, n, K>& jv) {
  if constexpr (bilateral_rows_v<M> != 0) {
    if (bilateral_rows_v<M> != Dynamic || holonomic_count(model) + pfaffian_count(model) > 0) {
      solve_constrained_tangent<n, K>(model, mass, r, dmass, q, qd, t, v, qdd, jv);
      return;
    }
  }
  (void)model, (void)v;
  solve_tangent<n, K>(mass, r, dmass, q, qd, t, qdd, jv);
}

/// The rows h = (g, ġ, φ) of `model` (manifold_rows()) on numbers D at
/// (q, q̇, t) given as such numbers: put(row, h_row) for each of the
/// 2 mh + mp rows, ġ as the derivative of g along the path (q + s q̇, t + s).
template <class M, class D, int n, class Put>
void manifold_rows_on(const M& model, const Vec<D, n>& q, const Vec<D, n>& qd, const D& t, Put&& put) {
  const int mh = holonomic_count(model), mp = pfaffian_count(model);
  if constexpr (holonomic_count_v<M> != 0) {
    using P = ad::Jet<D, 1, 1>;
    Vec<P, n> qp;
    P tp;
    ad::along_path(q, qd, t, qp, tp);
    const auto g = model.holonomic(qp, tp);
    for (int i = 0; i < mh; ++i) {
      put(i, g[i].v);
      put(mh + i, g[i].g[0]);
    }
  }
  if constexpr (pfaffian_count_v<M> != 0) {
    const auto phi = model.pfaffian(q, qd, t);
    for (int i = 0; i < mp; ++i) put(2 * mh + i, phi[i]);
  }
}

/// The constraint manifold in the state space x = (q, q̇) at (q, q̇, t):
/// its rows h = (g, ġ, φ) (the holonomic rows, their rates
/// ġ = ∂g/∂q q̇ + ∂g/∂t, the Pfaffian rows; 2 mh + mp values) into
/// `residual` and their Jacobian ∂h/∂(q, q̇) ((2 mh + mp) × 2n, column-major)
/// into `jacobian`. A tangent vector of the constrained motion has
/// (∂h/∂x) δx = 0.
template <class M>
void manifold_rows(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                   const Vec<double, coordinate_count_v<M>>& qd, double t, double* residual, double* jacobian) {
  constexpr int n = coordinate_count_v<M>, W = rows_directions<M>(2 * n);  // columns per evaluation
  const int mh = holonomic_count(model), mp = pfaffian_count(model);
  using D = ad::Jet<double, W, 1>;  // along W of the (q, q̇)
  Eigen::Map<Eigen::Matrix<double, Dynamic, 2 * n>> jac(jacobian, 2 * mh + mp, 2 * n);
  for (int first = 0; first < 2 * n; first += W) {
    const int count = std::min(W, 2 * n - first);
    Vec<D, n> qx, qdx;
    for (int k = 0; k < n; ++k) {
      qx[k] = D(q[k]);
      qdx[k] = D(qd[k]);
    }
    for (int w = 0; w < count; ++w) {
      const int j = first + w;
      (j < n ? qx[j] : qdx[j - n]).g[w] = 1.0;
    }
    manifold_rows_on(model, qx, qdx, D(t), [&](int row, const D& x) {
      residual[row] = x.v;
      for (int w = 0; w < count; ++w) jac(row, first + w) = x.g[w];
    });
  }
}

/// ∂h/∂p at (q, q̇, t), h = (g, ġ, φ) the rows of manifold_rows(), for the
/// parameter seeded in `seeded` (the model with parameters of type
/// ad::Jet<double, 1, 1>, one of them carrying the derivative 1:
/// sensitivity.hpp): how the constraint manifold moves past the state when
/// the parameter changes (2 mh + mp values into `out`; q and q̇ n values each).
template <int n, class E>
void manifold_rows_along_parameter(const E& seeded, const double* q, const double* qd, double t, double* out) {
  using D = ad::Jet<double, 1, 1>;  // the parameter's direction
  Vec<D, n> qx, qdx;
  for (int k = 0; k < n; ++k) {
    qx[k] = D(q[k]);
    qdx[k] = D(qd[k]);
  }
  manifold_rows_on(seeded, qx, qdx, D(t), [&](int row, const D& x) { out[row] = x.g[0]; });
}

}  // namespace lagrangian::detail
