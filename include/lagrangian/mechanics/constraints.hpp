#pragma once
/// \file constraints.hpp
/// Constrained systems: holonomic constraints g(q, t) = 0 and Pfaffian
/// (nonholonomic) constraints A(q, t) q̇ + a(q, t) = 0, declared in the model
/// like T and V:
///
///   template <class S> Vec<S, m> holonomic(const Vec<S, n>& q, const S& t) const;
///   template <class S> Vec<S, k> pfaffian(const Vec<S, n>& q, const Vec<S, n>& qd, const S& t) const;
///
/// (the Pfaffian expression is written as the whole of A q̇ + a and must be
/// affine in q̇), optionally with `holonomic_names()` / `pfaffian_names()`;
/// and unilateral constraints g(q, t) ≥ 0,
///
///   template <class S> Vec<S, u> unilateral(const Vec<S, n>& q, const S& t) const;
///
/// which act like holonomic ones while active (contact) and are released when
/// their multiplier would pull (see simulate.hpp).
///
/// All constraints are used at the velocity level, C(q, t) q̇ + c(q, t) = 0, with
/// the rows of C the holonomic Jacobian G = ∂g/∂q and the Pfaffian A = ∂φ/∂q̇.
/// Differentiating once more, C q̈ + γ = 0, where γ is the second derivative of
/// g along the path (δq, δt) = (q̇, 1), and for Pfaffian rows the derivative of
/// φ along (q̇, 1) at fixed q̇. With Lagrange multipliers λ the equations of
/// motion are the saddle-point system
///   M q̈ = f + Cᵀ λ,    C q̈ = −γ − b,
/// where f is the unconstrained right-hand side, Cᵀλ the generalized
/// constraint force (λ is the force along +∇g of each constraint, in N for a
/// length constraint) and b the Baumgarte term. It is solved by the Schur
/// complement S = C M⁻¹ Cᵀ, factorised with a complete orthogonal
/// decomposition so that redundant constraints (S singular) still give the
/// minimum-norm multipliers and the right q̈.

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "lagrangian/ad.hpp"
#include "lagrangian/mechanics/detail/min_norm_solver.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/detail/csv_header.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

namespace detail {
/// True when R is a column vector with a number of rows known at compile time.
template <class R>
concept fixed_column = requires {
  { R::RowsAtCompileTime } -> std::convertible_to<int>;
  { R::ColsAtCompileTime } -> std::convertible_to<int>;
} && R::ColsAtCompileTime == 1 && R::RowsAtCompileTime >= 1;
/// True when R is a column vector whose number of rows is known at run time only.
template <class R>
concept dynamic_column = requires {
  { R::RowsAtCompileTime } -> std::convertible_to<int>;
  { R::ColsAtCompileTime } -> std::convertible_to<int>;
} && R::ColsAtCompileTime == 1 && R::RowsAtCompileTime == Dynamic;

/// Rows of a constraint function's result R: its compile-time rows, or
/// Dynamic for a run-time sized column (whose model then says the count,
/// see holonomic_count()). Any other result stops compilation with one
/// sentence and counts as no rows, so nothing else is compiled for it.
template <class R, int kind>
constexpr int rows_of() {
  constexpr bool column = fixed_column<R> || dynamic_column<R>;
  static_assert(column || kind != 0,
                "lagrangian: holonomic(q, t) must return lagrangian::Vec<S, m>, one entry per constraint (also for a "
                "single constraint: Vec<S, 1>), not a scalar");
  static_assert(column || kind != 1,
                "lagrangian: unilateral(q, t) must return lagrangian::Vec<S, u>, one entry per contact (also for a "
                "single contact: Vec<S, 1>), not a scalar");
  static_assert(column || kind != 2,
                "lagrangian: pfaffian(q, qd, t) must return lagrangian::Vec<S, k>, one entry per constraint (also for "
                "a single constraint: Vec<S, 1>), not a scalar");
  if constexpr (fixed_column<R>) {
    return R::RowsAtCompileTime;
  } else if constexpr (dynamic_column<R>) {
    return Dynamic;
  } else {
    return 0;
  }
}
template <class M>
constexpr int unilateral_rows() {
  if constexpr (has_unilateral_c<M>) {
    using V = Vec<double, coordinate_count_v<M>>;
    using R = std::decay_t<decltype(std::declval<const M&>().unilateral(std::declval<const V&>(), 0.0))>;
    return rows_of<R, 1>();
  } else {
    return 0;
  }
}
template <class M>
constexpr int holonomic_rows() {
  if constexpr (has_holonomic_c<M>) {
    using V = Vec<double, coordinate_count_v<M>>;
    using R = std::decay_t<decltype(std::declval<const M&>().holonomic(std::declval<const V&>(), 0.0))>;
    return rows_of<R, 0>();
  } else {
    return 0;
  }
}
template <class M>
constexpr int pfaffian_rows() {
  if constexpr (has_pfaffian_c<M>) {
    using V = Vec<double, coordinate_count_v<M>>;
    using R =
        std::decay_t<decltype(std::declval<const M&>().pfaffian(std::declval<const V&>(), std::declval<const V&>(), 0.0))>;
    return rows_of<R, 2>();
  } else {
    return 0;
  }
}
}  // namespace detail

