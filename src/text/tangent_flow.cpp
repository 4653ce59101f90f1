// Lyapunov exponents, Floquet multipliers and sensitivities of a text model
// (text/tangent_flow.hpp): the model seen at its size n as a
// FixedSizeModel<n>, n = 1 … kMaxTangentFlowCoordinates, each compiled here once.
// A library configured with LAGRANGIAN_COMPILED_TANGENT_FLOW=OFF (the
// sanitizer build) compiles none of it: the three functions say so.

#include "lagrangian/text/tangent_flow.hpp"

#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "lagrangian/text/fixed_size.hpp"

namespace lagrangian::text {

#if defined(LAGRANGIAN_NO_COMPILED_TANGENT_FLOW) && LAGRANGIAN_NO_COMPILED_TANGENT_FLOW

namespace {
[[noreturn]] void not_compiled(const char* prefix) {
  throw AnalysisError(std::string(prefix) +
                      "the tangent flow of text models is not in this library (configured with "
                      "LAGRANGIAN_COMPILED_TANGENT_FLOW=OFF)");
}
}  // namespace

void state_jacobian(const TextModel&, const Eigen::VectorXd&, const Eigen::VectorXd&, double, Eigen::VectorXd&,
                    Eigen::MatrixXd&) {
  not_compiled("state_jacobian: ");
}
LyapunovResult lyapunov_spectrum(const TextModel&, const State<Dynamic>&, const LyapunovOptions&) {
  not_compiled("lyapunov: ");
}
FloquetResult floquet_multipliers(const TextModel&, const State<Dynamic>&, const FloquetOptions&) {
  not_compiled("floquet: ");
}
SensitivityResult sensitivities(const TextModel&, const State<Dynamic>&, const SensitivityOptions&) {
  not_compiled("sensitivity: ");
}

#else

void detail::project_state(const std::shared_ptr<const Parsed>& parsed, double* q, double* qd, double t) {
  const TextModel model(parsed);
  lagrangian::detail::evaluate_projection<TextModel>(&model, q, qd, t);
}

namespace {

static_assert(kMaxTangentFlowCoordinates == 6, "at_fixed_size() lists the sizes 1 … 6");

template <int N, class Compute>
auto at_size(const TextModel& model, const State<Dynamic>& initial, Compute&& compute) {
  const FixedSizeModel<N> fixed(model);
  State<N> start;
  start.q = initial.q;
  start.qd = initial.qd;
  return compute(fixed, start);
}

/// compute(FixedSizeModel<n>, State<n>) for the model's size n; AnalysisError
/// (its message starting with `prefix`) for a model with more coordinates
/// than the tangent flow takes, or constraints it is not derived for
/// (require_tangent_flow_constraints()), OptionError for a start of another
/// size. Constraints and contacts are carried over.
template <class Compute>
auto at_fixed_size(const TextModel& model, const State<Dynamic>& initial, const std::string& prefix,
                   Compute&& compute) {
  lagrangian::detail::require_tangent_flow_constraints(model, prefix);
  const int n = model.size();
  if (initial.q.size() != n || initial.qd.size() != n)
    throw OptionError(prefix + "the initial state's q and qd have sizes " + std::to_string(initial.q.size()) + " and " +
                      std::to_string(initial.qd.size()) + "; the model has " + std::to_string(n) + " coordinates");
  switch (n) {
    case 1:
      return at_size<1>(model, initial, compute);
    case 2:
      return at_size<2>(model, initial, compute);
    case 3:
      return at_size<3>(model, initial, compute);
    case 4:
      return at_size<4>(model, initial, compute);
    case 5:
      return at_size<5>(model, initial, compute);
    case 6:
      return at_size<6>(model, initial, compute);
    default:
      throw AnalysisError(prefix + "the tangent flow is derived for models of at most " +
                          std::to_string(kMaxTangentFlowCoordinates) + " coordinates; this text model has " +
                          std::to_string(n));
  }
}

}  // namespace

void state_jacobian(const TextModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double t,
                    Eigen::VectorXd& qdd, Eigen::MatrixXd& jacobian) {
  State<Dynamic> at(static_cast<int>(q.size()));
  at.q = q;
  at.qd = qd;
  at_fixed_size(model, at, "state_jacobian: ", [&](const auto& fixed, const auto& start) {
    constexpr int n = std::decay_t<decltype(fixed)>::coordinate_count;
    Vec<double, n> a;
    Eigen::Matrix<double, n, 2 * n> j;
    lagrangian::state_jacobian(fixed, start.q, start.qd, t, a, j);
    qdd = a;
    jacobian = j;
    return 0;
  });
}

LyapunovResult lyapunov_spectrum(const TextModel& model, const State<Dynamic>& initial,
                                 const LyapunovOptions& options) {
  return at_fixed_size(model, initial, "lyapunov: ", [&](const auto& fixed, const auto& start) {
    return lagrangian::lyapunov_spectrum(fixed, start, options);
  });
}

FloquetResult floquet_multipliers(const TextModel& model, const State<Dynamic>& initial,
                                  const FloquetOptions& options) {
  return at_fixed_size(model, initial, "floquet: ", [&](const auto& fixed, const auto& start) {
    return lagrangian::floquet_multipliers(fixed, start, options);
  });
}

namespace {

using Seed = ad::Jet<double, 1, 1>;

/// The model at size N with, for each parameter asked for, the twin whose
/// parameter carries the derivative 1 (built once per call).
template <int N>
struct WithSeeds : FixedSizeModel<N> {
  std::vector<std::optional<FixedSizeModel<N, Seed>>> seeded;  // by the parameter's index
  std::vector<double> values;                                   // the parameters' values
  WithSeeds(const FixedSizeModel<N>& fixed, const TextModel& model, const std::vector<int>& parameters)
      : FixedSizeModel<N>(fixed), seeded(model.parsed().definition.parameters.size()) {
    for (const auto& [name, v] : model.parsed().definition.parameters) values.push_back(v);
    for (int i : parameters) {
      Seed value(values[static_cast<std::size_t>(i)]);
      value.g[0] = 1.0;
      seeded[static_cast<std::size_t>(i)].emplace(model, i, value);
    }
  }
};

/// q̈ and (∂q̈/∂x) v + ∂q̈/∂p_parameter (TangentModel::evaluate_parameter):
/// the tangent pass on the twin whose parameter is seeded.
template <int N>
void parameter_direction(const void* model, const double* q, const double* qd, double t, const double* v,
                         int parameter, double* qdd, double* jv) {
  const auto& base = *static_cast<const FixedSizeModel<N>*>(model);
  const auto& twins = static_cast<const WithSeeds<N>&>(base).seeded;
  lagrangian::detail::jvp_along(base, q, qd, t, v, qdd, jv, &*twins[static_cast<std::size_t>(parameter)]);
}

/// ∂h/∂p of the constraint manifold's rows on the twin whose parameter is
/// seeded (TangentModel::parameter_manifold); returns p.
template <int N>
double parameter_manifold(const void* model, const double* q, const double* qd, double t, int parameter, double* out) {
  const auto& with = static_cast<const WithSeeds<N>&>(*static_cast<const FixedSizeModel<N>*>(model));
  const std::size_t i = static_cast<std::size_t>(parameter);
  lagrangian::detail::manifold_rows_along_parameter<N>(*with.seeded[i], q, qd, t, out);
  return with.values[i];
}

/// ∂q̇⁺/∂p and ∂φ_j/∂p at an impact (TangentModel::parameter_impact) on
/// the twin whose parameter is seeded.
template <int N>
double parameter_impact(const void* model, const double* q, const double* qd, double t, int contact, int parameter,
                        bool plastic, double* dqd_plus) {
  const auto& with = static_cast<const WithSeeds<N>&>(*static_cast<const FixedSizeModel<N>*>(model));
  return lagrangian::detail::impact_along_parameter<N>(*with.seeded[static_cast<std::size_t>(parameter)], q, qd, t,
                                                       contact, plastic, dqd_plus);
}

/// Contact j held shut or opened (TangentModel::rest) in the model and in
/// each seeded twin, so that a parameter's column follows the held motion:
/// the twin's rows are then the model's, each carrying its derivative
/// along the parameter (a floor's height moves the held row).
template <int N>
void hold_with_seeds(const void* model, int contact, bool shut) {
  const auto& with = static_cast<const WithSeeds<N>&>(*static_cast<const FixedSizeModel<N>*>(model));
  with.hold(contact, shut);
  for (const auto& twin : with.seeded)
    if (twin) twin->hold(contact, shut);
}

}  // namespace

SensitivityResult sensitivities(const TextModel& model, const State<Dynamic>& initial,
                                const SensitivityOptions& options) {
  return at_fixed_size(model, initial, "sensitivity: ", [&](const auto& fixed, const auto& start) {
    constexpr int n = std::decay_t<decltype(fixed)>::coordinate_count;
    const std::vector<std::string> names = fixed.parameter_names();
    std::vector<int> indices;
    if (!options.parameters.empty()) indices = lagrangian::detail::parameter_indices(options.parameters, names);
    const WithSeeds<n> with(fixed, model, indices);
    const FixedSizeModel<n>& base = with;
    lagrangian::detail::TangentModel tm = lagrangian::detail::tangent_model_of(base, "sensitivity: ");
    if (!indices.empty()) {
      tm.evaluate_parameter = &parameter_direction<n>;
      if (tm.manifold > 0) tm.parameter_manifold = &parameter_manifold<n>;
      if (tm.contacts > 0) tm.parameter_impact = &parameter_impact<n>;
      if (tm.rest != nullptr) {
        tm.rest = &hold_with_seeds<n>;
        tm.rest_holds_parameters = true;
      }
    }
    return lagrangian::detail::sensitivities(tm, start.q.data(), start.qd.data(), indices, names, options);
  });
}

#endif

}  // namespace lagrangian::text
