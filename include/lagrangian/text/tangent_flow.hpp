#pragma once
/// \file text/tangent_flow.hpp
/// Lyapunov exponents, Floquet multipliers and sensitivities of a model
/// stated as text: the analyses of analysis/lyapunov.hpp, floquet.hpp and
/// sensitivity.hpp, whose tangent flow J = ∂(q̇, q̈)/∂(q, q̇) comes from the
/// same automatic differentiation of the model's expressions as for a C++
/// model (no finite differences). Each one sees the model at its size n
/// (text::FixedSizeModel<n>, text/fixed_size.hpp), compiled once in the
/// library for n = 1 … kMaxTangentFlowCoordinates.
///
/// Scope, as for C++ models: at most kMaxTangentFlowCoordinates (6)
/// coordinates; holonomic and Pfaffian constraints are kept on their
/// manifold (at most kMaxRuntimeBilateralRows rows: the text model counts
/// them at run time), contacts are crossed at their impacts by the
/// saltation matrix (analysis/saltation.hpp), the constraints kept through
/// them. Sensitivities to the model's parameters (by name, as in its
/// definition) come from its expressions as written, each parameter
/// carrying its derivative through them.

#include "lagrangian/analysis/floquet.hpp"
#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/text/text_model.hpp"

namespace lagrangian::text {

/// q̈ and J = ∂q̈/∂(q, q̇) (n × 2n: the columns ∂/∂q, then ∂/∂q̇) of `model`
/// at (q, q̇, t), as lagrangian::state_jacobian() gives them for a C++
/// model, by the same passes the analyses below take (on a constraint
/// manifold, J of the constrained motion). OptionError for q or q̇ of
/// another size; AnalysisError as the analyses (more than
/// kMaxTangentFlowCoordinates coordinates, constraints and contacts
/// together).
void state_jacobian(const TextModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double t,
                    Eigen::VectorXd& qdd, Eigen::MatrixXd& jacobian);

/// The Lyapunov exponents of the motion of `model` from `initial` (see
/// lagrangian::lyapunov_spectrum()).
LyapunovResult lyapunov_spectrum(const TextModel& model, const State<Dynamic>& initial, const LyapunovOptions& options);

/// The Floquet multipliers of the motion of `model` from `initial` over
/// one period (see lagrangian::floquet_multipliers()).
FloquetResult floquet_multipliers(const TextModel& model, const State<Dynamic>& initial, const FloquetOptions& options);

/// ∂x(t)/∂x(t0), and ∂x(t)/∂p for the parameters named in
/// options.parameters (OptionError naming an unknown one), of the motion of
/// `model` from `initial` (see lagrangian::sensitivities()).
SensitivityResult sensitivities(const TextModel& model, const State<Dynamic>& initial,
                                const SensitivityOptions& options);

}  // namespace lagrangian::text
