// The particle scenes' engine: a scene of bodies (particle_model.hpp) as a
// System for the one integration driver (integrate.hpp). This adapter has
// no loop or stepper of its own: it supplies the right-hand side, the
// monitors at samples, the projection of constraint rows, and the contacts
// — a broad phase (sweep and prune), their location on the driver's step
// interpolant and their resolution by Newton's law with the rules every
// system shares (integrate/detail/contact_rules.hpp: touching, closing, lift-off, the
// Zeno rule).

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <utility>

#include "lagrangian/integrate/detail/contact_rules.hpp"
#include "lagrangian/integrate/detail/energy_monitor.hpp"
#include "lagrangian/integrate/detail/contacts.hpp"
#include "lagrangian/integrate/detail/momentum_symmetry.hpp"
#include "lagrangian/integrate/detail/point_momenta_monitor.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/integrate/integrate.hpp"
#include "lagrangian/integrate/system.hpp"
#include "particle_engine.hpp"
#include "particle_impact.hpp"
#include "particle_model.hpp"

namespace lagrangian::scene::detail {
namespace {

using namespace particles;
using lagrangian::detail::Closing;
using lagrangian::detail::GapRate;

/// The path of the bodies inside a step, for sorting out the candidate
/// contacts that merely pass by: the step's interpolant evaluated at six
/// times t_old + k h / 5 (the ends exactly), and each coordinate between them
/// by the polynomial of degree 5 through those values. dopri5's dense output
/// is itself of degree 5 in the time, so for it this reproduces the
/// interpolant to rounding; for the steppers that locate on a
/// sub-integration it is a close stand-in. One contact's gap then costs a
/// few dozen operations instead of a whole state's interpolation (a gas of
/// 1 000 spheres has thousands of candidate pairs per step); contacts that
/// may close are located on the interpolant itself.
class StepPath {
 public:
  static constexpr int kNodes = 6;

  void reset(double t0, double t1, const double* x0, const double* x1, int dim) {
    t0_ = t0;
    h_ = t1 - t0;
    dim_ = dim;
    x0_ = x0;
    x1_ = x1;
    ready_ = false;
  }
  /// Evaluates the interior nodes, once per step, when first needed.
  void prepare(const StepInterpolant& interp) {
    if (ready_) return;
    const auto size = static_cast<std::size_t>(2 * dim_);
    nodes_.resize(kNodes * size);
    std::copy(x0_, x0_ + size, nodes_.begin());
    for (int k = 1; k + 1 < kNodes; ++k)
      interp(t0_ + h_ * k / (kNodes - 1), nodes_.data() + static_cast<std::size_t>(k) * size);
    std::copy(x1_, x1_ + size, nodes_.begin() + static_cast<std::ptrdiff_t>((kNodes - 1) * size));
    ready_ = true;
  }
  double t0() const { return t0_; }
  double t1() const { return t0_ + h_; }
  /// Position and velocity of body i at time t inside the step.
  void body(int i, double t, Vector3d& r, Vector3d& v) const {
    std::array<double, kNodes> w;  // Lagrange weights at θ = (t − t0)/h, nodes θ_k = k/5
    const double theta = (t - t0_) / h_ * (kNodes - 1);
    for (int k = 0; k < kNodes; ++k) {
      double wk = 1;
      for (int j = 0; j < kNodes; ++j)
        if (j != k) wk *= (theta - j) / (k - j);
      w[static_cast<std::size_t>(k)] = wk;
    }
    const auto size = static_cast<std::size_t>(2 * dim_);
    for (int c = 0; c < 3; ++c) {
      double rc = 0, vc = 0;
      for (int k = 0; k < kNodes; ++k) {
        const double* node = nodes_.data() + static_cast<std::size_t>(k) * size;
        rc += w[static_cast<std::size_t>(k)] * node[3 * i + c];
        vc += w[static_cast<std::size_t>(k)] * node[dim_ + 3 * i + c];
      }
      r[c] = rc;
      v[c] = vc;
    }
  }

