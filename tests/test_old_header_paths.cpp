// The flat header paths of the releases before the layer folders
// (docs/architecture.md, "Layers") keep compiling: each is a forwarding
// header to its new path. Removing one, or pointing it at the wrong header,
// breaks this file's build; the checks below use a name from each.
#include <type_traits>

#include <gtest/gtest.h>

#include "lagrangian/analysis.hpp"
#include "lagrangian/bench.hpp"
#include "lagrangian/bvp.hpp"
#include "lagrangian/constraints.hpp"
#include "lagrangian/discrete.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/equilibria.hpp"
#include "lagrangian/hard_spheres.hpp"
#include "lagrangian/impact.hpp"
#include "lagrangian/inlined.hpp"
#include "lagrangian/integrate.hpp"
#include "lagrangian/linearisation.hpp"
#include "lagrangian/method.hpp"
#include "lagrangian/modes.hpp"
#include "lagrangian/observers.hpp"
#include "lagrangian/plots.hpp"
#include "lagrangian/progress.hpp"
#include "lagrangian/properties.hpp"
#include "lagrangian/report.hpp"
#include "lagrangian/scene.hpp"
#include "lagrangian/scene_analysis.hpp"
#include "lagrangian/scene_io.hpp"
#include "lagrangian/scene_model_run.hpp"
#include "lagrangian/scene_models.hpp"
#include "lagrangian/scene_run.hpp"
#include "lagrangian/scene_text_model.hpp"
#include "lagrangian/simulate.hpp"
#include "lagrangian/sweep.hpp"
#include "lagrangian/system.hpp"
#include "lagrangian/variational.hpp"
#include "lagrangian/view.hpp"
// The new paths of the same headers: the same declarations, included twice
// without a redefinition.
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/scene/scene.hpp"

TEST(OldHeaderPaths, NameTheSameDeclarationsAsTheNewOnes) {
  lagrangian::SimulationOptions options;
  EXPECT_EQ(options.method, lagrangian::Method::dopri5);
  EXPECT_EQ(lagrangian::parse_method("rk4", "method"), lagrangian::Method::rk4);
  static_assert(std::is_base_of_v<lagrangian::Error, lagrangian::ConstraintError>);
  static_assert(std::is_base_of_v<lagrangian::Error, lagrangian::AnalysisError>);
  static_assert(std::is_class_v<lagrangian::RunReport>);
  static_assert(std::is_class_v<lagrangian::scene::Scene>);
}
