#pragma once
// Shared by the tangent-flow tests: dopri5 runs for Lyapunov exponents (to
// t_end at rtol, atol 1e-13), for Floquet multipliers (one period at
// rtol 1e-12, atol 1e-14) and for sensitivities (to t_end at rtol 1e-13,
// atol 1e-15), and the relative distance of two matrices.

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/analysis/floquet.hpp"
#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/sensitivity.hpp"

namespace lagrangian_test {

inline lagrangian::LyapunovOptions lyapunov_options(double t_end, double rtol = 1e-11) {
  lagrangian::LyapunovOptions o;
  o.run.t_end = t_end;
  o.run.rtol = rtol;
  o.run.atol = 1e-13;
  return o;
}

/// Sensitivities to t_end of the initial state and of `parameters`;
/// samples every `interval` s (0: every step, negative: the ends only).
inline lagrangian::SensitivityOptions sensitivity_options(double t_end, std::vector<std::string> parameters = {},
                                                          double interval = 0.0) {
  lagrangian::SensitivityOptions o;
  o.run.t_end = t_end;
  o.run.rtol = 1e-13;
  o.run.atol = 1e-15;
  o.run.output_interval = interval;
  o.parameters = std::move(parameters);
  return o;
}

/// The largest entry of |got − expected| / (1 + |expected|).
inline double worst_relative(const Eigen::MatrixXd& got, const Eigen::MatrixXd& expected) {
  return ((got - expected).array().abs() / (1.0 + expected.array().abs())).maxCoeff();
}

inline lagrangian::FloquetOptions floquet_options(double period) {
  lagrangian::FloquetOptions o;
  o.period = period;
  o.run.rtol = 1e-12;
  o.run.atol = 1e-14;
  return o;
}

}  // namespace lagrangian_test
