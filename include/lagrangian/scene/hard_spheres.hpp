#pragma once
/// \file hard_spheres.hpp
/// An exact event-driven engine for smooth hard spheres in a box: between
/// collisions nothing acts on the spheres, so every sphere flies in a straight
/// line and the run jumps from one collision to the next.
///
/// **Free flight.** Sphere i carries a position r_i⁰ (m) valid at its own
/// reference time t_i (s) and a velocity v_i (m/s); its position at t is
///   r_i(t) = r_i⁰ + v_i (t − t_i).
/// Only the spheres taking part in an event are moved to the event time
/// (their r⁰ and t_i are rebased); all spheres are brought to a common time
/// only at the samples.
///
/// **Collision times.** Spheres i and j (radii R_i, R_j) touch when
///   |Δr + Δv τ|² = σ²,   Δr = r_i − r_j,  Δv = v_i − v_j,  σ = R_i + R_j,
/// a quadratic a τ² + 2 b τ + c = 0 with a = |Δv|², b = Δr·Δv (m²/s),
/// c = |Δr|² − σ² (m²). They meet only if b < 0 (approaching) and the
/// discriminant d = b² − a c > 0; the first contact is the smaller root, computed as
///   τ = c / (−b + √d)          (= (−b − √d)/a without cancellation).
/// Spheres found overlapping by round-off (c ≤ 0) while approaching collide at
/// once; b ≥ 0 is never a collision. Δr and Δv are formed at the later of
/// the two reference times, so a prediction does not depend on when (or by
/// which broad phase) it was made. A wall with inward unit normal n through
/// the point p is met when n·(r − p) = R, after τ = (n·(r − p) − R)/(−n·v) if n·v < 0.
///
/// **Impacts** (smooth spheres, Newton's law of restitution along the line of
/// centres n = (r_i − r_j)/|r_i − r_j|). With the approach speed
/// u = −(v_i − v_j)·n > 0 and the reduced mass μ = m_i m_j/(m_i + m_j), the
/// impulse on i is J n with
///   J = (1 + e) μ u   (N·s),   v_i ← v_i + (J/m_i) n,   v_j ← v_j − (J/m_j) n,
/// so the normal relative velocity becomes e u and the tangential components
/// are unchanged. On a head-on line this is
///   v₁' = ((m₁ − e m₂) v₁ + (1 + e) m₂ v₂)/(m₁ + m₂),
///   v₂' = ((m₂ − e m₁) v₂ + (1 + e) m₁ v₁)/(m₁ + m₂).
/// The kinetic energy lost is ½ μ (1 − e²) u² (J). At a wall the normal
/// velocity v_n = n·v < 0 becomes −e v_n and ½ m (1 − e²) v_n² is lost.
///
/// **Inelastic collapse** (e < 1: infinitely many collisions in a finite
/// time, e.g. a sphere trapped between two others or against a wall) is
/// avoided with the TC model of S. Luding and S. McNamara, "How to handle the
/// inelastic collapse of a dissipative hard-sphere gas with the TC model",
/// Granular Matter 1, 113 (1998): a collision (with a sphere or a wall) that
/// comes within HardSphereOptions::collapse_time of the previous impact of
/// either sphere is elastic (e = 1). Runs whose restitution coefficients are
/// all 1 are not affected.
///
/// **Event queue and broad phase** (the scheme of D. C. Rapaport, "The Art of
/// Molecular Dynamics Simulation", 2nd ed., Cambridge 2004, ch. 14, and
/// B. D. Lubachevsky, J. Comput. Phys. 94, 255 (1991)). Predicted
/// sphere–sphere collisions, sphere–wall collisions and cell crossings wait
/// in a binary heap ordered by time. Every sphere counts the impacts it has
/// taken part in; an event records the counts of its spheres when it was
/// predicted and is dropped, when it comes up, if one of them has changed.
/// The box is divided into a grid of cells no narrower than the largest
/// diameter (and at most ~8 cells per sphere); a sphere's possible partners
/// are looked for only in the 27 cells around its own, and moving from one
/// cell to the next is an event that looks for partners in the layer of 9
/// cells that has come into range. Per
/// collision the work is then O(1) candidates plus O(log H) for the heap of
/// H entries, so a gas of N spheres costs O(N log N) per unit simulated time.
/// Stale entries are left in the heap until they come up, and purged in one
/// pass when the heap outgrows max(8 N + 1024, twice its size after the
/// last purge); its storage is reserved up front (and grows geometrically
/// if it must), so processing an event allocates nothing.
///
/// Units: SI throughout (m, kg, s, m/s, J, N·s).

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/integrate/report.hpp"

