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

#include "lagrangian/detail/scene_registry.hpp"
#include "lagrangian/report.hpp"
#include "lagrangian/scene.hpp"

namespace lagrangian::scene::detail {

/// A sample of a particle run: t, positions (3N), velocities (3N), T + V.
using ParticleSample = std::function<void(double t, const double* q, const double* qd, int n, double energy)>;

struct ParticleRun {
  RunReport report;
  std::map<std::string, std::uint64_t> effect_evaluations;
  std::vector<double> q_final, qd_final;
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

/// The integration options of a scene's [run] table.
SimulationOptions options_of(const RunSpec& run);

/// Runs a validated scene whose gas (if any) has been expanded: the scene
/// as a System for the one driver (integrate.hpp).
ParticleRun run_particles(const Scene& scene, const ParticleSample& sample, const SampleTick& tick);

/// True when the bodies fly freely between contacts: sphere or box contacts,
/// a box, and no effect or constraint (the exact event-driven engine applies).
bool event_driven_eligible(const Scene& scene);

/// Inspection text of a particle scene at t0.
std::string inspect_particles(const Scene& scene);

}  // namespace lagrangian::scene::detail