 private:
  double t0_ = 0, h_ = 0;
  int dim_ = 0;
  const double *x0_ = nullptr, *x1_ = nullptr;
  bool ready_ = false;
  std::vector<double> nodes_;
};

/// The scene's contacts for detail::resolve_contacts, numbered by
/// Contact::id. The change of kinetic energy ΔT at each impact at t goes to
/// the energy monitor (EnergyMonitor::shift: h and E move alike here).
class ParticleContacts final : public lagrangian::detail::ContactSystem {
 public:
  ParticleContacts(ParticleModel& model, lagrangian::detail::EnergyMonitor& energy)
      : model_(model), energy_(energy) {}

  int coordinates() const override { return model_.dim(); }
  std::string contact_name(int j) const override { return model_.contact(j).name; }
  void gap_rates(const double* x, double, const std::vector<int>& which, GapRate* out) override {
    const double* v = x + model_.dim();
    for (std::size_t k = 0; k < which.size(); ++k) {
      const Contact& c = model_.contact(which[k]);
      out[k] = {c.gap(x), c.rate(x, v)};
    }
  }
  void near(const double* x, double, double touch, int, std::vector<int>& out) override {
    model_.near_contacts(x, touch, near_);
    out.clear();
    for (const Contact* c : near_) out.push_back(c->id);
  }
  lagrangian::detail::ContactHistory& history(int j) override { return model_.contact(j).history; }
  double restitution(int j) const override { return model_.contact(j).e; }
  bool pressed(int j, const double* x, double) override { return model_.pressed(x, model_.contact(j)); }
  lagrangian::detail::LawResult apply_law(int j, double e, double* x, double t, bool record) override {
    const Contact& c = model_.contact(j);
    const double* v = x + model_.dim();
    lagrangian::detail::LawResult r;
    r.kinetic_before = model_.kinetic(x);
    r.approach = -c.rate(x, v);
    r.impulse = impulse(model_, c, e, x);
    r.kinetic_after = model_.kinetic(x);
    r.separation = c.rate(x, v);
    if (record) energy_.shift(t, r.kinetic_after - r.kinetic_before, r.kinetic_after - r.kinetic_before);
    return r;
  }
  std::pair<double, double> jump_velocities(double* x, const double* v, double t) override {
    const double T_before = model_.kinetic(x);
    std::copy(v, v + model_.dim(), x + model_.dim());
    const double T_after = model_.kinetic(x);
    energy_.shift(t, T_after - T_before, T_after - T_before);
    return {T_before, T_after};
  }
  /// Σ_k J_k n_k (on both bodies of a pair) = M Δv: least squares.
  void impulse_shares(const double* x, const double* v, double, const std::vector<int>& which,
                      double* out) override {
    const int dim = model_.dim();
    Eigen::MatrixXd N = Eigen::MatrixXd::Zero(dim, static_cast<Eigen::Index>(which.size()));
    Eigen::VectorXd dp(dim);
    for (int i = 0; i < dim; ++i) dp[i] = model_.mass()[static_cast<std::size_t>(i / 3)] * (v[i] - x[dim + i]);
    for (std::size_t k = 0; k < which.size(); ++k) {
      const Contact& c = model_.contact(which[k]);
      const Vector3d nrm = c.normal(x);
      N.block<3, 1>(3 * c.a, static_cast<Eigen::Index>(k)) = nrm;
      if (c.pair) N.block<3, 1>(3 * c.b, static_cast<Eigen::Index>(k)) = -nrm;
    }
    Eigen::Map<Eigen::VectorXd>(out, static_cast<Eigen::Index>(which.size())) =
        N.completeOrthogonalDecomposition().solve(dp);
  }
  double kinetic(const double* x, double) override { return model_.kinetic(x); }
  bool resting(int j) const override { return model_.contact(j).resting; }
  void resting_contacts(std::vector<int>& out) const override {
    out.clear();
    for (const Contact* c : model_.resting_contacts()) out.push_back(c->id);
  }
  void rest(int j) override { model_.make_resting(model_.contact(j)); }
  void release(int j) override { model_.release(resting_index(j)); }