namespace detail {
/// a + b for row counts, Dynamic when either is.
constexpr int add_rows(int a, int b) { return a == Dynamic || b == Dynamic ? Dynamic : a + b; }
}  // namespace detail

/// Number of holonomic constraints a model declares (0 when none, Dynamic
/// when the model says it at run time).
template <class M>
inline constexpr int holonomic_count_v = detail::holonomic_rows<M>();
/// Number of Pfaffian constraints a model declares (0 when none, or Dynamic).
template <class M>
inline constexpr int pfaffian_count_v = detail::pfaffian_rows<M>();
/// Number of unilateral constraints g(q, t) ≥ 0 a model declares.
template <class M>
inline constexpr int unilateral_count_v = detail::unilateral_rows<M>();
/// Rows at the position level: holonomic, then unilateral.
template <class M>
inline constexpr int position_rows_v = detail::add_rows(holonomic_count_v<M>, unilateral_count_v<M>);
/// Total number of constraint rows: holonomic, unilateral, Pfaffian (in
/// that order); Dynamic when any kind is counted at run time.
template <class M>
inline constexpr int constraint_count_v = detail::add_rows(position_rows_v<M>, pfaffian_count_v<M>);
/// True when the model declares constraints (for run-time counts: may
/// declare; has_constraints(model) says whether it does).
template <class M>
inline constexpr bool has_constraints_v = constraint_count_v<M> != 0;
/// True when the model's constraint counts are known at run time only: its
/// holonomic(q, t), unilateral(q, t) and pfaffian(q, qd, t) return run-time
/// sized vectors and it says their lengths by `int holonomic_count() const`,
/// `int unilateral_count() const` and `int pfaffian_count() const` (a
/// model says the counts of the kinds it declares).
template <class M>
inline constexpr bool runtime_constraint_counts_v = constraint_count_v<M> == Dynamic;

