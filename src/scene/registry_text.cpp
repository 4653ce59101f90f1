// The registry entry of a model stated by expressions (TextModelSpec,
// text/text_model.hpp): a text::TextModel built from the scene's [model]
// table on every call.

#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Cholesky>

#include "lagrangian/text/tangent_flow.hpp"
#include "lagrangian/text/text_model.hpp"
#include "registry_entry.hpp"
#include "scene_messages.hpp"
#include "text_model_spec.hpp"

namespace lagrangian::scene::detail {
namespace {

std::shared_ptr<const lagrangian::text::Parsed> parsed_of(const ModelSpec& spec) {
  try {
    return lagrangian::text::read(text_definition(spec));
  } catch (const lagrangian::text::ExpressionError& e) {
    throw SceneError(e.field(), scene_message(e));
  }
}

/// spec.q and spec.qd (zero when not given), checked against the coordinates.
State<Dynamic> initial_of(const ModelSpec& spec) {
  const ModelInfo info = *model_info(spec);
  check_state_sizes(info, spec);
  const int n = static_cast<int>(info.coordinates.size());
  if (spec.q.empty()) throw SceneError("model.q", "a model stated by expressions needs its initial coordinates q");
  State<Dynamic> s(n);
  for (int i = 0; i < n; ++i) s.q[i] = spec.q[static_cast<std::size_t>(i)];
  if (!spec.qd.empty())
    for (int i = 0; i < n; ++i) s.qd[i] = spec.qd[static_cast<std::size_t>(i)];
  return s;
}

/// Refuses a start where an expression is undefined (naming it and the
/// operation) or where M = ∂²T/∂q̇² is not positive definite (naming a
/// coordinate that carries no inertia), as errors of the scene's keys.
void check_start(const lagrangian::text::TextModel& model, const State<Dynamic>& s, double t0) {
  const lagrangian::text::Parsed& p = model.parsed();
  const lagrangian::text::Definition& d = p.definition;
  std::vector<double> values;
  for (const auto& [name, value] : d.parameters) values.push_back(value);
  auto check = [&](const lagrangian::text::Expression& e, const std::string& key) {
    const std::string why = lagrangian::text::undefined_at(e, p.symbols, s.q.data(), s.qd.data(), t0, values.data());
    if (!why.empty()) throw SceneError(d.field_prefix + key, "at t0 = " + format_value(t0) + " s, " + why);
  };
  auto index = [](const char* key, std::size_t i) { return std::string(key) + "[" + std::to_string(i) + "]"; };
  check(p.kinetic, "kinetic");
  check(p.potential, "potential");
  for (std::size_t i = 0; i < p.forces.size(); ++i) check(p.forces[i], index("forces", i));
  check(p.dissipation, "dissipation");
  for (std::size_t i = 0; i < p.holonomic.size(); ++i) check(p.holonomic[i], index("holonomic", i));
  for (std::size_t i = 0; i < p.pfaffian.size(); ++i) check(p.pfaffian[i], index("pfaffian", i));
  for (std::size_t j = 0; j < p.gaps.size(); ++j) check(p.gaps[j], index("contacts", j) + ".gap");
  const Eigen::MatrixXd mass = mass_matrix(model, s.q, s.qd, t0);
  if (Eigen::LLT<Eigen::MatrixXd>(mass).info() == Eigen::Success && mass.allFinite()) return;
  const double big = mass.cwiseAbs().maxCoeff();
  for (int i = 0; i < mass.rows(); ++i)
    if (!(mass.row(i).cwiseAbs().maxCoeff() > 1e-14 * big)) {
      const std::string& q = d.coordinates[static_cast<std::size_t>(i)];
      throw SceneError(d.field_prefix + "kinetic",
                       "coordinate '" + q + "' carries no inertia at t0: T does not depend on " + q +
                           "_dot there (row " + std::to_string(i + 1) +
                           " of M = d2T/dqd2 is zero); every coordinate needs its velocity in T");
    }
  std::ostringstream os;
  os.precision(6);
  os << "M = d2T/dqd2 is not positive definite at t0: M = [";
  for (int i = 0; i < mass.rows(); ++i)
    for (int j = 0; j < mass.cols(); ++j) os << (i || j ? (j ? ", " : "; ") : "") << mass(i, j);
  os << "]; T must be positive for every nonzero velocity";
  throw SceneError(d.field_prefix + "kinetic", os.str());
}

RunReport run_text(const ModelSpec& spec, const SimulationOptions& options, const std::string& csv_path,
                   const SampleTick& tick, FinalState* final_state) {
  const State<Dynamic> s0 = initial_of(spec);
  const lagrangian::text::TextModel model(parsed_of(spec));
  check_start(model, s0, options.t0);
  return run_model(model, s0, options, csv_path, tick, final_state);
}

/// p_i = ∂T/∂q̇_i as formulas in the scene's names (V has no velocities);
/// "(no formula: …)" where T takes min or max of a velocity.
std::vector<std::string> momentum_formulas(const lagrangian::text::Parsed& p) {
  std::vector<std::string> out;
  for (std::size_t i = 0; i < p.symbols.coordinates.size(); ++i) {
    try {
      out.push_back(lagrangian::text::to_text(
          lagrangian::text::derivative(p.kinetic, lagrangian::text::Op::velocity, static_cast<int>(i)), p.symbols));
    } catch (const lagrangian::text::ExpressionError&) {
      out.push_back("(no formula: T takes min or max of a velocity)");
    }
  }
  return out;
}

std::string inspect_text(const ModelSpec& spec, double t0, bool as_json) {
  const ModelInfo info = *model_info(spec);
  const Parameters p(info, spec);
  const State<Dynamic> s0 = initial_of(spec);
  const lagrangian::text::TextModel model(parsed_of(spec));
  InspectExtras extras;
  extras.momentum_formulas = momentum_formulas(model.parsed());
  return inspect_model(model, info, "text::TextModel", p, s0, t0, as_json, extras);
}

lagrangian::detail::EomSample eom_text(const ModelSpec& spec, const double* q, const double* qd, double t) {
  return lagrangian::detail::eom_sample(lagrangian::text::TextModel(parsed_of(spec)), q, qd, t);
}

std::string analyse_text(const ModelSpec& spec, double t0, const AnalysisRequest& request) {
  return analyse_model(lagrangian::text::TextModel(parsed_of(spec)), *model_info(spec), initial_of(spec), t0, request);
}

BvpResult bvp_text(const ModelSpec& spec, const BvpRequest& request, DiscreteRule rule) {
  return solve_model_bvp(lagrangian::text::TextModel(parsed_of(spec)), *model_info(spec), request, rule);
}

/// `compute(model, initial)` on the scene's text model and initial state,
/// checked as a run's start is; the refusals of built-in models
/// (no_tangent_flow) for a model with more coordinates than the tangent
/// flow takes, and for constraints it is not derived for
/// (require_tangent_flow_constraints(): more bilateral rows than it takes
/// at run time). Holonomic and Pfaffian constraints are kept to their
/// manifold, contacts crossed at their impacts.
template <class Compute>
auto with_text_tangent_flow(const ModelSpec& spec, double t0, const char* what, Compute&& compute) {
  const State<Dynamic> s0 = initial_of(spec);
  const lagrangian::text::TextModel model(parsed_of(spec));
  const std::string label = "the model stated as text";
  if (model.size() > kMaxTangentFlowCoordinates)
    throw no_tangent_flow(what, label, too_many_coordinates(std::to_string(model.size())));
  try {
    lagrangian::detail::require_tangent_flow_constraints(model, "");
  } catch (const AnalysisError& e) {
    throw no_tangent_flow(what, label, e.what());
  }
  check_start(model, s0, t0);
  return compute(model, s0);
}

LyapunovResult lyapunov_text(const ModelSpec& spec, const LyapunovOptions& options) {
  return with_text_tangent_flow(spec, options.run.t0, "lyapunov", [&](const auto& model, const auto& s0) {
    return lagrangian::text::lyapunov_spectrum(model, s0, options);
  });
}
SensitivityResult sensitivity_text(const ModelSpec& spec, const SensitivityOptions& options) {
  return with_text_tangent_flow(spec, options.run.t0, "sensitivity", [&](const auto& model, const auto& s0) {
    return lagrangian::text::sensitivities(model, s0, options);
  });
}
FloquetResult floquet_text(const ModelSpec& spec, const FloquetOptions& options) {
  return with_text_tangent_flow(spec, options.run.t0, "floquet", [&](const auto& model, const auto& s0) {
    return lagrangian::text::floquet_multipliers(model, s0, options);
  });
}

/// The points of [[model.points]] (none: an empty figure), with rods from a
/// pivot at the origin through them when `rods` is set; up is +z, or +y
/// when every point has z = 0 (a plane motion drawn in x–y).
view::Figure picture_text(const ModelSpec& spec, const double* t, const double* q, std::size_t rows,
                          std::vector<double>& xyz) {
  const std::shared_ptr<const lagrangian::text::Parsed> p = parsed_of(spec);
  const auto& points = p->definition.points;
  view::Figure f;
  bool planar = true;
  for (std::size_t b = 0; b < points.size(); ++b) {
    f.bodies.push_back({points[b].name, 0.0, -1});
    const lagrangian::text::Expression& z = p->points[b][2];
    planar = planar && z.nodes.size() == 1 && z.nodes[0].op == lagrangian::text::Op::constant && z.nodes[0].value == 0;
    if (p->definition.rods) f.rods.push_back({static_cast<int>(b), static_cast<int>(b) - 1, {0, 0, 0}});
  }
  if (p->definition.rods && !points.empty()) f.pivots = {{0, 0, 0}};
  f.up = planar ? view::Point{0, 1, 0} : view::Point{0, 0, 1};
  const std::size_t nb = points.size(), n = p->definition.coordinates.size();
  xyz.assign(rows * nb * 3, 0.0);
  std::vector<double> slots;
  for (std::size_t r = 0; r < rows; ++r) {
    const Eigen::Map<const Eigen::VectorXd> qr(q + r * n, static_cast<Eigen::Index>(n));
    for (std::size_t b = 0; b < nb; ++b)
      for (std::size_t a = 0; a < 3; ++a)
        xyz[(r * nb + b) * 3 + a] = lagrangian::text::evaluate(p->points[b][a], qr, qr, t[r], slots);
  }
  return f;
}

std::vector<std::array<int, 3>> no_particles(const ModelSpec&) { return {}; }

}  // namespace

const ModelEntry& text_entry() {
  static const ModelEntry e{"text",        &run_text,     &inspect_text, &analyse_text,  &bvp_text,
                            &picture_text, &no_particles, &eom_text,     &lyapunov_text, &floquet_text,
                            &sensitivity_text};
  return e;
}

}  // namespace lagrangian::scene::detail
