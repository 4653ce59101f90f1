#pragma once
// Particle scenes shared by the tangent-flow tests of particle scenes
// (test_particle_tangent.cpp, test_particle_sensitivity.cpp).

#include <cstddef>
#include <sstream>
#include <string>

#include <Eigen/Core>

#include "lagrangian/scene/run.hpp"

namespace lagrangian_test {

/// A scene file named `name`, run by dopri5 at rtol 1e-12, atol 1e-14 to
/// t_end (s), with the tables `tables` (bodies, effects, contacts).
inline std::string precise_scene(const std::string& name, double t_end, const std::string& tables) {
  std::ostringstream os;
  os.precision(17);
  os << "name = \"" << name << "\"\n[run]\nmethod = \"dopri5\"\nrtol = 1e-12\natol = 1e-14\nt_end = " << t_end << "\n"
     << tables;
  return os.str();
}

/// x(t_end) = (q, q̇) of a plain run of `scene` that writes no files; its
/// number of impacts into `impacts` when given.
inline Eigen::VectorXd plain_end_state(const lagrangian::scene::Scene& scene, int* impacts = nullptr) {
  lagrangian::scene::RunControls quiet;
  quiet.write_outputs = false;
  const lagrangian::scene::RunResult r = lagrangian::scene::run(scene, quiet);
  if (impacts != nullptr) *impacts = static_cast<int>(r.report.impacts);
  const auto n = static_cast<Eigen::Index>(r.q_final.size());
  Eigen::VectorXd x(2 * n);
  for (Eigen::Index i = 0; i < n; ++i) {
    x[i] = r.q_final[static_cast<std::size_t>(i)];
    x[n + i] = r.qd_final[static_cast<std::size_t>(i)];
  }
  return x;
}

/// A ball (0.3 kg, R = 0.05 m) dropped on a frictionless plane through
/// p = (0.1, −0.2, 0.03) m tilted by 0.3 rad about y, n̂ = (sin 0.3, 0,
/// cos 0.3), e = 0.5: its bounces accumulate, the Zeno rule rests it at
/// about 1.05 s and it slides down the plane.
inline const char* const kBallOnAnIncline = R"(
[[bodies]]
name = "ball"
mass = 0.3
radius = 0.05
position = [0.2, 0.1, 0.6]
velocity = [0.4, -0.3, 0.0]
[gravity]
g = [0.0, 0.0, -9.81]
[[contacts.planes]]
name = "incline"
point = [0.1, -0.2, 0.03]
normal = [0.29552020666133955, 0.0, 0.955336489125606]
restitution = 0.5
)";

}  // namespace lagrangian_test