/// Holonomic constraints of `model` (m), at run time.
template <class M>
int holonomic_count(const M& model) {
  if constexpr (holonomic_count_v<M> == Dynamic) {
    static_assert(requires { { model.holonomic_count() } -> std::convertible_to<int>; },
                  "lagrangian: a model whose holonomic(q, t) returns a run-time sized vector says its length by "
                  "int holonomic_count() const");
    return model.holonomic_count();
  } else {
    (void)model;
    return holonomic_count_v<M>;
  }
}
/// Pfaffian constraints of `model` (k), at run time.
template <class M>
int pfaffian_count(const M& model) {
  if constexpr (pfaffian_count_v<M> == Dynamic) {
    static_assert(requires { { model.pfaffian_count() } -> std::convertible_to<int>; },
                  "lagrangian: a model whose pfaffian(q, qd, t) returns a run-time sized vector says its length by "
                  "int pfaffian_count() const");
    return model.pfaffian_count();
  } else {
    (void)model;
    return pfaffian_count_v<M>;
  }
}
/// Unilateral constraints (contacts) of `model`, at run time.
template <class M>
int unilateral_count(const M& model) {
  if constexpr (unilateral_count_v<M> == Dynamic) {
    static_assert(requires { { model.unilateral_count() } -> std::convertible_to<int>; },
                  "lagrangian: a model whose unilateral(q, t) returns a run-time sized vector says its length by "
                  "int unilateral_count() const");
    return model.unilateral_count();
  } else {
    (void)model;
    return unilateral_count_v<M>;
  }
}
/// Position-level rows (holonomic, then unilateral) of `model`.
template <class M>
int position_rows(const M& model) {
  return holonomic_count(model) + unilateral_count(model);
}
/// All constraint rows of `model`.
template <class M>
int constraint_count(const M& model) {
  return position_rows(model) + pfaffian_count(model);
}
/// True when `model` has constraints at run time.
template <class M>
bool has_constraints(const M& model) {
  if constexpr (!has_constraints_v<M>) {
    (void)model;
    return false;
  } else {
    return constraint_count(model) > 0;
  }
}
/// True when `model` has bilateral constraints (holonomic or Pfaffian), not only contacts.
template <class M>
bool has_bilateral_constraints(const M& model) {
  return holonomic_count(model) + pfaffian_count(model) > 0;
}
/// Which unilateral constraints (contacts) are active: held shut as
/// constraint rows, while the others carry no force. Contact j is the
/// model's unilateral constraint j; there may be any number. Sets of
/// contacts below 64 are stored inline, so copying them never allocates.
class ActiveSet {
 public:
  /// No contact active: the bilateral rows only.
  ActiveSet() = default;
  /// Every contact active, however many there are.
  static ActiveSet all() {
    ActiveSet s;
    s.all_ = true;
    return s;
  }
  /// Contact j alone.
  static ActiveSet only(int j) {
    ActiveSet s;
    s.insert(j);
    return s;
  }
  bool contains(int j) const {
    if (all_) return true;
    const auto [w, bit] = place(j);
    return w == 0 ? (low_ & bit) != 0 : w <= high_.size() && (high_[w - 1] & bit) != 0;
  }
  /// Whether any of the contacts 0 … count − 1 is active.
  bool any(int count) const {
    if (all_) return count > 0;
    for (int j = 0; j < count; ++j)
      if (contains(j)) return true;
    return false;
  }
  /// Contact j becomes active.
  void insert(int j) {
    if (all_) return;
    const auto [w, bit] = place(j);
    if (w == 0) {
      low_ |= bit;
      return;
    }
    if (high_.size() < w) high_.resize(w, 0);
    high_[w - 1] |= bit;
  }
  /// Contact j becomes inactive (a set made by all() lists no contacts to
  /// remove: std::logic_error).
  void erase(int j) {
    if (all_) throw std::logic_error("ActiveSet::erase on ActiveSet::all(), which does not know its contacts");
    const auto [w, bit] = place(j);
    if (w == 0) {
      low_ &= ~bit;
    } else if (w <= high_.size()) {
      high_[w - 1] &= ~bit;
    }
  }
  /// This set without contact j.
  ActiveSet without(int j) const {
    ActiveSet s = *this;
    s.erase(j);
    return s;
  }

 private:
  /// The word (0: inline) and bit of contact j.
  static std::pair<std::size_t, std::uint64_t> place(int j) {
    const auto u = static_cast<std::size_t>(j);
    return {u / 64, std::uint64_t{1} << (u % 64)};
  }
  bool all_ = false;
  std::uint64_t low_ = 0;
  std::vector<std::uint64_t> high_;
};
/// Every unilateral constraint active.
inline const ActiveSet all_active = ActiveSet::all();

/// Relative tolerance of the rank decisions: a singular value σ_i counts when
/// σ_i > rank_tolerance · σ_max (and σ_max > 0).
inline constexpr double rank_tolerance = 1e-10;

namespace detail {
/// Appends one kind's names (the model's own, checked for count, or
/// prefix0, prefix1, …).
template <class Names>
void append_constraint_names(std::vector<std::string>& out, const Names* given, int count, const char* prefix,
                             const char* accessor, const char* kind) {
  if (given) {
    const std::size_t before = out.size();
    for (const auto& s : *given) out.emplace_back(s);
    if (out.size() - before != static_cast<std::size_t>(count))
      throw ConstraintError(std::string(accessor) + "() gives " + std::to_string(out.size() - before) +
                            " names for " + std::to_string(count) + " " + kind + " constraints");
  } else {
    for (int i = 0; i < count; ++i) out.push_back(prefix + std::to_string(i));
  }
}
}  // namespace detail