  /// The broad phase (sweep and prune over the step, ParticleModel::
  /// candidates), from the accelerations at both ends; the end of the
  /// previous step is reused when nothing has moved the state since.
  void step_candidates(double t0, const double* x0, double t1, const double* x1, std::vector<int>& out) override {
    const int dim = model_.dim();
    const auto n2 = static_cast<std::size_t>(2 * dim);
    f0_.resize(n2);
    f1_.resize(n2);
    if (x_f_.size() == n2 && std::equal(x0, x0 + n2, x_f_.begin())) {
      std::swap(f0_, f1_);
    } else {
      model_.rhs(x0, f0_.data(), t0);
    }
    model_.rhs(x1, f1_.data(), t1);
    x_f_.assign(x1, x1 + n2);
    lambda_at_ = x1;  // the resting contacts' multipliers at the step's end, from that evaluation
    model_.candidates(x0, x1, f0_.data() + dim, f1_.data() + dim, t1 - t0, cand_);
    path_.reset(t0, t1, x0, x1, dim);
    out.clear();
    for (const Contact* c : cand_) out.push_back(c->id);
  }
  void resting_multipliers(const double* x, double t, const std::vector<int>& which, double* out) override {
    if (x != lambda_at_) {
      scratch_.resize(static_cast<std::size_t>(2 * model_.dim()));
      model_.rhs(x, scratch_.data(), t);
    }
    lambda_at_ = nullptr;
    for (std::size_t k = 0; k < which.size(); ++k) out[k] = model_.resting_multiplier(resting_index(which[k]));
  }
  /// On the step path (StepPath): the bodies of the contact only.
  GapRate gap_on_path(int j, double ts, const StepInterpolant& interp) override {
    const Contact& c = model_.contact(j);
    path_.prepare(interp);
    Vector3d ra, va, rb = Vector3d::Zero(), vb = Vector3d::Zero();
    path_.body(c.a, ts, ra, va);
    if (c.pair) path_.body(c.b, ts, rb, vb);
    return c.gap_rate(ra, va, rb, vb);
  }

 private:
  /// The place of contact j among the resting contacts (the order of their rows).
  std::size_t resting_index(int j) const {
    const auto& resting = model_.resting_contacts();
    return static_cast<std::size_t>(std::find_if(resting.begin(), resting.end(),
                                                 [j](const Contact* c) { return c->id == j; }) -
                                    resting.begin());
  }

  ParticleModel& model_;
  lagrangian::detail::EnergyMonitor& energy_;  ///< moved by what each impact takes (h = E here)
  std::vector<Contact*> near_, cand_;
  std::vector<double> f0_, f1_, x_f_, scratch_;  // f at a step's two ends, the end's state
  const double* lambda_at_ = nullptr;  // where the model's multipliers were last evaluated, when known
  StepPath path_;
};

class ParticleSystem final : public lagrangian::System {
 public:
  ParticleSystem(const Scene& scene, const SimulationOptions& options, const ParticleOutput& output,
                 const SampleTick& tick, ParticleRun& out)
      : model_(scene), opt_(options), output_(output), tick_(tick), out_(out), rep_(out.report) {
    const auto size = static_cast<std::size_t>(2 * model_.dim());
    scratch_.assign(size, 0.0);
    sample_x_.assign(size, 0.0);
    if (opt_.stabilization == Stabilization::baumgarte) model_.omega = opt_.baumgarte_omega;
  }

  int coordinate_count() const override { return model_.dim(); }
  void rhs(const double* x, double* dxdt, double t) const override { model_.rhs(x, dxdt, t); }

