#pragma once
// Internal: a model frozen at a time t and seen at rest (q̇ = 0), the
// interface the equilibria and small-oscillation analyses (compiled once in
// src/analysis/) run on, and its adapter from a Model, the only per-model
// part of those analyses: L's second-order expansions about rest and the
// holonomic constraints with their derivatives, by automatic differentiation.

#include <Eigen/Core>

#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/analysis/linearisation.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian::detail {

class RestModel {
 public:
  virtual ~RestModel() = default;
  virtual int coordinate_count() const = 0;
  virtual int holonomic_count() const = 0;
  virtual PotentialDerivatives potential(const Eigen::VectorXd& q) const = 0;
  virtual HolonomicDerivatives holonomic(const Eigen::VectorXd& q) const = 0;
  virtual QuadraticLagrangian quadratic(const Eigen::VectorXd& q) const = 0;
  /// Moves q onto g(q, t) = 0 (tolerance 1e-12, 50 Gauss–Newton steps);
  /// false when it does not get there.
  virtual bool project(Eigen::VectorXd& q) const = 0;
};

template <class M>
class RestModelOf final : public RestModel {
 public:
  RestModelOf(const M& model, double t) : model_(model), t_(t) {}
  int coordinate_count() const override { return model_size(model_); }
  int holonomic_count() const override { return lagrangian::holonomic_count(model_); }
  PotentialDerivatives potential(const Eigen::VectorXd& q) const override {
    return potential_derivatives(model_, Vec<double, coordinate_count_v<M>>(q), t_);
  }
  HolonomicDerivatives holonomic(const Eigen::VectorXd& q) const override {
    return holonomic_derivatives(model_, Vec<double, coordinate_count_v<M>>(q), t_);
  }
  QuadraticLagrangian quadratic(const Eigen::VectorXd& q) const override {
    return quadratic_lagrangian(model_, Vec<double, coordinate_count_v<M>>(q), t_);
  }
  bool project(Eigen::VectorXd& q) const override {
    if constexpr (holonomic_count_v<M> != 0) {
      Vec<double, coordinate_count_v<M>> x = q;
      try {
        project_positions(model_, x, t_, 1e-12, 50, ActiveSet{});
      } catch (const ConstraintError&) {
        return false;
      }
      q = x;
    }
    return true;
  }

 private:
  const M& model_;
  double t_;
};

}  // namespace lagrangian::detail
