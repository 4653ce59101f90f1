#pragma once
/// \file scene.hpp
/// Scenes: a mechanical system composed at run time.
///
/// A scene is either
///  - a set of bodies (point masses and smooth spheres, Cartesian coordinates
///    x, y, z in m) with the effects that act on them — uniform gravity,
///    Newtonian gravity between bodies, linear springs, linear and quadratic
///    drag — the constraints that bind them — fixed-distance links and
///    surfaces a body is bound to — and the contacts they can hit —
///    sphere–sphere, sphere–plane and the walls of a box, each with its
///    coefficient of restitution e; or
///  - one of the built-in generalized-coordinate models with its parameters
///    (see `lagrangian list`), integrated by simulate();
/// plus the stepper, tolerances, time span and outputs.
///
/// The same vocabulary is written in TOML (docs/scenes.md, load_scene() in
/// scene/io.hpp) and in C++: a Scene is a plain aggregate.
/// \code
/// lagrangian::scene::Scene s;
/// s.name = "projectile";
/// s.bodies.push_back({.name = "ball", .mass = 0.2, .position = {0, 0, 1}, .velocity = {10, 0, 10}});
/// s.gravity = lagrangian::scene::UniformGravity{};
/// s.run.t_end = 2.0;
/// lagrangian::scene::RunResult r = lagrangian::scene::run(s);
/// \endcode
///
/// Only what a scene declares is built: build_scene() turns the declared
/// effects into a list of force kernels once, so the right-hand side visits
/// exactly those — no contact search without contacts, no constraint solve
/// without constraints, no drag term without drag.

#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/errors.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/text/definition.hpp"

