#pragma once
// Internal: the ODE engine of particle scenes (bodies in Cartesian
// coordinates with run-time composed effects, constraints and contacts),
// run by the one integration driver (src/scene/particle_system.cpp).

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/analysis/fwd.hpp"
#include "lagrangian/scene/detail/registry.hpp"
#include "lagrangian/scene/hard_spheres.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/scene/scene.hpp"

namespace lagrangian::scene::detail {

/// What a particle run reports as it goes. `begin`, once before the first
/// sample: the names of the constraint rows (links, surfaces), in the order
/// of the multipliers the samples carry. `sample`, at each output time: t,
/// positions (3N, m), velocities (3N, m/s), T + V (J), the rows'
/// multipliers λ (N for a distance row) and the constraint force Cᵀλ on
/// each coordinate (N), both empty when the scene has no rows.
struct ParticleOutput {
  /// The fixed constraint rows' names and their multipliers' units.
  std::function<void(const std::vector<std::string>& rows, const std::vector<std::string>& units)> begin;
  std::function<void(double t, const double* q, const double* qd, int n, double energy,
                     const Eigen::VectorXd& multipliers, const Eigen::VectorXd& forces)>
      sample;
};

struct ParticleRun {
  RunReport report;
  std::map<std::string, std::uint64_t> effect_evaluations;
  std::vector<double> q_final, qd_final;
  std::uint64_t contact_locations = 0;  ///< see RunResult::contact_locations
};

/// The right-hand side ẋ = [v; a] a particle scene composes when it is built
/// (for benchmarks: the same code the ODE engine calls).
class ComposedRhs {
 public:
  explicit ComposedRhs(const Scene& scene);
  ~ComposedRhs();
  ComposedRhs(const ComposedRhs&) = delete;
  ComposedRhs& operator=(const ComposedRhs&) = delete;
  int size() const;  ///< 6N
  void operator()(const double* x, double* dx, double t);
  std::uint64_t evaluations() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Runs a validated scene whose gas (if any) has been expanded: the scene
/// as a System for the one driver (integrate.hpp).
ParticleRun run_particles(const Scene& scene, const ParticleOutput& output, const SampleTick& tick);

/// The names of the bodies' coordinates, "<body>.x", "<body>.y", "<body>.z"
/// for each body in order (the columns of trajectory.csv).
std::vector<std::string> body_coordinates(const Scene& scene);

/// The state x = [r; v] of the scene's bodies at t0: 3N positions (m),
/// then 3N velocities (m/s).
std::vector<double> initial_state(const Scene& scene);

/// True when the bodies fly freely between contacts: sphere or box contacts,
/// a box, and no effect or constraint (the exact event-driven engine applies).
bool event_driven_eligible(const Scene& scene);

/// An event_driven_eligible() scene's bodies, box, contact planes and
/// restitutions as the engine's HardSphereSystem (hard_spheres_scene.cpp).
HardSphereSystem hard_sphere_system(const Scene& scene);
/// The engine's run over `run`'s t0, t_end and output_interval (the scene's
/// own run, or an analysis's), logging the scene's output.max_events impacts.
HardSphereOptions hard_sphere_options(const Scene& scene, const SimulationOptions& run);

/// Lyapunov exponents and MEGNO, and Floquet multipliers, of a particle
/// scene's motion from its bodies' state at t0 (particle_tangent.cpp): its
/// tangent flow by automatic differentiation of its force effects and of
/// the rows of its links and surfaces, its contacts crossed at their
/// impacts by the saltation matrix. A gas runs on the event-driven
/// engine's tangent flow instead (scene/hard_spheres_tangent.hpp; its
/// Floquet multipliers are refused). A scene with rows and contacts
/// together or more than 100 bodies is refused with OptionError
/// ("lyapunov: particle scene '<name>': …").
LyapunovResult particle_lyapunov(const Scene& scene, const LyapunovOptions& options);
FloquetResult particle_floquet(const Scene& scene, const FloquetOptions& options);
/// ∂x(t)/∂x(t0) of the same motion (analysis/sensitivity.hpp); OptionError
/// as above, and for parameters (a particle scene's masses and effects are
/// not parameters of its tangent flow).
SensitivityResult particle_sensitivities(const Scene& scene, const SensitivityOptions& options);
/// What that tangent flow integrates: ∂a/∂(r, v) (3N × 6N; 1/s², 1/s) of
/// the scene's accelerations (its force effects, constrained by its links
/// and surfaces) at x = [r; v] (6N values, m and m/s), with the
/// accelerations a (3N values, m/s²) when `a` is given. OptionError as above.
Eigen::MatrixXd particle_acceleration_jacobian(const Scene& scene, const std::vector<double>& x,
                                               Eigen::VectorXd* a = nullptr);

/// Inspection text of a particle scene at t0.
std::string inspect_particles(const Scene& scene, bool as_json = false);

}  // namespace lagrangian::scene::detail