  void start(double* x, double t0) override {
    rep_.conservative = !model_.dissipative();
    const double T0 = model_.kinetic(x), V0 = model_.potential(x);
    energy_.start(rep_, T0 + V0, T0, V0);  // h = T + V: particles in fixed surroundings
    rep_.has_particles = true;
    probe_momentum_symmetry(x, t0);
    rep_.constrained = model_.fixed_rows() > 0;
    if (rep_.constrained) {
      for (const Row& r : model_.rows()) rep_.constraints.names.push_back(r.name);
      rep_.constraints.stabilization = to_string(opt_.stabilization);
      rep_.constraints.baumgarte_omega = model_.omega;
      Eigen::MatrixXd C;
      jacobian(model_.rows(), x, model_.dim(), C);
      rep_.constraints.initial_rank = rep_.constraints.min_rank = lagrangian::detail::numeric_rank(C);
      // The fixed rows that add no rank to those before them (a link
      // declared twice, a surface repeating a link), named as models' are.
      for (int k : lagrangian::detail::rows_adding_no_rank(C, model_.fixed_rows()))
        rep_.constraints.warnings.push_back(
            lagrangian::detail::redundant_constraint_warning(model_.rows()[static_cast<std::size_t>(k)].name));
    }
    if (output_.begin) {
      std::vector<std::string> names, units;
      for (int k = 0; k < model_.fixed_rows(); ++k) {
        const Row& row = model_.rows()[static_cast<std::size_t>(k)];
        names.push_back(row.name);
        units.push_back(row.multiplier_unit());
      }
      output_.begin(names, units);
    }
    // Contacts closing or resting at t0: every touching one takes part, and the rests that begin are not logged.
    if (model_.has_contacts()) events_.resolve(contacts_, x, t0, -1, false, opt_, rep_);
  }

  void sample(double t, const double* x_in) override {
    // With projection (the default), a sample from the dense output between steps is projected onto the
    // constraint rows as the steps are, so that samples meet the steps' tolerance; the integration's own
    // state stays as it is.
    const double* x = x_in;
    if (projects()) {
      std::copy(x_in, x_in + 2 * model_.dim(), sample_x_.begin());
      model_.project(sample_x_.data(), 1e-12);
      x = sample_x_.data();
    }
    const double T = model_.kinetic(x), V = model_.potential(x), E = T + V;
    if (!std::isfinite(E)) lagrangian::detail::throw_non_finite_energy(t, E, x, model_.dim());
    energy_.sample_h_is_total(rep_, t, T, V);
    // P and L about the origin (the point the symmetry probe judges them about).
    momenta_.clear();
    const int dim = model_.dim();
    for (int i = 0; i < model_.bodies(); ++i) momenta_.add(model_.mass()[static_cast<std::size_t>(i)], x + 3 * i, x + dim + 3 * i);
    momenta_.record(rep_);
    double scale = rep_.coordinate_scale;
    for (int i = 0; i < dim; ++i) scale = std::max(scale, std::abs(x[i]));
    rep_.coordinate_scale = scale;
    if (rep_.constrained && !model_.rows().empty()) {
      rep_.constraints.min_rank = std::min(rep_.constraints.min_rank, rank(x));
      record_residuals(x);
    }
    if (output_.sample) {
      if (model_.fixed_rows() > 0) multipliers_at(x, t);
      output_.sample(t, x, x + model_.dim(), model_.dim(), E, lambda_, forces_);
    }
    if (tick_) {
      const auto dim = static_cast<std::size_t>(model_.dim());
      tick_(SampleRow{t, {x, dim}, {x + dim, dim}, E, std::numeric_limits<double>::quiet_NaN()});
    }
  }

  void finish(double t, const double* x, bool sample_end) override {
    if (sample_end) sample(t, x);
    energy_.finish(rep_, t);  // from the last sample, at the end, as the CSV's last row has it
    if (rep_.constrained) {
      rep_.constraints.final_position_residual = model_.position_residual(x);
      rep_.constraints.final_velocity_residual = model_.velocity_residual(x);
    }
    const int dim = model_.dim();
    out_.q_final.assign(x, x + dim);
    out_.qd_final.assign(x + dim, x + 2 * dim);
    out_.effect_evaluations = model_.counts();
    rep_.rhs_evaluations = model_.rhs_evaluations;  // every evaluation, the contacts' too
    out_.contact_locations = events_.locations();
  }

  /// Constraint rows: the links and surfaces, and resting contacts.
  bool has_constraints() const override { return model_.fixed_rows() > 0 || model_.has_contacts(); }