namespace lagrangian::scene {

using Vec3 = Eigen::Vector3d;

/// A point mass (radius 0) or a smooth sphere (radius > 0).
struct Body {
  std::string name;               ///< unique name, used by effects, contacts and outputs
  double mass = 1.0;              ///< m (kg), > 0
  double radius = 0.0;            ///< R (m), ≥ 0; contacts see the body as a sphere of this radius
  Vec3 position = Vec3::Zero();   ///< r(t0) (m)
  Vec3 velocity = Vec3::Zero();   ///< ṙ(t0) (m/s)
};

/// Spheres placed at random in the box (the course notes' gas molecules in a
/// container): `count` spheres of one mass and radius, at the sites of a
/// cubic lattice filling the box (so none overlap), with speed `speed` in
/// directions drawn uniformly on the sphere from a seeded generator, then
/// shifted to zero total momentum and rescaled to rms speed `speed`
/// (docs/scenes.md). Needs a box contact. Bodies are named <prefix>1,
/// <prefix>2, …
struct GasFill {
  static constexpr int max_count = 10'000'000;  ///< largest accepted `count`
  int count = 0;                  ///< number of spheres, in [1, max_count]
  double mass = 1.0;              ///< kg, > 0
  double radius = 0.01;           ///< m, > 0
  double speed = 1.0;             ///< rms of |ṙ(t0)| (m/s), ≥ 0
  std::uint64_t seed = 1;         ///< random seed (same seed, same gas)
  std::string prefix = "m";       ///< body name prefix
};

// -- effects ------------------------------------------------------------------

/// Uniform gravity on every body: F = m g, V = −m g·r (J).
struct UniformGravity {
  Vec3 g{0.0, 0.0, -9.81};  ///< acceleration of gravity (m/s²)
};

/// Newtonian gravity between every pair of bodies:
/// V = −G m_i m_j / |r_i − r_j| (J), F_i = −G m_i m_j (r_i − r_j)/|r_i − r_j|³ (N).
struct NewtonianGravity {
  double G = 6.67430e-11;  ///< gravitational constant (m³ kg⁻¹ s⁻²), CODATA 2018
};

/// A linear spring between two bodies, or between a body and a fixed anchor:
/// V = ½ k (|r_a − r_b| − L₀)² (J).
struct Spring {
  std::string name;               ///< optional; defaults to "spring<i>"
  std::string a;                  ///< first body
  std::string b;                  ///< second body; empty: the spring is fixed at `anchor`
  Vec3 anchor = Vec3::Zero();     ///< fixed end (m), used when b is empty
  double stiffness = 0.0;         ///< k (N/m), > 0
  double rest_length = 0.0;       ///< L₀ (m), ≥ 0
};

/// Linear (viscous) drag F = −b ṙ (N) on the listed bodies (all when empty);
/// Rayleigh function D = ½ b |ṙ|² (W).
struct LinearDrag {
  double coefficient = 0.0;         ///< b (kg/s), ≥ 0
  std::vector<std::string> bodies;  ///< bodies it acts on; empty: all
};

/// Quadratic drag F = −c |ṙ| ṙ (N) on the listed bodies (all when empty);
/// D = ⅓ c |ṙ|³ (W).
struct QuadraticDrag {
  double coefficient = 0.0;         ///< c (kg/m), ≥ 0
  std::vector<std::string> bodies;  ///< bodies it acts on; empty: all
};

// -- constraints ----------------------------------------------------------------

/// A massless rigid link of fixed length between two bodies, or between a body
/// and a fixed anchor (a pendulum): g = ½(|r_a − r_b|² − L²) = 0 (m²).
struct Link {
  std::string name;               ///< optional; defaults to "link<i>"
  std::string a;                  ///< first body
  std::string b;                  ///< second body; empty: anchored at `anchor`
  Vec3 anchor = Vec3::Zero();     ///< fixed end (m), used when b is empty
  /// L (m), > 0. Not given (NaN): the distance at t0. Given: the initial
  /// positions must satisfy it to 1e-9 relative.
  double length = std::numeric_limits<double>::quiet_NaN();
};

/// A body bound to a fixed surface (a bead on a wire is two surfaces):
///  plane:  g = n·(r − p) = 0 (m);
///  sphere: g = ½(|r − c|² − ρ²) = 0 (m²).
/// The initial position must lie on it (1e-9 relative) and the initial
/// velocity must be tangent to it (the velocity is not silently changed).
struct Surface {
  enum class Kind { plane, sphere };
  std::string name;               ///< optional; defaults to "surface<i>"
  std::string body;               ///< the bound body
  Kind kind = Kind::plane;
  Vec3 point = Vec3::Zero();      ///< plane: a point p on it; sphere: its centre c (m)
  Vec3 normal{0.0, 0.0, 1.0};     ///< plane: normal n (normalised when built)
  double radius = 0.0;            ///< sphere: ρ (m), > 0
};

// -- contacts -------------------------------------------------------------------

/// Sphere–sphere contacts among the listed bodies (all bodies when empty):
/// gap φ = |r_i − r_j| − (R_i + R_j) ≥ 0, Newton's law with restitution e.
struct SphereContacts {
  double restitution = 1.0;         ///< e in [0, 1]
  std::vector<std::string> bodies;  ///< bodies that collide with each other; empty: all
};

/// A fixed plane that the listed bodies (all when empty) stay on the
/// normal side of: φ = n·(r − p) − R ≥ 0.
struct PlaneContact {
  std::string name;                 ///< optional; defaults to "plane<i>"
  Vec3 point = Vec3::Zero();        ///< a point p on the plane (m)
  Vec3 normal{0.0, 0.0, 1.0};       ///< n, towards the allowed side (normalised when built)
  double restitution = 1.0;         ///< e in [0, 1]
  std::vector<std::string> bodies;  ///< bodies it stops; empty: all
};

/// The six walls of an axis-aligned box that holds every body:
/// φ = x − R − x_min ≥ 0, x_max − x − R ≥ 0, and likewise for y and z.
struct BoxContact {
  Vec3 min = Vec3::Zero();          ///< lower corner (m)
  Vec3 max = Vec3::Ones();          ///< upper corner (m), > min on every axis
  double restitution = 1.0;         ///< e in [0, 1]
};

// -- built-in model ---------------------------------------------------------------

/// A model stated by expressions (text/text_model.hpp): T, V and
/// optionally Q, D and holonomic and Pfaffian constraints, of the
/// coordinates, their velocities `<name>_dot`, t and the parameters of
/// ModelSpec::parameters.
struct TextModelSpec {
  std::vector<std::string> coordinates;  ///< names of q_i
  std::vector<std::string> units;        ///< SI unit of each q_i; empty: none given
  std::string kinetic;                   ///< T (J)
  std::string potential;                 ///< V (J); empty: 0
  std::vector<std::string> forces;       ///< generalized forces Q_i; empty: none
  std::string dissipation;               ///< Rayleigh D (W); empty: none
  std::vector<std::string> holonomic;    ///< holonomic constraints g_i(q, t) = 0; empty: none
  std::vector<std::string> pfaffian;     ///< Pfaffian constraints A_i(q, t)·q̇ + a_i(q, t) = 0; empty: none
  std::vector<std::string> constraint_names;  ///< one per constraint (holonomic, then Pfaffian); empty: g0, …, a0, …
  std::vector<std::string> constraint_units;  ///< unit of each constraint function; empty: none given
  std::vector<lagrangian::text::Contact> contacts;  ///< [[model.contacts]]: gaps ≥ 0 with restitution
  /// A point drawn on the animation page: x, y, z (m) as expressions of q and t.
  struct Point {
    std::string name;
    double mass = 0;     ///< kg (0: drawn only)
    std::string x, y, z; ///< empty: 0
  };
  std::vector<Point> points;  ///< [[model.points]]
  bool rods = false;          ///< rods from the origin through consecutive points
};

namespace detail {
class UserModel;  // scene/detail/model_run.hpp
}

/// A generalized-coordinate model: one of the built-in models (`lagrangian
/// list`), one stated by expressions (`text`), or a C++ model handed to
/// scene::run_model() (`user`).
struct ModelSpec {
  std::string name;                          ///< registry name, e.g. "double_pendulum"; empty for a text model
  /// Overrides of a built-in model's defaults, or a text model's parameters (SI units).
  std::map<std::string, double> parameters;
  std::vector<double> q;                     ///< q(t0); empty: the model's default state
  std::vector<double> qd;                    ///< q̇(t0); empty: the model's default state (a text model: 0)
  std::optional<TextModelSpec> text;         ///< set for a model stated by expressions
  /// Set by scene::run_model() (scene/model_run.hpp): a C++ model with its
  /// initial state (name, parameters, q and qd then stay empty).
  std::shared_ptr<const detail::UserModel> user;
};

// -- run and outputs --------------------------------------------------------------

/// How the scene is integrated: the options of simulate() (report.hpp;
/// times in s), of which a scene file sets method, t0, t_end, dt, rtol,
/// atol, output_interval (0.01 s unless given), max_steps, stabilization and
/// baumgarte_omega, and the engine.
struct RunSpec : SimulationOptions {
  RunSpec() { output_interval = 0.01; }
  /// "auto": the exact event-driven engine when the bodies fly freely between
  /// contacts (spheres in a box, no forces, no constraints), else "ode";
  /// "event_driven" (a scene file may also say method = "event_driven").
  std::string engine = "auto";
  /// The key that chose the engine, named by messages about it: "run.engine",
  /// or "run.method" when the file chose it by method = "event_driven".
  std::string engine_key = "run.engine";
};

/// What a run writes.
struct OutputSpec {
  std::string directory = "out";   ///< trajectory.csv, events.csv, report.json and plots go here
  bool trajectory = true;          ///< write trajectory.csv
  bool plots = true;               ///< make plots with gnuplot (skipped with a note when it is missing)
  bool png = true;                 ///< plots as PNG
  bool svg = true;                 ///< plots as SVG
  /// write animation.html: the bodies moving in space, with the energy and
  /// coordinates against time (view.hpp)
  bool animation = true;
  /// Events written to events.csv and kept in the report by the event-driven
  /// engine (every impact is still counted and its energy loss summed); a
  /// run that has more says so in its summary, report.json and events.csv.
  std::uint64_t max_events = 100'000;
};

/// Where each key of a scene file was written: key path ("bodies[2].mass")
/// → line (1-based). Filled by the TOML reader so that errors found later can
/// point at the line; empty for scenes built in C++.
struct SourceMap {
  std::string file;
  std::map<std::string, int> lines;
  /// Keys set from the command line after the file was read: key → the flag
  /// ("run.rtol" → "--rtol"); errors in them name the flag, not the file.
  std::map<std::string, std::string> overrides;
  int line_of(const std::string& key) const;  ///< the line of key, or of its nearest written parent; 0 if none
};

/// A scene: what to simulate, how and what to write.
struct Scene {
  std::string name = "scene";
  std::string description;

