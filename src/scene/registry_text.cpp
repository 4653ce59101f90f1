// The registry entry of a model stated by expressions (TextModelSpec,
// text/text_model.hpp): built from the scene's [model] table on every call,
// as a TextModel, or a ForcedTextModel when Q or D is given.

#include <memory>
#include <string>
#include <vector>

#include "lagrangian/text/text_model.hpp"
#include "registry_entry.hpp"
#include "text_model_spec.hpp"

namespace lagrangian::scene::detail {
namespace {

std::shared_ptr<const lagrangian::text::Parsed> parsed_of(const ModelSpec& spec) {
  try {
    return lagrangian::text::read(text_definition(spec));
  } catch (const lagrangian::text::ExpressionError& e) {
    throw SceneError(e.field(), e.what());
  }
}

/// Calls f with the model: a ForcedTextModel when Q or D is given.
template <class F>
auto with_model(const ModelSpec& spec, F&& f) {
  const std::shared_ptr<const lagrangian::text::Parsed> p = parsed_of(spec);
  if (p->has_forces || p->has_dissipation) return f(lagrangian::text::ForcedTextModel(p));
  return f(lagrangian::text::TextModel(p));
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

RunReport run_text(const ModelSpec& spec, const SimulationOptions& options, const std::string& csv_path,
                   const SampleTick& tick, FinalState* final_state) {
  const State<Dynamic> s0 = initial_of(spec);
  return with_model(spec, [&](const auto& model) { return run_model(model, s0, options, csv_path, tick, final_state); });
}

std::string_view type_of(const lagrangian::text::TextModel&) { return "text::TextModel"; }
std::string_view type_of(const lagrangian::text::ForcedTextModel&) { return "text::ForcedTextModel"; }

std::string inspect_text(const ModelSpec& spec, double t0, bool as_json) {
  const ModelInfo info = *model_info(spec);
  const Parameters p(info, spec);
  const State<Dynamic> s0 = initial_of(spec);
  return with_model(spec, [&](const auto& model) { return inspect_model(model, info, type_of(model), p, s0, t0, as_json); });
}

// Equilibria, modes and the boundary-value problem are built on fixed-size
// numbers (linearisation.hpp, discrete.hpp): not yet for text models.
std::string analyse_text(const ModelSpec& spec, double, const AnalysisRequest&) {
  parsed_of(spec);
  throw OptionError("inspect --equilibria/--modes: not available yet for a model stated by expressions");
}

BvpResult bvp_text(const ModelSpec& spec, const BvpRequest&, DiscreteRule) {
  parsed_of(spec);
  throw OptionError("solve-bvp: not available yet for a model stated by expressions");
}

view::Figure picture_text(const ModelSpec&, const double*, const double*, std::size_t, std::vector<double>& xyz) {
  xyz.clear();
  return {};
}

std::vector<std::array<int, 3>> no_particles(const ModelSpec&) { return {}; }

}  // namespace

const ModelEntry& text_entry() {
  static const ModelEntry e{"text", &run_text, &inspect_text, &analyse_text, &bvp_text, &picture_text, &no_particles};
  return e;
}

}  // namespace lagrangian::scene::detail
