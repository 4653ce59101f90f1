#pragma once
/// \file scene/model_run.hpp
/// A model written in C++ given the outputs of `lagrangian run` in one call:
/// the trajectory as CSV with the model's coordinate names and units, the
/// events, report.json, the plots and the animation page. Link
/// `lagrangian::scene` (which brings `lagrangian::view` for the page and
/// runs gnuplot for the plots when it is installed).
///
/// \code
/// lagrangian::scene::RunSpec run;
/// run.t_end = 10.0;
/// lagrangian::scene::OutputSpec out;
/// out.directory = "out/my_model";
/// const auto result = lagrangian::scene::run_and_write(my_model, initial_state, run, out);
/// \endcode

#include <memory>
#include <utility>

#include "lagrangian/scene/detail/model_run.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/run.hpp"

namespace lagrangian::scene {

/// Runs `model` from `initial` with the stepper, times and tolerances of
/// `run_spec`, as `lagrangian run` runs a scene's [model], and writes what
/// it writes into output.directory: trajectory.csv (the model's
/// coordinate_names() and coordinate_units() in the header), events.csv,
/// report.json and the plots (output.plots; gnuplot), each through a partial
/// file that only a successful run renames. animation.html draws a model of
/// particles (particles()) as point masses; a model without them gets no
/// page, and RunResult::animation_note says so. Returns the run
/// (RunResult::report is simulate()'s report); throws as scene::run(): a
/// SceneError for bad options or an inconsistent initial state, a
/// SimulationError for a run that fails.
template <class M>
RunResult run_and_write(const M& model, const State<coordinate_count_v<M>>& initial, const RunSpec& run_spec = {},
                        const OutputSpec& output = {}, const RunControls& controls = {}) {
  Scene scene;
  scene.name = model_name(model);
  scene.run = run_spec;
  scene.output = output;
  ModelSpec m;
  m.user = std::make_shared<detail::UserModelOf<M>>(model, initial, scene.name);
  scene.model = std::move(m);
  return run(scene, controls);
}

}  // namespace lagrangian::scene