/// Names of the constraints, holonomic, unilateral, then Pfaffian: the
/// model's own, or g0, g1, …, u0, …, a0, ….
template <class M>
std::vector<std::string> constraint_names(const M& model) {
  std::vector<std::string> names;
  if constexpr (holonomic_count_v<M> != 0) {
    if constexpr (requires { model.holonomic_names(); }) {
      const auto given = model.holonomic_names();
      detail::append_constraint_names(names, &given, holonomic_count(model), "g", "holonomic_names", "holonomic");
    } else {
      detail::append_constraint_names<std::vector<std::string>>(names, nullptr, holonomic_count(model), "g", "", "");
    }
  }
  if constexpr (unilateral_count_v<M> != 0) {
    if constexpr (requires { model.unilateral_names(); }) {
      const auto given = model.unilateral_names();
      detail::append_constraint_names(names, &given, unilateral_count(model), "u", "unilateral_names", "unilateral");
    } else {
      detail::append_constraint_names<std::vector<std::string>>(names, nullptr, unilateral_count(model), "u", "", "");
    }
  }
  if constexpr (pfaffian_count_v<M> != 0) {
    if constexpr (requires { model.pfaffian_names(); }) {
      const auto given = model.pfaffian_names();
      detail::append_constraint_names(names, &given, pfaffian_count(model), "a", "pfaffian_names", "Pfaffian");
    } else {
      detail::append_constraint_names<std::vector<std::string>>(names, nullptr, pfaffian_count(model), "a", "", "");
    }
  }
  return names;
}

/// True when the model gives the units of its constraint functions.
template <class M>
inline constexpr bool has_constraint_units_v = requires(const M& m) {
  { m.constraint_units() };
};

/// SI unit of each constraint's multiplier λ, in constraint_names() order:
/// λ ∂g/∂q is a generalized force, so λ is work per unit of the constraint
/// function, from the model's optional `constraint_units()` (the unit of
/// each g, gap or Pfaffian row A δq): "m" gives "N", "rad" "N*m", "m^2"
/// "N/m". "" for each when the model gives none. Throws ConstraintError
/// when it gives a different number of units than constraints.
template <class M>
std::vector<std::string> multiplier_units(const M& model) {
  const std::size_t count = constraint_names(model).size();
  std::vector<std::string> units;
  if constexpr (has_constraint_units_v<M>) {
    for (const auto& u : model.constraint_units()) units.push_back(detail::csv_force_unit(u));
    if (units.size() != count)
      throw ConstraintError("constraint_units() gives " + std::to_string(units.size()) + " units for " +
                            std::to_string(count) + " constraints");
  } else {
    units.resize(count);
  }
  return units;
}

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