  /// Constraint rows are held by projection (the default stabilization), at steps and at samples.
  bool projects() const { return !model_.rows().empty() && opt_.stabilization == Stabilization::projection; }

  bool stabilize(double* x, double t, bool allow_projection) override {
    (void)t;
    bool moved = false;
    if (allow_projection && projects()) {
      const auto ps = std::chrono::steady_clock::now();
      const int it = model_.project(x, 1e-12);
      if (it >= 0) {
        moved = true;
        ++rep_.constraints.projections;
        rep_.constraints.projection_iterations += static_cast<std::uint64_t>(it);
      }
      rep_.constraints.stabilization_time_s +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - ps).count();
    }
    if (rep_.constrained) record_residuals(x);
    return moved;
  }

  bool has_events() const override { return model_.has_contacts(); }

  /// The first contact event in the step from (t_old, x_old) to (t, x)
  /// (detail::ContactEvents): the state moves there and the event is applied.
  bool handle_events(double t_old, const double* x_old, double& t, double* x,
                     const StepInterpolant& interp) override {
    if (!(t > t_old)) return false;
    const lagrangian::detail::ContactEvent e =
        events_.first(contacts_, t_old, x_old, t, x, interp, opt_.contact_touch_speed);
    if (e.kind == lagrangian::detail::ContactEvent::Kind::none) return false;
    events_.move_to(e.t, t_old, interp, t, x, model_.dim());
    events_.apply(contacts_, e, x, t, opt_, rep_);
    return true;
  }

 private:
  /// The constraint residuals at x into the report's maxima (at accepted
  /// steps and at samples).
  void record_residuals(const double* x) {
    auto& c = rep_.constraints;
    c.max_position_residual = std::max(c.max_position_residual, model_.position_residual(x));
    c.max_velocity_residual = std::max(c.max_velocity_residual, model_.velocity_residual(x));
  }

  /// Which components of P and L (about the origin) the scene conserves
  /// (integrate/detail/momentum_symmetry.hpp): from the accelerations at the start
  /// state x0 and four states perturbed from it, at times spread over the
  /// run, and from the impulse directions of the contacts with fixed planes
  /// and walls at the bodies' positions there (contacts between bodies are
  /// internal and conserve both).
  void probe_momentum_symmetry(const double* x0, double t0) {
    lagrangian::detail::MomentumSymmetry sym({0.0, 0.0, 0.0});
    using Source = lagrangian::detail::MomentumSymmetry::Source;
    const int dim = model_.dim();
    std::vector<double> dxdt(static_cast<std::size_t>(2 * dim));
    auto probe = [&](const double* x, double t) {
      bool evaluated = true;
      try {
        model_.rhs_uncounted(x, dxdt.data(), t);
      } catch (const lagrangian::Error&) {
        evaluated = false;  // a singular state among the probes: judged at the others
      }
      if (evaluated) {
        for (int i = 0; i < model_.bodies(); ++i)
          sym.add(model_.mass()[static_cast<std::size_t>(i)], x + 3 * i, dxdt.data() + dim + 3 * i);
        sym.end_probe(Source::force);
      }
      for (const Contact& c : model_.wall_contacts()) {
        const Vector3d point = at(x, c.a) - c.R * c.n;
        sym.add(1.0, point.data(), c.n.data());
        sym.end_probe(Source::contact);
      }
    };
    lagrangian::detail::for_each_probe_state(x0, 2 * dim, t0, opt_.t_end,
                                             lagrangian::detail::function_ref<void(const double*, double)>(probe));
    sym.write(rep_);
  }

  /// The fixed rows' multipliers and the constraint force Cᵀλ at a sample,
  /// from one evaluation of the right-hand side there (not counted among
  /// the run's evaluations).
  void multipliers_at(const double* x, double t) {
    model_.rhs_uncounted(x, scratch_.data(), t);
    lambda_ = model_.multipliers().head(model_.fixed_rows());
    forces_.noalias() = model_.constraint_jacobian().transpose() * model_.multipliers();
  }

  int rank(const double* x) const {
    Eigen::MatrixXd C;
    jacobian(model_.rows(), x, model_.dim(), C);
    return lagrangian::detail::numeric_rank(C);
  }

