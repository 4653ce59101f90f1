#pragma once
/// \file saltation.hpp
/// How a small change of the state crosses an impact: the saltation matrix.
///
/// At an impact of contact j at time τ the gap φ_j(q, t) (impact.hpp) falls
/// through zero and Newton's law of restitution replaces the velocities:
///   x⁺ = R(x⁻, τ),  R(q, q̇, t) = (q, q̇⁺(q, q̇, t)),
///   q̇⁺ = q̇ − (1 + e) v M⁻¹Gᵀ / (G M⁻¹ Gᵀ),
///   G = ∂φ_j/∂q (a row),  v = G q̇ + ∂φ_j/∂t  (the approach speed, < 0),
/// M = ∂²L/∂q̇² (one contact, no bilateral constraints: apply_impact()'s law).
/// A model with holonomic or Pfaffian rows C q̇ + c = 0 keeps them through
/// the impact (apply_impact()'s law too): with W = [C; G] and the rows'
/// rates w = W q̇ + (c, ∂φ_j/∂t),
///   q̇⁺ = q̇ + M⁻¹Wᵀ μ,   (W M⁻¹ Wᵀ) μ = −(C q̇ + c, (1 + e) v),
/// rows that depend on those before them (redundant constraints) left out,
/// which gives the same q̇⁺ as the minimum-norm multipliers of a run.
/// Between impacts such a model moves on its constraint manifold; the
/// formula for S below holds there, with f∓ the constrained motion's rates
/// and w a tangent vector of the manifold (R maps the manifold into itself).
/// A neighbouring motion x + w reaches the contact at τ + δτ with
/// δτ = −(∇ₓφ · w) / v, ∇ₓφ = (G, 0), and leaves it at
///   w⁺ = S w,   S = R_x + (f⁺ − R_x f⁻ − R_t) ∇ₓφᵀ / v,
/// with f∓ = (q̇∓, q̈∓) the motion's rates just before and after, R_x the
/// 2n × 2n derivative of R in x = (q, q̇) and R_t its derivative in t:
/// the saltation matrix (Aizerman & Gantmacher 1958; Müller 1995). Its top
/// rows are those of [I + (q̇⁺ − q̇⁻) G / v, 0]: a neighbour that hits
/// later flies on with the old velocity meanwhile. For a ball on a floor
/// (x = (z, ż), R = (z, −e ż)) it is S = [[−e, 0], [(1 + e) g / |v|, −e]].
///
/// ∂q̇⁺/∂(q, q̇, t) comes from automatic differentiation: M (L on ad::Jet to
/// second order in q̇), G and ∂φ/∂t (φ on ad::Jet to first order in (q, t))
/// and the solve above are evaluated on numbers that carry their first
/// derivatives along (q, q̇, t). No finite differences.
///
/// Units: S maps a change (δq, δq̇) before the impact to one after it, each
/// in the units of the state (m or rad, m/s or rad/s).

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/ad.hpp"
#include "lagrangian/analysis/tangent_flow.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/constraint_counts.hpp"
#include "lagrangian/mechanics/dof.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/mechanics/impact.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// The impact map at an impact of one contact, with its derivatives.
template <int n>
struct ImpactMap {
  Vec<double, n> qd_plus;                         ///< q̇⁺ (m/s or rad/s)
  Eigen::Matrix<double, n, 2 * n + 1> jacobian;   ///< ∂q̇⁺/∂(q, q̇, t): columns q_0 … q_{n−1}, q̇_0 … q̇_{n−1}, t
  Vec<double, n> gap_gradient;                    ///< G = ∂φ/∂q (m per unit of each coordinate for a distance gap)
  double gap_rate_t = 0;                          ///< ∂φ/∂t (m/s for a distance gap)
  double approach = 0;                            ///< v = G q̇⁻ + ∂φ/∂t before the impact (< 0 when approaching)
  /// γ = d²φ/dt² − G q̈ along the motion before the impact (q̇⁻ᵀ ∂²φ/∂q² q̇⁻
  /// + 2 ∂²φ/∂q∂t q̇⁻ + ∂²φ/∂t²; m/s² for a distance gap): the gap's
  /// acceleration is G q̈ + γ.
  double gamma = 0;
};

