#pragma once
/// \file constraint_counts.hpp
/// How many holonomic, Pfaffian and unilateral constraint rows a model
/// declares (at compile time, or at run time for a model that says so).

#include <string>

#include <Eigen/Core>

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
}  // namespace lagrangian