  mutable ParticleModel model_;
  const SimulationOptions& opt_;
  const ParticleOutput& output_;
  Eigen::VectorXd lambda_, forces_;  ///< at the last sample (empty without rows)
  const SampleTick& tick_;
  ParticleRun& out_;
  RunReport& rep_;
  std::vector<double> scratch_;
  std::vector<double> sample_x_;  // a sample projected onto the constraint rows (2 dim)
  lagrangian::detail::EnergyMonitor energy_;  ///< E = T + V (= h) against E₀, impacts' shifts applied
  ParticleContacts contacts_{model_, energy_};
  lagrangian::detail::ContactEvents events_;
  lagrangian::detail::PointMomenta momenta_{{0.0, 0.0, 0.0}};
};

}  // namespace

// The 64 right-hand sides (particle_model.hpp) are compiled here, once.
void particles::ParticleModel::select_rhs() {
  unsigned kinds = 0;
  if (gravity_) kinds |= 1u;
  if (newton_) kinds |= 2u;
  if (springs_) kinds |= 4u;
  if (linear_drag_) kinds |= 8u;
  if (quadratic_drag_) kinds |= 16u;
  static constexpr auto table = rhs_table(std::make_integer_sequence<unsigned, 64>{});
  rhs_fn_ = table[(kinds << 1) | (constrained_ ? 1u : 0u)];
}

std::vector<std::string> body_coordinates(const Scene& scene) {
  std::vector<std::string> names;
  for (const Body& b : scene.bodies)
    for (const char* axis : {".x", ".y", ".z"}) names.push_back(b.name + axis);
  return names;
}

std::vector<double> initial_state(const Scene& scene) {
  const std::size_t dim = 3 * scene.bodies.size();
  std::vector<double> x(2 * dim, 0.0);
  for (std::size_t i = 0; i < scene.bodies.size(); ++i)
    for (int k = 0; k < 3; ++k) {
      x[3 * i + static_cast<std::size_t>(k)] = scene.bodies[i].position[k];
      x[dim + 3 * i + static_cast<std::size_t>(k)] = scene.bodies[i].velocity[k];
    }
  return x;
}

ParticleRun run_particles(const Scene& scene, const ParticleOutput& output, const SampleTick& tick) {
  const MethodInfo& method = method_info(scene.run.method);
  // The variational and symplectic steppers work on a model's L or its separable form.
  if (method.needs_lagrangian || method.needs_separable)
    throw OptionError("run.method: '" + std::string(method.name) +
                      "' runs built-in models (model = ...) only; a scene of bodies runs with rk4, dopri5, "
                      "cash_karp54, fehlberg78, bulirsch_stoer, gauss_radau15 or rosenbrock4");
  const auto wall_start = std::chrono::steady_clock::now();
  const SimulationOptions& opt = scene.run;
  ParticleRun out;
  RunReport& rep = out.report;
  rep.model = scene.name;
  rep.coordinates = body_coordinates(scene);
  rep.method = method.name;
  rep.adaptive = method.adaptive;
  rep.rtol = opt.rtol;
  rep.atol = opt.atol;
  rep.dt = opt.dt;
  rep.t0 = opt.t0;
  rep.t_end = opt.t_end;
  ParticleSystem system(scene, opt, output, tick, out);
  std::vector<double> x = initial_state(scene);
  integrate(system, x, opt, rep);
  rep.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
  return out;
}

struct ComposedRhs::Impl {
  explicit Impl(const Scene& s) : model(s) {}
  ParticleModel model;
};
ComposedRhs::ComposedRhs(const Scene& scene) : impl_(std::make_unique<Impl>(scene)) {}
ComposedRhs::~ComposedRhs() = default;
int ComposedRhs::size() const { return 2 * impl_->model.dim(); }
void ComposedRhs::operator()(const double* x, double* dx, double t) { impl_->model.rhs(x, dx, t); }
std::uint64_t ComposedRhs::evaluations() const { return impl_->model.rhs_evaluations; }

}  // namespace lagrangian::scene::detail