namespace detail {

/// The Cholesky factor L (M = L Lᵀ, no pivoting) of a symmetric positive
/// definite M of numbers S, in place of M's lower triangle. DynamicsError
/// when a pivot is not positive.
template <class S, int n>
void factor_spd_in_place(Mat<S, n>& m) {
  using std::sqrt;
  const int size = static_cast<int>(m.rows());
  double largest = 0;
  for (int j = 0; j < size; ++j) largest = std::max(largest, std::abs(ad::value_of(m(j, j))));
  for (int j = 0; j < size; ++j) {
    S d = m(j, j);
    for (int k = 0; k < j; ++k) d -= m(j, k) * m(j, k);
    // The pivots are the squares of the Cholesky factor's diagonal; each
    // must exceed singular_mass_tolerance times M's largest diagonal entry.
    if (!(ad::value_of(d) > 0.0) || ad::value_of(d) < singular_mass_tolerance * largest)
      throw DynamicsError("impact map: the mass matrix M = d2L/dqd2 is singular or not positive definite");
    m(j, j) = sqrt(d);
    for (int i = j + 1; i < size; ++i) {
      S s = m(i, j);
      for (int k = 0; k < j; ++k) s -= m(i, k) * m(j, k);
      m(i, j) = s / m(j, j);
    }
  }
}

/// Solves L Lᵀ w = b in place of b, L from factor_spd_in_place().
template <class S, int n, class V>
void solve_factored_in_place(const Mat<S, n>& m, V& b) {
  const int size = static_cast<int>(m.rows());
  for (int i = 0; i < size; ++i) {  // L y = b
    for (int k = 0; k < i; ++k) b[i] -= m(i, k) * b[k];
    b[i] /= m(i, i);
  }
  for (int i = size - 1; i >= 0; --i) {  // Lᵀ w = y
    for (int k = i + 1; k < size; ++k) b[i] -= m(k, i) * b[k];
    b[i] /= m(i, i);
  }
}

/// x ↦ M⁻¹ x for a symmetric positive definite M of numbers S (Cholesky,
/// no pivoting): solves M w = b in place of b (M overwritten by its
/// factor). DynamicsError when a pivot is not positive.
template <class S, int n>
void solve_spd_in_place(Mat<S, n>& m, Vec<S, n>& b) {
  factor_spd_in_place(m);
  solve_factored_in_place(m, b);
}

/// The restitution coefficient of `contact`; AnalysisError unless the
/// model declares restitution().
template <class M>
double restitution_of(const M& model, int contact, const std::string& prefix) {
  if constexpr (has_restitution_v<M>) {
    return restitution_coefficients(model)[static_cast<std::size_t>(contact)];
  } else {
    (void)contact;
    throw AnalysisError(prefix + "model '" + model_name(model) +
                        "' has contacts without restitution coefficients: its impacts cannot be crossed");
  }
}

}  // namespace detail

