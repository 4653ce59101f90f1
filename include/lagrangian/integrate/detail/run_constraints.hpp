#pragma once
// ModelSystem's members for constrained models: consistency and rank at t0,
// projection or monitoring after each step, conditioning of the constraint
// Jacobian, multipliers at samples. Included by model_system.hpp.

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/integrate/detail/model_system.hpp"
#include "lagrangian/errors.hpp"

namespace lagrangian::detail {

/// Constrained models: projection (when chosen) and residual monitoring
/// after an accepted step ending at t with state x; true when x changed.
template <class M>
bool ModelSystem<M>::stabilize(double* x, double t, bool allow_projection) {
  if constexpr (!has_constraints_v<M>) {
    (void)x;
    (void)t;
    (void)allow_projection;
    return false;
  } else {
    if (!ctx_) return false;
    ConstraintReport& cr = report_.constraints;
    if (only_contacts_v && !active().any(unilateral_count(model_))) return false;  // free flight: nothing to hold
    Vec<double, n> q(size_), qd(size_);
    split_state(x, q, qd);
    bool changed = false;
    if (allow_projection && opt_.stabilization == Stabilization::projection) {
      const auto start = std::chrono::steady_clock::now();
      cr.projection_iterations += static_cast<std::uint64_t>(project_onto_constraints(q, qd, t));
      ++cr.projections;
      for (int i = 0; i < size_; ++i) {
        changed = changed || x[i] != q[i] || x[size_ + i] != qd[i];
        x[i] = q[i];
        x[size_ + i] = qd[i];
      }
      cr.stabilization_time_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    auto cs = constraint_state(model_, q, qd, t);
    for (int j = 0; j < unilateral_count(model_); ++j) {
      const int row = holonomic_count(model_) + j;
      if (!active().contains(j) && cs.position[row] < -1e-9 * (1.0 + q.template lpNorm<Eigen::Infinity>())) {
        std::ostringstream os;
        os.precision(17);
        os << "unilateral constraint " << cr.names[static_cast<std::size_t>(row)] << " is violated at t = " << t
           << " (g = " << cs.position[row]
           << ") without a located contact event; the step passed through the contact (try a smaller dt or "
              "tighter tolerances)";
        throw SimulationError(os.str(), t);
      }
    }
    if constexpr (add_rows(holonomic_count_v<M>, pfaffian_count_v<M>) != 0) {
      if (has_bilateral_constraints(model_)) monitor_conditioning(cs, t);
    }
    record_residuals(cs, true);
    return changed;
  }
}

/// ‖g‖∞ of the holonomic and active unilateral rows and ‖C q̇ + c‖∞ of the
/// active rows at one state, into the run's maxima (and, at a step's end,
/// the final values): at accepted steps and at the samples between them,
/// which come from the stepper's dense output and are what the user gets.
template <class M>
template <class CS>
void ModelSystem<M>::record_residuals(CS cs, bool at_step) {
  if constexpr (has_constraints_v<M>) {
    ConstraintReport& cr = report_.constraints;
    drop_inactive(model_, cs, active());
    const int rows = position_rows(model_);
    const double pos = rows > 0 ? cs.position.head(rows).template lpNorm<Eigen::Infinity>() : 0.0;
    const double vel = cs.velocity.template lpNorm<Eigen::Infinity>();
    cr.max_position_residual = std::max(cr.max_position_residual, pos);
    cr.max_velocity_residual = std::max(cr.max_velocity_residual, vel);
    if (at_step) {
      cr.final_position_residual = pos;
      cr.final_velocity_residual = vel;
    }
  } else {
    (void)cs, (void)at_step;
  }
}

/// Tracks σ_r/σ_1 of the bilateral constraint Jacobian (r = rank at t0)
/// at accepted steps and samples, and warns once when it falls below
/// 1e-3: a singular configuration is near (the multipliers grow without
/// bound there, and the motion may switch assembly branches).
template <class M>
template <class CS>
void ModelSystem<M>::monitor_conditioning(CS cs, double t) {
  ConstraintReport& cr = report_.constraints;
  drop_inactive(model_, cs, ActiveSet{});
  const double* sv = ctx_->conditioning.compute(cs.jacobian.data());
  const int r = cr.initial_rank;
  if (r < 1 || ctx_->conditioning.size() == 0 || !(sv[0] > 0)) return;
  const double ratio = r <= ctx_->conditioning.size() ? sv[r - 1] / sv[0] : 0.0;
  if (ratio < cr.min_conditioning) {
    cr.min_conditioning = ratio;
    cr.min_conditioning_time = t;
  }
  if (ratio < 1e-3 && !warned_conditioning_) {
    warned_conditioning_ = true;
    std::ostringstream os;
    os.precision(6);
    os << "near-singular configuration at t = " << t << ": the constraint Jacobian's singular values fall to "
       << ratio << " of the largest (rank " << r << " at t0); multipliers may be large there";
    cr.warnings.push_back(os.str());
  }
}

/// The contacts at t0: a gap below zero is an error naming the contact; a
/// touching contact rests where the forces press it shut, and one
/// approaching faster than the touch speed is an impact resolved here (x0
/// and cs are then those after it). Returns the resting contacts.
template <class M>
ActiveSet ModelSystem<M>::start_contacts(State<n>& x0, ConstraintState<n, constraint_count_v<M>>& cs, double qs) {
  ActiveSet active;
  const ConstraintReport& cr = report_.constraints;
  const int contacts = unilateral_count(model_);
  restitution_ = restitution_coefficients(model_);
  if constexpr (unilateral_count_v<M> == Dynamic) {
    history_.assign(static_cast<std::size_t>(contacts), ContactHistory{});
  } else {
    history_.fill(ContactHistory{});
  }
  for (auto* v : {&gap_in_, &rate_in_}) v->setZero(contacts);
  if (ctx_ && contacts > 0) contacts_ = std::make_unique<Contacts>(*this);
  bool approaching = false;
  for (int j = 0; j < contacts; ++j) {
    const int row = holonomic_count(model_) + j;
    const double g = cs.position[row], gd = cs.velocity[row];
    if (g < -1e-9 * qs) {
      std::ostringstream os;
      os.precision(17);
      os << "unilateral constraint " << cr.names[static_cast<std::size_t>(row)] << " is violated at t0: g = " << g
         << " (the bodies overlap); start on or outside the admissible side";
      throw ConstraintError(os.str());
    }
    if (std::abs(g) <= 1e-9 * qs) {
      if (gd < -opt_.contact_touch_speed) {
        approaching = true;  // an impact at t0
      } else if (gd <= opt_.contact_touch_speed) {
        active.insert(j);  // resting contact, if pressed (below)
      }
    }
  }
  if (ctx_) ctx_->active = active;
  // A contact touching at t0 rests only where the forces press it shut.
  for (int j = 0; j < contacts && ctx_; ++j)
    if (active.contains(j) && !(gap_acceleration(x0.q, x0.qd, opt_.t0, j) < 0)) {
      active.erase(j);
      ctx_->active = active;
    }
  if (approaching) {
    if constexpr (!has_restitution_v<M>) {
      throw ConstraintError("a unilateral constraint is approached at t0 (an impact) but the model declares no "
                            "restitution(); start at rest relative to it, or declare restitution()");
    }
    StateBuffer<n> xb = make_buffer<n>(size_);
    for (int i = 0; i < size_; ++i) {
      xb[static_cast<std::size_t>(i)] = x0.q[i];
      xb[static_cast<std::size_t>(size_ + i)] = x0.qd[i];
    }
    for (int j = 0; j < contacts; ++j) {
      const int row = holonomic_count(model_) + j;
      if (std::abs(cs.position[row]) <= 1e-9 * qs && cs.velocity[row] < -opt_.contact_touch_speed) {
        resolve_contacts(xb.data(), opt_.t0, j);
        break;
      }
    }
    split_state(xb.data(), x0.q, x0.qd);
    active = ctx_ ? ctx_->active : active;
    cs = constraint_state(model_, x0.q, x0.qd, opt_.t0);
  }
  return active;
}

template <class M>
void ModelSystem<M>::start_constraints(State<n>& x0, Columns& columns) {
  if constexpr (has_constraints_v<M>) {
    ConstraintReport& cr = report_.constraints;
    report_.constrained = true;
    cr.names = constraint_names(model_);
    columns.constraints = cr.names;
    columns.constraint_units = multiplier_units(model_);
    cr.stabilization = to_string(opt_.stabilization);
    cr.baumgarte_omega = opt_.stabilization == Stabilization::baumgarte ? opt_.baumgarte_omega : 0.0;
    // A violated position constraint is said as such before the rank is
    // judged: off the constraint manifold dependent rows (an over-constrained
    // mechanism) look independent, and "no motion is left" would mislead.
    const auto violation = [&](int i, double g, double velocity_residual, bool holo) {
      std::ostringstream os;
      os.precision(17);
      os << "initial state violates constraint " << cr.names[static_cast<std::size_t>(i)] << ": "
         << (holo ? "g = " : "") << (holo ? g : 0.0) << (holo ? ", " : "") << "velocity residual = " << velocity_residual
         << "; use consistent_initial_state() to find the nearest consistent state";
      return ConstraintError(os.str());
    };
    auto cs = constraint_state(model_, x0.q, x0.qd, opt_.t0);
    const double qs = 1.0 + x0.q.template lpNorm<Eigen::Infinity>();
    const double vs = 1.0 + x0.qd.template lpNorm<Eigen::Infinity>();
    for (int i = 0; i < holonomic_count(model_); ++i)
      if (!(std::abs(cs.position[i]) <= 1e-9 * qs)) throw violation(i, cs.position[i], cs.velocity[i], true);
    const DofReport dof = dof_report(model_, x0, opt_.t0);
    cr.initial_rank = cr.min_rank = dof.velocity_rank;
    // Full rank leaves no motion unless the constraints themselves move (a
    // prescribed, rheonomic motion with 0 degrees of freedom).
    if (dof.holonomic_rank >= size_ && constraints_workless(model_, x0, opt_.t0))
      throw ConstraintError("the holonomic constraints fix all " + std::to_string(size_) +
                            " coordinates (rank " + std::to_string(dof.holonomic_rank) + "): no motion is left");
    for (const auto& r : dof.redundant)
      cr.warnings.push_back(redundant_constraint_warning(r));
    ActiveSet active;
    if constexpr (unilateral_count_v<M> != 0) active = start_contacts(x0, cs, qs);
    if (ctx_) ctx_->active = active;
    drop_inactive(model_, cs, active);
    for (int i = 0; i < constraint_count(model_); ++i) {
      const bool holo = i < position_rows(model_);
      if ((holo && !(std::abs(cs.position[i]) <= 1e-9 * qs)) || !(std::abs(cs.velocity[i]) <= 1e-9 * vs))
        throw violation(i, cs.position[i], cs.velocity[i], holo);
    }
  }
}

template <class M>
int ModelSystem<M>::project_onto_constraints(Vec<double, n>& q, Vec<double, n>& qd, double t) {
  int iterations = 0;
  try {
    iterations = project_positions_with(model_, q, t, opt_.projection_tolerance, 20, active(), ctx_->positions);
  } catch (const ConstraintError& e) {
    throw SimulationError(std::string("projection failed: ") + e.what(), t);
  }
  project_velocities_with(model_, ws_, q, qd, t, active(), ctx_->velocities);
  return iterations;
}

template <class M>
void ModelSystem<M>::project_sample(Sample<n>& s) {
  if constexpr (has_constraints_v<M>) {
    if (opt_.stabilization != Stabilization::projection) return;
    if (only_contacts_v && !active().any(unilateral_count(model_))) return;  // free flight: nothing to hold
    project_onto_constraints(s.q, s.qd, s.t);
  }
}

template <class M>
void ModelSystem<M>::sample_constraints(Sample<n>& s) {
  if constexpr (has_constraints_v<M>) {
    Vec<double, n> qdd(size_);
    constrained_accelerations(model_, ws_, cw_, s.q, s.qd, s.t, qdd, 0.0, active());
    s.multipliers = cw_.multipliers;
    s.constraint_forces = cw_.constraint_forces;
    auto cs = constraint_state(model_, s.q, s.qd, s.t);
    if constexpr (add_rows(holonomic_count_v<M>, pfaffian_count_v<M>) != 0) {
      if (has_bilateral_constraints(model_)) monitor_conditioning(cs, s.t);
    }
    if (!(only_contacts_v && !active().any(unilateral_count(model_)))) record_residuals(cs, false);
    drop_inactive(model_, cs, ActiveSet{});  // rank of the bilateral constraints
    const int rank = detail::numeric_rank(cs.jacobian);
    ConstraintReport& cr = report_.constraints;
    if (rank < cr.min_rank) {
      std::ostringstream os;
      os.precision(10);
      os << "rank of the constraint Jacobian dropped from " << cr.initial_rank << " to " << rank << " at t = " << s.t
         << " (singular configuration)";
      cr.warnings.push_back(os.str());
      cr.min_rank = rank;
    }
  }
}

}  // namespace lagrangian::detail