namespace lagrangian {

/// A smooth hard sphere.
struct HardSphere {
  std::string name;           ///< used in event names ("s3-s7") and coordinates ("s3.x"); empty: "s<index+1>"
  double mass = 1.0;          ///< m (kg), finite and > 0
  double radius = 0.1;        ///< R (m), finite and > 0
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< centre r at t0 (m)
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< v at t0 (m/s)
};

/// A fixed plane wall. The spheres live on the side its normal points to:
/// n·(r − p) ≥ R for every sphere at every time.
struct HardWall {
  std::string name;           ///< used in event names ("s3-floor"); empty: "wall<index+1>"
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   ///< a point p of the plane (m)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ(); ///< n, pointing to the spheres' side (normalized by the engine)
  double restitution = 1.0;   ///< e ∈ [0, 1]
};

/// Names of the box's six faces, in the order x_min, x_max, y_min, y_max,
/// z_min, z_max (face k is normal to axis k / 2): event names ("s3-wall:x_max")
/// and RunReport::wall_impulses use them.
inline constexpr const char* box_wall_names[6] = {"wall:x_min", "wall:x_max", "wall:y_min",
                                                  "wall:y_max", "wall:z_min", "wall:z_max"};

/// Spheres in a rectangular box, optionally with extra plane walls.
struct HardSphereSystem {
  std::vector<HardSphere> spheres;
  /// The container's corners (m): every centre stays in
  /// [box_min + R, box_max − R] on each axis. Its six faces are walls named
  /// wall:x_min, wall:x_max, wall:y_min, … with restitution box_restitution.
  Eigen::Vector3d box_min = Eigen::Vector3d::Zero();
  Eigen::Vector3d box_max = Eigen::Vector3d::Ones();
  double box_restitution = 1.0;   ///< e of the box walls, in [0, 1]
  std::vector<HardWall> walls;    ///< optional extra planes
  double pair_restitution = 1.0;  ///< e of sphere–sphere impacts, in [0, 1]
};

/// How candidate collision partners are found.
enum class BroadPhase {
  cell_grid,  ///< the 27 neighbouring cells of a grid with cells ≥ the largest diameter (default)
  all_pairs,  ///< every other sphere: O(N) per event, O(N²) per unit time; a reference for tests and benchmarks
};

/// What a run does. Times in s.
struct HardSphereOptions {
  double t0 = 0.0;      ///< start time (s)
  double t_end = 1.0;   ///< end time (s), > t0
  /// Time between samples (s). 0: samples at t0 and t_end only; > 0: at
  /// t0 + k·output_interval and at t_end.
  double output_interval = 0.0;
  /// A run processing more events (collisions and cell crossings) fails
  /// with SimulationError.
  std::uint64_t max_events = 1'000'000'000;
  /// Impacts logged in RunReport::events (the rest are still counted in
  /// RunReport::impacts and impact_energy_loss). Each logged impact
  /// allocates its record; 0 logs none.
  std::size_t max_recorded_events = 100'000;
  /// t_c of the TC model (s): an impact within t_c of the previous impact of
  /// either sphere is elastic. 1 ns suits spheres of millimetres to metres
  /// moving at mm/s to km/s (mean free times ≫ 1 ns); scale it with the
  /// system's shortest time between collisions. 0 disables the model.
  double collapse_time = 1e-9;
  /// Point r₀ (m) about which the angular momentum L = Σ m (r − r₀) × v is reported.
  Eigen::Vector3d angular_momentum_point = Eigen::Vector3d::Zero();
  BroadPhase broad_phase = BroadPhase::cell_grid;
};

/// Called at every sample with the time t (s) and all spheres moved to t:
/// position (m), velocity (m/s), masses and radii as given, empty names
/// replaced by "s<index+1>". The vector is the engine's own synchronized
/// copy, valid during the call. An impact at exactly a sample time is
/// resolved after the sample (the sample shows the spheres touching).
using HardSphereSampler = std::function<void(double t, const std::vector<HardSphere>&)>;

/// One impact as the engine resolved it, for a HardSphereImpactObserver:
/// sphere `a` against sphere `b` or, with b = −1, against wall `wall`.
struct HardSphereImpact {
  double t = 0;         ///< time of the impact (s)
  std::size_t a = 0;    ///< the sphere (index into HardSphereSystem::spheres)
  std::ptrdiff_t b = -1;  ///< the other sphere, or −1 at a wall
  /// At a wall: 0 … 5 the box's faces (box_wall_names' order), 6 + k the
  /// extra wall k; −1 for two spheres.
  int wall = -1;
  /// Unit normal: from b's centre to a's (two spheres), the wall's inward
  /// normal (a wall).
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double distance = 0;     ///< |r_a − r_b| at the impact (m), R_a + R_b to round-off; 0 at a wall
  double restitution = 1;  ///< e applied (1 where the TC model made the impact elastic)
  Eigen::Vector3d va_before = Eigen::Vector3d::Zero(), va_after = Eigen::Vector3d::Zero();  ///< v_a (m/s)
  Eigen::Vector3d vb_before = Eigen::Vector3d::Zero(), vb_after = Eigen::Vector3d::Zero();  ///< v_b (m/s); 0 at a wall
};

/// Called at every impact, in the order the engine resolves them, after
/// the velocities have changed (lyapunov_hard_spheres() carries its tangent
/// vectors across them).
using HardSphereImpactObserver = std::function<void(const HardSphereImpact&)>;

/// Checks a system and options; throws OptionError, naming the sphere(s) or
/// wall or option and the offending values, for: a non-finite or inverted
/// box; a mass or radius that is not finite and > 0; a non-finite position
/// or velocity; a sphere not inside the box (its centre must lie in
/// [box_min + R, box_max − R]) or on the wrong side of an extra wall
/// (n·(r − p) < R); two spheres overlapping at t0 (|r_i − r_j| < R_i + R_j:
/// both names, the distance and the sum of radii); duplicate names; a
/// restitution coefficient outside [0, 1]; a zero or non-finite wall normal;
/// t_end ≤ t0, a non-finite time, output_interval < 0, max_events = 0 or
/// collapse_time < 0. Costs O(N) (overlaps are looked for on a cell grid).
void validate(const HardSphereSystem& system, const HardSphereOptions& options);

/// Runs the event-driven engine from options.t0 to options.t_end, sending
/// samples to `sampler` (if any), and reports:
///  - model "hard spheres (event-driven)", method "event_driven", not adaptive;
///  - steps: events processed — collisions plus cell crossings (stale queue
///    entries not counted); rhs_evaluations = 0;
///  - samples: sample times taken (the statistics below are gathered there
///    whether or not a sampler is given);
///  - coordinates "s1.x", "s1.y", "s1.z", … (sphere names);
///  - energy = kinetic energy T = Σ ½ m |v|² (J); conservative iff every
///    restitution coefficient is 1. The drift is measured against
///    T0 − (energy lost at the impacts so far), each loss taken from the
///    closed form above, so it measures the engine's own round-off also when
///    e < 1: energy_drift_* = |T − T0 + loss| / energy_scale, energy_scale = T0
///    (1 J when T0 = 0);
///  - has_particles: total linear momentum P = Σ m v and angular momentum L
///    about options.angular_momentum_point at t0, and their drifts over the
///    samples as they are: pair impacts conserve both, wall impacts change them;
///  - events: the first max_recorded_events impacts (kind impact, name
///    "s3-s7" or "s3-wall:x_max", impulse J (N·s), approach speed u,
///    separation speed, and the system's kinetic energy before and after,
///    T0 minus the losses so far); impacts counts all of them;
///    impact_energy_loss their summed losses (J); t_final = t_end;
///  - wall_impulses: the normal impulse each wall received over the run
///    (N·s), every impact counted: the six box faces ("wall:x_min", …) and
///    the extra planes.
/// `on_impact`, if given, sees every impact (HardSphereImpact).
/// Throws OptionError (see validate) and SimulationError when more than
/// options.max_events events are needed.
RunReport run_hard_spheres(const HardSphereSystem& system, const HardSphereOptions& options,
                           const HardSphereSampler& sampler = {}, const HardSphereImpactObserver& on_impact = {});

}  // namespace lagrangian
