#pragma once
// Internal: a scene run's animation page (view.hpp), from its trajectory.csv.

#include <string>

#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/run.hpp"
#include "lagrangian/view/view.hpp"

namespace lagrangian::scene::detail {

/// What the page and the video of a run show.
struct SceneView {
  view::Figure figure;
  view::Track track;
  view::Options options;  ///< the title and description; the size budget the track was thinned to
};

/// The figure and track of a finished run of `scene` (gas expanded) that
/// wrote <output.directory>/trajectory.csv: the samples thinned while read
/// to the page's budget (view::sample_stride). Throws OptionError when the
/// CSV cannot be read.
SceneView scene_view(const Scene& scene, const RunResult& result);

}  // namespace lagrangian::scene::detail