namespace detail {
/// Newton's law of the file comment on numbers B.
template <class B, int n>
struct ImpactLaw {
  Vec<B, n> plus;      ///< q̇⁺
  Vec<B, n> gradient;  ///< G = ∂φ_j/∂q
  B rate_t;            ///< ∂φ_j/∂t
  B approach;          ///< v = G q̇ + ∂φ_j/∂t
  B gap;               ///< φ_j
};

/// The model's own holonomic rows: holonomic_count() less the rows of the
/// contacts it holds shut at a rest (held_count(), after its own: the
/// tangent runs' resting contacts, whose impact maps are those of the
/// contacts alone).
template <class E>
int declared_holonomic_count(const E& eval) {
  int held = 0;
  if constexpr (requires { eval.held_count(); }) held = eval.held_count();
  return holonomic_count(eval) - held;
}

/// The change of q̇ at an impact under holonomic and Pfaffian rows (the
/// file comment): Δq̇ = M⁻¹Wᵀμ with W = [C; G] and
/// (W M⁻¹ Wᵀ) μ = −(C q̇ + c, closing), on numbers B. `mass` is M
/// (overwritten by its Cholesky factor), `gradient` G and `closing`
/// (1 + e) v. A holonomic row g gives C = ∂g/∂q and c = ∂g/∂t by a Jet
/// along (q, t); a Pfaffian row A q̇ + a gives A by the same Jet type along
/// q̇ and its value is C q̇ + c. The Cholesky factor of W M⁻¹ Wᵀ leaves out
/// the rows whose pivot is at most rank_tolerance of its largest diagonal
/// entry (rows that depend on those before them: redundant constraints,
/// their μ 0); DynamicsError when the contact's own row is one (its gap does
/// not change along the motions the constraints allow).
template <class B, class E, int n>
Vec<B, n> impulse_under_rows(const E& eval, Mat<B, n>& mass, const Vec<B, n>& qx, const Vec<B, n>& qdx, const B& tx,
                             const Vec<B, n>& gradient, const B& closing, int contact) {
  using std::sqrt;
  const int mh = declared_holonomic_count(eval), mp = pfaffian_count(eval), rows = mh + mp + 1;
  Eigen::Matrix<B, Dynamic, n> w(rows, n);
  Eigen::Matrix<B, Dynamic, 1> mu(rows);  // the right-hand side, then μ
  using G = ad::Jet<B, n + 1, 1>;
  if constexpr (holonomic_count_v<E> != 0) {
    Vec<G, n> qg;
    for (int k = 0; k < n; ++k) qg[k] = G::variable(qx[k], k);
    const auto g = eval.holonomic(qg, G::variable(tx, n));
    for (int i = 0; i < mh; ++i) {
      B rate = g[i].g[n];
      for (int k = 0; k < n; ++k) {
        w(i, k) = g[i].g[k];
        rate += g[i].g[k] * qdx[k];
      }
      mu[i] = -rate;
    }
  }
  if constexpr (pfaffian_count_v<E> != 0) {
    Vec<G, n> qg, qdg;
    for (int k = 0; k < n; ++k) {
      qg[k] = G(qx[k]);
      qdg[k] = G::variable(qdx[k], k);
    }
    const auto a = eval.pfaffian(qg, qdg, G(tx));
    for (int i = 0; i < mp; ++i) {
      for (int k = 0; k < n; ++k) w(mh + i, k) = a[i].g[k];
      mu[mh + i] = -a[i].v;
    }
  }
  for (int k = 0; k < n; ++k) w(rows - 1, k) = gradient[k];
  mu[rows - 1] = -closing;
  // X = M⁻¹ Wᵀ and the lower triangle of S = W X.
  factor_spd_in_place(mass);
  Eigen::Matrix<B, n, Dynamic> x(n, rows);
  for (int r = 0; r < rows; ++r) {
    Vec<B, n> column = w.row(r).transpose();
    solve_factored_in_place(mass, column);
    x.col(r) = column;
  }
  Eigen::Matrix<B, Dynamic, Dynamic> s(rows, rows);
  double largest = 0;
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j <= i; ++j) {
      B sum(0.0);
      for (int k = 0; k < n; ++k) sum += w(i, k) * x(k, j);
      s(i, j) = sum;
    }
    largest = std::max(largest, std::abs(ad::value_of(s(i, i))));
  }
  std::vector<char> kept(static_cast<std::size_t>(rows), 0);
  for (int j = 0; j < rows; ++j) {
    B d = s(j, j);
    for (int k = 0; k < j; ++k)
      if (kept[static_cast<std::size_t>(k)]) d -= s(j, k) * s(j, k);
    if (!(ad::value_of(d) > rank_tolerance * largest)) {
      if (j == rows - 1)
        throw DynamicsError("impact map: the gap of contact " + std::to_string(contact) +
                            " does not change along the motions the holonomic and Pfaffian constraints allow here");
      continue;
    }
    kept[static_cast<std::size_t>(j)] = 1;
    s(j, j) = sqrt(d);
    for (int i = j + 1; i < rows; ++i) {
      B sum = s(i, j);
      for (int k = 0; k < j; ++k)
        if (kept[static_cast<std::size_t>(k)]) sum -= s(i, k) * s(j, k);
      s(i, j) = sum / s(j, j);
    }
  }
  for (int i = 0; i < rows; ++i) {  // L y = b over the rows kept
    if (!kept[static_cast<std::size_t>(i)]) {
      mu[i] = B(0.0);
      continue;
    }
    for (int k = 0; k < i; ++k)
      if (kept[static_cast<std::size_t>(k)]) mu[i] -= s(i, k) * mu[k];
    mu[i] /= s(i, i);
  }
  for (int i = rows - 1; i >= 0; --i) {  // Lᵀ μ = y
    if (!kept[static_cast<std::size_t>(i)]) continue;
    for (int k = i + 1; k < rows; ++k)
      if (kept[static_cast<std::size_t>(k)]) mu[i] -= s(k, i) * mu[k];
    mu[i] /= s(i, i);
  }
  Vec<B, n> change;
  for (int k = 0; k < n; ++k) {
    B sum(0.0);
    for (int r = 0; r < rows; ++r) sum += x(k, r) * mu[r];
    change[k] = sum;
  }
  return change;
}

