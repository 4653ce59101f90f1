#pragma once
/// \file dof.hpp
/// Degrees of freedom at a state from the ranks of the constraint
/// Jacobians, and the constraints whose rows are redundant.

#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/mechanics/active_set.hpp"
#include "lagrangian/mechanics/constraint_counts.hpp"
#include "lagrangian/mechanics/constraint_names.hpp"
#include "lagrangian/mechanics/constraint_state.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

/// Relative tolerance of the rank decisions: a singular value σ_i counts when
/// σ_i > rank_tolerance · σ_max (and σ_max > 0).
inline constexpr double rank_tolerance = 1e-10;

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

}  // namespace lagrangian
