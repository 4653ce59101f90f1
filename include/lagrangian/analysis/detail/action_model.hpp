#pragma once
// Internal: what the stationary-action solvers (compiled once in
// src/analysis/bvp.cpp) need of a model — the discrete Lagrangian of one
// segment with its slot derivatives, and the mass matrix, momenta and energy
// at a node — and its adapter from a Model, the only per-model part of them.

#include <Eigen/Core>

#include "lagrangian/integrate/discrete.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian::detail {

/// L_d over one segment and its slot derivatives (DiscreteLagrangian, sized n at run time).
struct SegmentDerivatives {
  double value = 0;
  Eigen::VectorXd d1, d2;
  Eigen::MatrixXd d11, d12, d22;
};

class ActionModel {
 public:
  virtual ~ActionModel() = default;
  virtual int coordinate_count() const = 0;
  /// L_d(q0, q1) over [t, t + h] and its derivatives into `out` (q0, q1: n values each).
  virtual void segment(const double* q0, const double* q1, double t, double h, DiscreteRule rule,
                       SegmentDerivatives& out) const = 0;
  /// M(q, 0, t) and p(q, 0, t) at a node.
  virtual void at_rest(const double* q, double t, Eigen::MatrixXd& mass, Eigen::VectorXd& momenta) const = 0;
  /// h = p·q̇ − L at (q, q̇, t) (J).
  virtual double energy(const double* q, const double* qd, double t) const = 0;
};

template <class M>
class ActionModelOf final : public ActionModel {
 public:
  static constexpr int n = coordinate_count_v<M>;
  explicit ActionModelOf(const M& model) : model_(model) {}
  int coordinate_count() const override { return model_size(model_); }
  void segment(const double* q0, const double* q1, double t, double h, DiscreteRule rule,
               SegmentDerivatives& out) const override {
    const DiscreteLagrangian<n> d = discrete_lagrangian_derivatives(model_, at(q0), at(q1), t, h, rule);
    out.value = d.value;
    out.d1 = d.d1;
    out.d2 = d.d2;
    out.d11 = d.d11;
    out.d12 = d.d12;
    out.d22 = d.d22;
  }
  void at_rest(const double* q, double t, Eigen::MatrixXd& mass, Eigen::VectorXd& momenta_out) const override {
    const Vec<double, n> x = at(q);
    const Vec<double, n> zero = Vec<double, n>::Zero(model_size(model_));
    mass = mass_matrix(model_, x, zero, t);
    momenta_out = momenta(model_, x, zero, t);
  }
  double energy(const double* q, const double* qd, double t) const override {
    return energy_function(model_, at(q), at(qd), t);
  }

 private:
  /// The n values at v as a vector.
  Vec<double, n> at(const double* v) const {
    return Eigen::Map<const Vec<double, n>>(v, model_size(model_));
  }
  const M& model_;
};

}  // namespace lagrangian::detail