/// The law at (q, q̇, t) given as numbers B, for the model or its seeded
/// twin `eval` (sensitivity.hpp) and the restitution coefficient e (a
/// double or a B). B carries the derivatives wanted: along (q, q̇, t) for
/// the impact map, along a parameter for its parameter column. A model
/// with holonomic or Pfaffian rows keeps them (impulse_under_rows()).
/// DynamicsError as impact_map().
template <class B, class E, int n, class R>
ImpactLaw<B, n> impact_law(const E& eval, const Vec<B, n>& qx, const Vec<B, n>& qdx, const B& tx, int contact,
                           const R& e) {
  ImpactLaw<B, n> out;
  // M: L to second order in q̇.
  using H = ad::Jet<B, n, 2>;
  Vec<H, n> qh, qdh;
  for (int k = 0; k < n; ++k) {
    qh[k] = H(qx[k]);
    qdh[k] = H::variable(qdx[k], k);
  }
  const H l = detail::lagrangian_of(eval, qh, qdh, H(tx));
  Mat<B, n> mass;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) mass(i, j) = l.hess(i, j);
  // G and ∂φ/∂t: the gap to first order in (q, t).
  using G = ad::Jet<B, n + 1, 1>;
  Vec<G, n> qg;
  for (int k = 0; k < n; ++k) qg[k] = G::variable(qx[k], k);
  const G phi = G(eval.unilateral(qg, G::variable(tx, n))[contact]);
  Vec<B, n> w;
  B v = phi.g[n];
  for (int k = 0; k < n; ++k) {
    w[k] = phi.g[k];
    out.gradient[k] = phi.g[k];
    v += phi.g[k] * qdx[k];
  }
  out.rate_t = phi.g[n];
  out.approach = v;
  out.gap = phi.v;
  if constexpr (bilateral_rows_v<E> != 0) {
    if (declared_holonomic_count(eval) + pfaffian_count(eval) > 0) {
      const Vec<B, n> change = impulse_under_rows(eval, mass, qx, qdx, tx, out.gradient, (1.0 + e) * v, contact);
      for (int i = 0; i < n; ++i) out.plus[i] = qdx[i] + change[i];
      return out;
    }
  }
  detail::solve_spd_in_place(mass, w);  // w = M⁻¹ Gᵀ
  B gw(0.0);
  for (int k = 0; k < n; ++k) gw += phi.g[k] * w[k];
  if (!(ad::value_of(gw) > 0.0))
    throw DynamicsError("impact map: contact " + std::to_string(contact) +
                        " has G M^-1 G^T = 0 (its gap does not change with the coordinates here)");
  const B scale = (1.0 + e) * v / gw;
  for (int i = 0; i < n; ++i) out.plus[i] = qdx[i] - scale * w[i];
  return out;
}

/// impact_map() with the restitution coefficient e given (the tangent run
/// reads them once).
template <class M>
ImpactMap<coordinate_count_v<M>> impact_map_with(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                                 const Vec<double, coordinate_count_v<M>>& qd, double t, int contact,
                                                 double e) {
  constexpr int n = coordinate_count_v<M>;
  using D = ad::Jet<double, 2 * n + 1, 1>;  // along (q, q̇, t)
  Vec<D, n> qx, qdx;
  for (int k = 0; k < n; ++k) {
    qx[k] = D::variable(q[k], k);
    qdx[k] = D::variable(qd[k], n + k);
  }
  const ImpactLaw<D, n> law = impact_law(model, qx, qdx, D::variable(t, 2 * n), contact, e);
  ImpactMap<n> out;
  for (int i = 0; i < n; ++i) {
    out.qd_plus[i] = law.plus[i].v;
    for (int c = 0; c < 2 * n + 1; ++c) out.jacobian(i, c) = law.plus[i].g[c];
    out.gap_gradient[i] = law.gradient[i].v;
  }
  out.gap_rate_t = law.rate_t.v;
  out.approach = law.approach.v;
  // γ: the gap to second order along the path direction (q̇, 1).
  using P = ad::Jet<double, 1, 2>;
  Vec<P, n> qp;
  P tp;
  ad::along_path(q, qd, t, qp, tp);
  out.gamma = P(model.unilateral(qp, tp)[contact]).hess(0, 0);
  return out;
}
}  // namespace detail