  std::vector<Body> bodies;
  std::optional<GasFill> gas;

  std::optional<UniformGravity> gravity;
  std::optional<NewtonianGravity> newtonian_gravity;
  std::vector<Spring> springs;
  std::vector<LinearDrag> linear_drag;
  std::vector<QuadraticDrag> quadratic_drag;

  std::vector<Link> links;
  std::vector<Surface> surfaces;

  std::optional<SphereContacts> sphere_contacts;
  std::vector<PlaneContact> planes;
  std::optional<BoxContact> box;

  std::optional<ModelSpec> model;

  RunSpec run;
  OutputSpec output;
  SourceMap source;

  /// Checks every value; throws SceneError naming the key, the value and,
  /// for scene files, the file and line. Also checks the bodies' initial
  /// state: no two spheres in contact overlapping, constraints satisfied.
  void validate() const;
  /// Adds the bodies of `gas` (if any) to `bodies` and clears `gas`.
  void expand_gas();
  /// Names of the declared effect kinds, constraints and contacts, in a fixed
  /// order: "uniform_gravity", "newtonian_gravity", "springs", "linear_drag",
  /// "quadratic_drag", "links", "surfaces", "sphere_contacts",
  /// "plane_contacts", "box_contacts" — only those the scene declares.
  std::vector<std::string> declared() const;
};

/// A scene value is invalid: the message is
///   "<file>:<line>: <key>: <what is wrong>" (scene files) or
///   "scene: <key>: <what is wrong>" (scenes built in C++).
/// Without a line for the key (nor for any parent) it is
/// "<file>: <key>: <what is wrong>"; with an empty key (TOML syntax errors,
/// unreadable files) the "<key>: " part is left out.
class SceneError : public OptionError {
 public:
  SceneError(const std::string& key, const std::string& what, const SourceMap& source = {});
  const std::string& key() const noexcept { return key_; }
  int line() const noexcept { return line_; }
  /// What is wrong, without the file, line and key.
  const std::string& message() const noexcept { return message_; }

 private:
  std::string key_;
  std::string message_;
  int line_ = 0;
};

/// The candidate nearest to `word` by edit distance, or "" when none is
/// close (distance > max(2, |word|/3)). For "did you mean" hints.
std::string nearest(const std::string& word, const std::vector<std::string>& candidates);

}  // namespace lagrangian::scene