/// Evaluates g, G, ġ, γ (holonomic) and φ, A, β (Pfaffian) by AD into `cs`,
/// sized to the model's rows (nothing allocated when `cs` has those sizes
/// already). For a run-time sized model (n = Dynamic) the Jacobians come
/// from first-order passes over blocks of coordinates, and a Pfaffian
/// row's affinity in q̇ is the model's to ensure (a text model checks it
/// when read); a fixed-size model's is checked here.
template <class M, class CS>
void constraint_state_into(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                           const Vec<double, coordinate_count_v<M>>& qd, double t, CS& cs) {
  constexpr int n = coordinate_count_v<M>;
  const int size = static_cast<int>(q.size());
  const int mh = holonomic_count(model);
  const int mu = unilateral_count(model);
  const int mp = pfaffian_count(model);
  const int mpos = mh + mu;
  cs.jacobian.setZero(mpos + mp, size);
  cs.position.setZero(mpos + mp);
  cs.velocity.resize(mpos + mp);
  cs.gamma.resize(mpos + mp);
  // Position-level rows (holonomic, then unilateral): g and G = ∂g/∂q from
  // first-order passes, ġ and γ from one second-order pass along (q̇, 1).
  auto position_rows = [&](int offset, int rows, const char* function, auto&& fn) {
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
    for (int k = 0; k < size; ++k) {
      qp[k] = J2(q[k]);
      qp[k].g[0] = qd[k];
    }
    J2 tp(t);
    tp.g[0] = 1.0;
    const auto g2 = fn(qp, tp);
    detail::check_rows(g2, rows, function);
    for (int i = 0; i < rows; ++i) {
      cs.velocity[offset + i] = g2[i].g[0];
      cs.gamma[offset + i] = g2[i].hess(0, 0);
    }
  };
  if constexpr (holonomic_count_v<M> != 0) {
    if (mh > 0)
      position_rows(0, mh, "holonomic()", [&](const auto& qq, const auto& tt) { return model.holonomic(qq, tt); });
  }
  if constexpr (unilateral_count_v<M> != 0) {
    if (mu > 0)
      position_rows(mh, mu, "unilateral()", [&](const auto& qq, const auto& tt) { return model.unilateral(qq, tt); });
  }
  if constexpr (pfaffian_count_v<M> != 0) {
    if (mp == 0) return;
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
      for (int k = 0; k < size; ++k) {
        qp[k] = J(q[k]);
        qp[k].g[0] = qd[k];
        qdp[k] = J(qd[k]);
      }
      J tp(t);
      tp.g[0] = 1.0;
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

/// Scratch space of a constrained evaluation, for n coordinates and c
/// constraint rows (the template sizes, or given at run time for Dynamic).
template <int N, int C>
struct ConstraintWorkspace {
  ConstraintWorkspace() : ConstraintWorkspace(N == Dynamic ? 0 : N, C == Dynamic ? 0 : C) {}
  ConstraintWorkspace(int n, int c)
      : minv_ct(n, c), schur(c, c), schur_solver(c, c), multipliers(c), constraint_forces(n), free(n), target(c) {}
  Eigen::Matrix<double, N, C> minv_ct;  ///< M⁻¹ Cᵀ
  Mat<double, C> schur;                 ///< S = C M⁻¹ Cᵀ
  /// S⁺ by a decomposition compiled once in the library (min_norm_solver.hpp),
  /// its storage allocated once here.
  detail::MinNormSolver schur_solver;
  Vec<double, C> multipliers;        ///< λ
  Vec<double, N> constraint_forces;  ///< Cᵀ λ
  Vec<double, N> free;               ///< M⁻¹ f
  Vec<double, C> target;             ///< −γ − b − C M⁻¹ f
  ConstraintState<N, C> state;       ///< C, g, ġ, γ at the last evaluation
};

/// The ConstraintWorkspace of model M (its n coordinates and all its constraint rows).
template <class M>
using ConstraintWorkspaceFor = ConstraintWorkspace<coordinate_count_v<M>, constraint_count_v<M>>;

/// A ConstraintWorkspaceFor<M> sized for `model` (needed when its sizes are run-time ones).
template <class M>
ConstraintWorkspaceFor<M> constraint_workspace(const M& model) {
  return ConstraintWorkspaceFor<M>(model_size(model), constraint_count(model));
}

/// q̈ and λ of a constrained model (see the file comment for the system).
/// `omega` > 0 adds the Baumgarte term with that rate (1/s); unilateral
/// constraints not in `active` are left out. A model whose only constraints
/// are unilateral, none of them active, takes the unconstrained path (λ = 0).
/// Nothing is allocated when `cw` is sized for the model.
template <class M>
void constrained_accelerations(const M& model, Workspace<coordinate_count_v<M>>& ws, ConstraintWorkspaceFor<M>& cw,
                               const Vec<double, coordinate_count_v<M>>& q, const Vec<double, coordinate_count_v<M>>& qd,
                               double t, Vec<double, coordinate_count_v<M>>& out, double omega = 0.0,
                               const ActiveSet& active = all_active) {
  if (!has_bilateral_constraints(model) && !active.any(unilateral_count(model))) {
    // contacts only, none touching (or no constraints at all): free motion
    detail::free_accelerations(model, ws, q, qd, t, out);
    cw.multipliers.setZero();
    cw.constraint_forces.setZero();
    return;
  }
  evaluate(model, ws, q, qd, t);
  detail::factor_mass_matrix(ws, q, qd, t);
  auto& cs = cw.state;
  constraint_state_into(model, q, qd, t, cs);
  drop_inactive(model, cs, active);
  const int rows = static_cast<int>(cs.position.size());
  const int mh = position_rows(model);
  cw.target = -cs.gamma;
  if (omega > 0) {
    for (int i = 0; i < rows; ++i) {
      if (i < mh) {
        cw.target[i] -= 2.0 * omega * cs.velocity[i] + omega * omega * cs.position[i];
      } else {
        cw.target[i] -= omega * cs.velocity[i];
      }
    }
  }
  cw.minv_ct = ws.cholesky.solve(cs.jacobian.transpose());
  cw.schur.noalias() = cs.jacobian * cw.minv_ct;
  cw.schur_solver.factorize(cw.schur.data());
  cw.free = ws.cholesky.solve(ws.rhs);
  cw.target.noalias() -= cs.jacobian * cw.free;
  cw.schur_solver.solve(cw.target.data(), cw.multipliers.data());
  cw.constraint_forces.noalias() = cs.jacobian.transpose() * cw.multipliers;
  out = cw.free;
  out.noalias() += cw.minv_ct * cw.multipliers;
}

/// Convenience form of constrained_accelerations() that allocates its own
/// workspaces and returns q̈, every constraint row active, no stabilisation;
/// the multipliers λ go to `*multipliers` when it is given. For repeated
/// calls keep a Workspace and a ConstraintWorkspaceFor<M> and use the form above.
template <class M>
  requires has_constraints_v<M>
Vec<double, coordinate_count_v<M>> constrained_accelerations(const M& model,
                                                             const Vec<double, coordinate_count_v<M>>& q,
                                              const Vec<double, coordinate_count_v<M>>& qd, double t = 0.0,
                                              Vec<double, constraint_count_v<M>>* multipliers = nullptr) {
  Workspace<coordinate_count_v<M>> ws(static_cast<int>(q.size()));
  ConstraintWorkspaceFor<M> cw = constraint_workspace(model);
  Vec<double, coordinate_count_v<M>> qdd(q.size());
  constrained_accelerations(model, ws, cw, q, qd, t, qdd);
  if (multipliers) *multipliers = cw.multipliers;
  return qdd;
}

// The deprecated members are copied by the implicit constructors; the
// pragma keeps that from warning (a use of them by name still warns).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
/// What the constraint Jacobians say about the degrees of freedom at a state.
struct DofReport {
  int coordinates = 0;            ///< n
  int holonomic = 0;              ///< m holonomic constraints declared
  int pfaffian = 0;               ///< k Pfaffian constraints declared
  int unilateral = 0;             ///< unilateral constraints declared (not counted in the ranks)
  int holonomic_rank = 0;         ///< rank of G = ∂g/∂q (SVD, rank_tolerance)
  int velocity_rank = 0;          ///< rank of [G; A]
  int degrees_of_freedom = 0;           ///< configuration degrees of freedom n − rank G
  int velocity_degrees_of_freedom = 0;  ///< velocity degrees of freedom n − rank [G; A]
  /// The same as degrees_of_freedom (the old spelling, deprecated).
  [[deprecated("use degrees_of_freedom")]] int dof = 0;
  /// The same as velocity_degrees_of_freedom.
  [[deprecated("use velocity_degrees_of_freedom")]] int velocity_dof = 0;
  std::vector<std::string> redundant;  ///< constraints whose rows depend on earlier ones
  std::vector<double> singular_values;  ///< of [G; A], descending
  /// A few lines for a terminal.
  std::string summary() const {
    std::ostringstream os;
    os << "coordinates " << coordinates << ", holonomic constraints " << holonomic << " (rank " << holonomic_rank
       << "), Pfaffian constraints " << pfaffian << "\n";
    os << "degrees of freedom " << degrees_of_freedom << " (velocity " << velocity_degrees_of_freedom << ")\n";
    if (!redundant.empty()) {
      os << "redundant:";
      for (const auto& r : redundant) os << " " << r;
      os << "\n";
    }
    return os.str();
  }
};
#pragma GCC diagnostic pop

namespace detail {
/// Numerical rank of a dense matrix: singular values σᵢ (by SVD, descending,
/// into *values when given) above rank_tolerance · σ_max. Compiled once
/// (src/mechanics/numeric_rank.cpp).
int numeric_rank_of(const Eigen::MatrixXd& a, std::vector<double>* values);
template <class Mtx>
int numeric_rank(const Mtx& a, std::vector<double>* values = nullptr) {
  if (a.rows() == 0) return 0;
  return numeric_rank_of(Eigen::MatrixXd(a), values);
}
/// Indices i < rows of the rows of a that add no rank to the rows above
/// them (numeric_rank of the first i + 1 rows equals that of the first i):
/// redundant constraints, or rows that are zero. Compiled once.
std::vector<int> rows_adding_no_rank(const Eigen::MatrixXd& a, int rows);
/// The warning that names a constraint whose Jacobian row adds no rank at t0.
inline std::string redundant_constraint_warning(const std::string& name) {
  return "constraint " + name + " is redundant at t0 (its Jacobian row depends on earlier rows)";
}
}  // namespace detail

/// Degrees of freedom at a state: DOF = n − rank(∂g/∂q), velocity DOF =
/// n − rank([G; A]); constraints whose rows add no rank to the rows before
/// them are reported as redundant, by name.
template <class M>
DofReport dof_report(const M& model, const State<coordinate_count_v<M>>& s, double t = 0.0) {
  check_model<M>();
  DofReport r;
  r.coordinates = model_size(model);
  r.holonomic = holonomic_count(model);
  r.pfaffian = pfaffian_count(model);
  r.unilateral = unilateral_count(model);
  if (has_constraints(model)) {
    auto cs = constraint_state(model, s.q, s.qd, t);
    drop_inactive(model, cs, ActiveSet{});  // bilateral rows only
    const auto names = constraint_names(model);
    r.holonomic_rank = detail::numeric_rank(cs.jacobian.topRows(r.holonomic));
    r.velocity_rank = detail::numeric_rank(cs.jacobian, &r.singular_values);
    // The contact rows, zeroed above, add no rank and are not redundant.
    for (int i : detail::rows_adding_no_rank(Eigen::MatrixXd(cs.jacobian), constraint_count(model))) {
      const bool unilateral = i >= r.holonomic && i < r.holonomic + r.unilateral;
      if (!unilateral) r.redundant.push_back(names[static_cast<std::size_t>(i)]);
    }
  }
  r.degrees_of_freedom = r.coordinates - r.holonomic_rank;
  r.velocity_degrees_of_freedom = r.coordinates - r.velocity_rank;
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-declarations"
  r.dof = r.degrees_of_freedom;  // the old spellings, kept working
  r.velocity_dof = r.velocity_degrees_of_freedom;
#pragma GCC diagnostic pop
  return r;
}

namespace detail {

/// project_positions with the pseudo-inverse's workspace `solver` (sized
/// position rows × n): nothing allocated per call.
template <class M>
int project_positions_with(const M& model, Vec<double, coordinate_count_v<M>>& q, double t, double tolerance,
                           int max_iterations, const ActiveSet& active, MinNormSolver& solver) {
  constexpr int mh_v = position_rows_v<M>;
  if constexpr (mh_v == 0) {
    return 0;
  } else {
    const int mh = position_rows(model);
    if (mh == 0) return 0;
    const Vec<double, coordinate_count_v<M>> zero = Vec<double, coordinate_count_v<M>>::Zero(q.size());
    for (int it = 0; it < max_iterations; ++it) {
      auto cs = constraint_state(model, q, zero, t);
      drop_inactive(model, cs, active);
      const Vec<double, mh_v> g = cs.position.head(mh);
      const double scale = 1.0 + q.template lpNorm<Eigen::Infinity>();
      if (g.template lpNorm<Eigen::Infinity>() <= tolerance * scale) return it;
      const Eigen::Matrix<double, mh_v, coordinate_count_v<M>> G = cs.jacobian.topRows(mh);
      solver.factorize(G.data());
      Vec<double, coordinate_count_v<M>> dq(q.size());
      solver.solve(g.data(), dq.data());
      q -= dq;
      if (!q.allFinite()) break;
    }
    const auto cs = constraint_state(model, q, zero, t);
    std::ostringstream os;
    os.precision(17);
    os << "cannot satisfy the holonomic constraints: after " << max_iterations
       << " Gauss-Newton steps the residuals are";
    const auto names = constraint_names(model);
    for (int i = 0; i < mh; ++i) os << " " << names[static_cast<std::size_t>(i)] << " = " << cs.position[i];
    os << " at t = " << t;
    throw ConstraintError(os.str());
  }
}

/// project_velocities with the workspace `solver` (sized c × c, c the
/// constraint count): nothing allocated per call.
template <class M>
void project_velocities_with(const M& model, Workspace<coordinate_count_v<M>>& ws,
                             const Vec<double, coordinate_count_v<M>>& q, Vec<double, coordinate_count_v<M>>& qd,
                             double t, const ActiveSet& active, MinNormSolver& solver) {
  if constexpr (has_constraints_v<M>) {
    if (!has_constraints(model)) return;
    evaluate(model, ws, q, qd, t);
    auto cs = constraint_state(model, q, qd, t);
    drop_inactive(model, cs, active);
    detail::factor_mass_matrix(ws, q, qd, t);
    const Eigen::Matrix<double, coordinate_count_v<M>, constraint_count_v<M>> minv_ct =
        ws.cholesky.solve(cs.jacobian.transpose());
    constexpr int c = constraint_count_v<M>;
    const Mat<double, c> schur = cs.jacobian * minv_ct;
    solver.factorize(schur.data());
    const Vec<double, c> residual = cs.velocity;
    Vec<double, c> correction(residual.size());
    solver.solve(residual.data(), correction.data());
    qd -= minv_ct * correction;
  }
}

}  // namespace detail

/// Moves q onto g(q, t) = 0 by Gauss–Newton steps q ← q − G⁺ g (G⁺ the
/// minimum-norm pseudo-inverse, by complete orthogonal decomposition) until
/// ‖g‖∞ ≤ tolerance. Returns the number of iterations; throws
/// ConstraintError when `max_iterations` do not reach the tolerance.
template <class M>
int project_positions(const M& model, Vec<double, coordinate_count_v<M>>& q, double t, double tolerance = 1e-12,
                      int max_iterations = 20, const ActiveSet& active = all_active) {
  if constexpr (position_rows_v<M> == 0) {
    return 0;
  } else {
    detail::MinNormSolver solver(position_rows(model), model_size(model));
    return detail::project_positions_with(model, q, t, tolerance, max_iterations, active, solver);
  }
}

/// Projects q̇ onto C q̇ + c = 0 in the M-norm (the nearest consistent
/// velocities in kinetic energy): q̇ ← q̇ − M⁻¹Cᵀ S⁺ (C q̇ + c).
template <class M>
void project_velocities(const M& model, Workspace<coordinate_count_v<M>>& ws,
                        const Vec<double, coordinate_count_v<M>>& q, Vec<double, coordinate_count_v<M>>& qd,
                        double t, const ActiveSet& active = all_active) {
  if constexpr (has_constraints_v<M>) {
    detail::MinNormSolver solver(constraint_count(model), constraint_count(model));
    detail::project_velocities_with(model, ws, q, qd, t, active, solver);
  }
}

/// What consistent_initial_state() found and how sure it is that the state
/// is the nearest one (docs/constraints.md, "Consistent initial states").
struct ConsistentStateReport {
  double distance = 0;           ///< ‖q − q_guess‖₂ (units of q)
  double position_residual = 0;  ///< ‖g(q, t)‖∞ of the holonomic rows
  double velocity_residual = 0;  ///< ‖C q̇ + c‖∞
  int starts = 0;                ///< starts projected onto g = 0 (the guess, SLSQP's point, q_guess ± d eᵢ)
  int candidates = 0;            ///< distinct consistent points they reached
  /// ‖(I − G⁺G)(q_guess − q)‖₂: the tangent part of q_guess − q, 0 at a
  /// stationary point of ‖q − q_guess‖ on g = 0.
  double stationarity = 0;
  /// Smallest eigenvalue of Zᵀ(I − Σμᵢ∇²gᵢ)Z, Gᵀμ = q − q_guess, Z a null-space
  /// basis of G: > 0 at a strict local minimum of the distance (0 when not computed).
  double tangent_curvature = 0;
  bool local_minimum = false;   ///< stationarity ≈ 0 and tangent_curvature > 0
  bool unique = true;           ///< no other candidate with motion left is as near (to 1e-9)
  /// Only when the guess is itself consistent (or there are no position
  /// constraints): otherwise a nearer point the starts missed cannot be ruled out.
  bool nearest_proven = false;
  bool rigid_nearer = false;  ///< a nearer candidate where the rank is n (no motion left) was passed over
  std::string note;           ///< one sentence saying the above
};

/// The nearest consistent initial state: q minimises ‖q − q_guess‖ subject
/// to g(q, t) = 0 — the nearest of the consistent points reached from several
/// starts (Gauss–Newton from the guess, SLSQP, q_guess ± d eᵢ), each slid
/// along the manifold to a stationary point of the distance, then polished
/// to `tolerance` — and q̇ is the M-weighted projection of q̇_guess onto
/// C q̇ + c = 0. Global nearness is not proven (`report` says what is).
/// Throws ConstraintError naming the residuals when no consistent state is
/// found, and when the constraints leave no motion at every point found.
template <class M>
State<coordinate_count_v<M>> consistent_initial_state(const M& model, const State<coordinate_count_v<M>>& guess,
                                                      double t = 0.0,
                                       double tolerance = 1e-12);
/// The same, and what was found into *report (when not null).
template <class M>
State<coordinate_count_v<M>> consistent_initial_state(const M& model, const State<coordinate_count_v<M>>& guess,
                                                      double t, double tolerance, ConsistentStateReport* report);

}  // namespace lagrangian

#include "lagrangian/mechanics/detail/holonomic_derivatives.hpp"
#include "lagrangian/mechanics/detail/consistent.hpp"