/// q̇⁺ and its derivatives at an impact of contact `contact` (an index among
/// the model's unilateral constraints) at (q, q̇⁻, t), by the law of the
/// file comment with the model's restitution coefficient, the model's
/// holonomic and Pfaffian rows kept. For models with a fixed number of
/// coordinates; DynamicsError when M is singular or not positive definite
/// or the contact's G M⁻¹ Gᵀ vanishes (under constraints: when its gap does
/// not change along the motions they allow).
template <class M>
ImpactMap<coordinate_count_v<M>> impact_map(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                            const Vec<double, coordinate_count_v<M>>& qd, double t, int contact) {
  check_model<M>();
  constexpr int n = coordinate_count_v<M>;
  static_assert(n != Dynamic, "impact_map: for models with a fixed coordinate_count");
  static_assert(unilateral_count_v<M> != 0, "impact_map: for models with contacts");
  if (contact < 0 || contact >= unilateral_count(model))
    throw OptionError("impact_map: contact index " + std::to_string(contact) + " is outside [0, " +
                      std::to_string(unilateral_count(model)) + ")");
  return detail::impact_map_with(model, q, qd, t, contact, detail::restitution_of(model, contact, "impact_map: "));
}

namespace detail {
/// S (2n × 2n, column-major, into `out`) from the impact map's q̇⁻, q̇⁺,
/// ∂q̇⁺/∂(q, q̇, t) (n × (2n + 1), column-major), G, v and the
/// accelerations q̈∓ (src/analysis/saltation.cpp).
/// `scratch` holds 2n values.
void saltation_from(int n, const double* qd_minus, const double* qdd_minus, const double* qd_plus,
                    const double* qdd_plus, const double* jacobian, const double* gap_gradient, double approach,
                    double* scratch, double* out);
}  // namespace detail

/// The saltation matrix S (file comment) of an impact of contact `contact`
/// at (q, q̇⁻, t): a change w of the state just before the impact becomes
/// S w just after it. For a model with holonomic or Pfaffian rows, w is a
/// tangent vector of the constraint manifold (f∓ are the constrained
/// motion's rates; S maps the manifold's tangent space before the impact
/// into the one after it). AnalysisError when the contact is not
/// approaching (v ≥ 0: S is not defined at a grazing contact).
template <class M>
Mat<double, 2 * coordinate_count_v<M>> saltation_matrix(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                                        const Vec<double, coordinate_count_v<M>>& qd, double t,
                                                        int contact) {
  constexpr int n = coordinate_count_v<M>;
  const ImpactMap<n> map = impact_map(model, q, qd, t, contact);
  if (!(map.approach < 0.0))
    throw AnalysisError("saltation_matrix: contact " + std::to_string(contact) +
                        " is not approaching (v = " + std::to_string(map.approach) + " >= 0)");
  Vec<double, n> before, after;
  Eigen::Matrix<double, n, 1> unused;
  const Eigen::Matrix<double, 2 * n, 1> none = Eigen::Matrix<double, 2 * n, 1>::Zero();
  state_jvp<1>(model, q, qd, t, none, before, unused);
  state_jvp<1>(model, q, map.qd_plus, t, none, after, unused);
  Mat<double, 2 * n> s;
  Eigen::Matrix<double, 2 * n, 1> scratch;
  detail::saltation_from(n, qd.data(), before.data(), map.qd_plus.data(), after.data(), map.jacobian.data(),
                         map.gap_gradient.data(), map.approach, scratch.data(), s.data());
  return s;
}

}  // namespace lagrangian
