// The particle scenes' engine: a scene of bodies (particle_model.hpp) as a
// System for the one integration driver (integrate.hpp). This adapter has
// no loop or stepper of its own: it supplies the right-hand side, the
// monitors at samples, the projection of constraint rows, and the contacts
// — a broad phase (sweep and prune), their location on the driver's step
// interpolant and their resolution by Newton's law with the rules every
// system shares (detail/contact_rules.hpp: touching, closing, lift-off, the
// Zeno rule).

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <utility>

#include "lagrangian/detail/contact_rules.hpp"
#include "lagrangian/detail/energy_scale.hpp"
#include "lagrangian/detail/impact_cycle.hpp"
#include "lagrangian/detail/momentum_symmetry.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/constraints.hpp"
#include "lagrangian/integrate.hpp"
#include "lagrangian/system.hpp"
#include "particle_engine.hpp"
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

class ParticleSystem final : public lagrangian::System {
 public:
  ParticleSystem(const Scene& scene, const SimulationOptions& options, const ParticleOutput& output,
                 const SampleTick& tick, ParticleRun& out)
      : model_(scene), opt_(options), output_(output), tick_(tick), out_(out), rep_(out.report) {
    const auto size = static_cast<std::size_t>(2 * model_.dim());
    f0_.assign(size, 0.0);
    f1_.assign(size, 0.0);
    x_f_.assign(size, 0.0);
    buf_.assign(size, 0.0);
    scratch_.assign(size, 0.0);
    sample_x_.assign(size, 0.0);
    if (opt_.stabilization == Stabilization::baumgarte) model_.omega = opt_.baumgarte_omega;
  }

  int coordinate_count() const override { return model_.dim(); }
  void rhs(const double* x, double* dxdt, double t) const override { model_.rhs(x, dxdt, t); }

  void start(double* x, double t0) override {
    rep_.conservative = !model_.dissipative();
    rep_.has_total_energy = true;
    const double T0 = model_.kinetic(x), V0 = model_.potential(x);
    E0_ = T0 + V0;
    scale_ = lagrangian::detail::EnergyScale();
    scale_.meet(E0_);
    scale_.meet(T0, V0);
    drift_ = 0;
    rescale_drift();
    rep_.energy_initial = rep_.total_energy_initial = E0_;
    rep_.has_particles = true;
    probe_momentum_symmetry(x, t0);
    momentum(x, P0_, L0_);
    for (int k = 0; k < 3; ++k) {
      rep_.linear_momentum_initial[static_cast<std::size_t>(k)] = P0_[k];
      rep_.angular_momentum_initial[static_cast<std::size_t>(k)] = L0_[k];
    }
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
    if (model_.has_contacts()) resolve_at(x, t0, nullptr);  // contacts closing or resting at t0
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
    E_last_ = E;
    drift_ = std::max(drift_, std::abs(E - E0_ - shift_at(t)));
    scale_.meet(E);
    scale_.meet(T, V);
    rescale_drift();
    Vector3d P, L;
    momentum(x, P, L);
    rep_.linear_momentum_drift_final =
        lagrangian::detail::conserved_drift({P[0], P[1], P[2]}, {P0_[0], P0_[1], P0_[2]}, rep_.linear_momentum_conserved);
    rep_.angular_momentum_drift_final = lagrangian::detail::conserved_drift(
        {L[0], L[1], L[2]}, {L0_[0], L0_[1], L0_[2]}, rep_.angular_momentum_conserved);
    rep_.linear_momentum_drift_max = std::max(rep_.linear_momentum_drift_max, rep_.linear_momentum_drift_final);
    rep_.angular_momentum_drift_max = std::max(rep_.angular_momentum_drift_max, rep_.angular_momentum_drift_final);
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

  /// The energy scale, as for models (EnergyScale), and the drift so far
  /// divided by it.
  void rescale_drift() {
    rep_.energy_scale = scale_.value();
    rep_.energy_drift_max = rep_.total_energy_drift_max = drift_ / rep_.energy_scale;
  }

  void finish(double t, const double* x, bool sample_end) override {
    if (sample_end) sample(t, x);
    const double E = E_last_;  // the last sample is at the end: its energy, as the CSV's last row has it
    rep_.energy_final = rep_.total_energy_final = E;
    rep_.total_energy_is_h = true;  // particles in fixed surroundings: T is quadratic in the velocities
    rep_.energy_drift_final = rep_.total_energy_drift_final =
        std::abs(E - E0_ - shift_at(std::numeric_limits<double>::infinity())) / rep_.energy_scale;
    if (rep_.constrained) {
      rep_.constraints.final_position_residual = model_.position_residual(x);
      rep_.constraints.final_velocity_residual = model_.velocity_residual(x);
    }
    const int dim = model_.dim();
    out_.q_final.assign(x, x + dim);
    out_.qd_final.assign(x + dim, x + 2 * dim);
    out_.effect_evaluations = model_.counts();
    rep_.rhs_evaluations = model_.rhs_evaluations;  // every evaluation, the contacts' too
    out_.contact_locations = contact_locations_;
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

  /// The first event in the step from (t_old, x_old) to (t, x): a resting
  /// contact lifting off (its multiplier turning negative) or an open one
  /// closing. The state moves there and the event is applied.
  bool handle_events(double t_old, const double* x_old, double& t, double* x,
                     const StepInterpolant& interp) override {
    const int dim = model_.dim();
    const auto n2 = static_cast<std::size_t>(2 * dim);
    if (!(t > t_old)) return false;
    // f at both ends: accelerations for the broad phase, and at the end the
    // multipliers of the resting contacts. The end of the previous step is
    // reused when nothing has moved the state since.
    if (std::equal(x_old, x_old + n2, x_f_.begin())) {
      std::swap(f0_, f1_);
    } else {
      model_.rhs(x_old, f0_.data(), t_old);
    }
    model_.rhs(x, f1_.data(), t);
    std::copy(x, x + n2, x_f_.begin());

    double best_t = std::numeric_limits<double>::infinity();
    Contact* closing = nullptr;
    std::ptrdiff_t lift_off = -1;
    // Lift-off: a resting contact whose multiplier pulls at the step end.
    const auto& resting = model_.resting_contacts();
    std::vector<double>& lambda_end = lambda_end_;
    lambda_end.resize(resting.size());
    for (std::size_t k = 0; k < resting.size(); ++k) lambda_end[k] = model_.resting_multiplier(k);
    for (std::size_t k = 0; k < resting.size(); ++k) {
      if (!(lambda_end[k] < 0)) continue;
      auto lambda = [&](double ts) {
        if (ts == t) return lambda_end[k];
        interp(ts, buf_.data());
        model_.rhs(buf_.data(), scratch_.data(), ts);
        return model_.resting_multiplier(k);
      };
      const double tl = lagrangian::detail::locate_lift_off(t_old, t, lambda(t_old), lambda_end[k],
                                                            lagrangian::detail::time_function(lambda));
      if (tl < best_t) {
        best_t = tl;
        lift_off = static_cast<std::ptrdiff_t>(k);
      }
    }
    // Closing: the open contacts the broad phase keeps. Only the earliest
    // event of the step matters, so the contacts that cross zero (open at
    // the step's start, closed at its end) are located in the order of
    // their chord estimate, and one still open on the step path at the
    // earliest time found so far closes after it and is not located. Without
    // this every crossing in the step was located on the interpolant, and a
    // step of free flight can hold thousands (a gas against its walls: the
    // steps grow until they span the rest of the run, and each is cut at
    // the first wall impact).
    model_.candidates(x_old, x, f0_.data() + dim, f1_.data() + dim, t - t_old, cand_);
    const double touch = lagrangian::detail::contact_touch_tolerance(x, dim);
    path_.reset(t_old, t, x_old, x, dim);
    order_.clear();
    for (Contact* c : cand_) {
      const GapRate a{c->gap(x_old), c->rate(x_old, x_old + dim)};
      const GapRate b{c->gap(x), c->rate(x, x + dim)};
      if (a.gap > touch && b.gap > touch && a.rate < 0 && b.rate > 0 && open_throughout(*c, interp, a, b, touch))
        continue;  // passes by: a dip of the gap that stays above the touch tolerance
      if (a.gap > touch && b.gap > touch && !(a.rate < 0 && b.rate > 0)) continue;  // open throughout: no crossing
      const bool crossing = a.gap > touch && b.gap < 0;
      const double key = crossing ? t_old + (t - t_old) * (a.gap / (a.gap - b.gap)) : t_old;
      order_.push_back({key, crossing, c, a, b});
    }
    std::sort(order_.begin(), order_.end(), [](const Pending& p, const Pending& q) { return p.key < q.key; });
    for (const Pending& p : order_) {
      Contact* c = p.contact;
      if (p.crossing && best_t < t && open_on_path(*c, interp, best_t, touch)) continue;  // closes after best_t
      auto on_step = [&](double ts) {
        interp(ts, buf_.data());
        return GapRate{c->gap(buf_.data()), c->rate(buf_.data(), buf_.data() + dim)};
      };
      ++contact_locations_;
      const Closing found = lagrangian::detail::locate_closing(t_old, t, p.a, p.b, touch, opt_.contact_touch_speed,
                                                               lagrangian::detail::gap_function(on_step));
      if (found.kind == Closing::Kind::penetrated) lagrangian::detail::throw_penetrated(c->name, t_old, p.a.gap);
      if (found.kind != Closing::Kind::none && found.t < best_t) {
        best_t = found.t;
        closing = c;
        lift_off = -1;
      }
    }
    if (!closing && lift_off < 0) return false;
    progress_.check(best_t, t_old);
    if (best_t < t) {
      interp(best_t, buf_.data());
      std::copy(buf_.begin(), buf_.end(), x);
      t = best_t;
    }
    if (closing) {
      resolve_at(x, t, closing);
    } else {
      const std::string name = resting[static_cast<std::size_t>(lift_off)]->name;
      model_.release(static_cast<std::size_t>(lift_off));
      log_event(t, EventKind::release, name, 0, 0, 0);
    }
    return true;
  }

 private:
  /// True when the gap of contact c, which falls at the step's start (a)
  /// and rises at its end (b), stays above `touch` throughout the step: its
  /// minimum, where φ̇ = 0, on the step path. The path reproduces the
  /// interpolant to rounding (~1e-16 of the coordinates), far below the
  /// touch tolerance, so a contact kept here cannot close.
  bool open_throughout(const Contact& c, const StepInterpolant& interp, GapRate a, GapRate b, double touch) {
    path_.prepare(interp);
    auto on_path = [&](double ts) {
      Vector3d ra, va, rb = Vector3d::Zero(), vb = Vector3d::Zero();
      path_.body(c.a, ts, ra, va);
      if (c.pair) path_.body(c.b, ts, rb, vb);
      return c.gap_rate(ra, va, rb, vb);
    };
    const double tm =
        lagrangian::detail::stationary_time(path_.t0(), path_.t1(), a, b, lagrangian::detail::gap_function(on_path));
    return on_path(tm).gap > touch;
  }

  /// True when contact c is open beyond `touch` at time ts of the step, on
  /// the step path (which reproduces the interpolant to rounding, far below
  /// the touch tolerance).
  bool open_on_path(const Contact& c, const StepInterpolant& interp, double ts, double touch) {
    path_.prepare(interp);
    Vector3d ra, va, rb = Vector3d::Zero(), vb = Vector3d::Zero();
    path_.body(c.a, ts, ra, va);
    if (c.pair) path_.body(c.b, ts, rb, vb);
    return c.gap_rate(ra, va, rb, vb).gap > touch;
  }

  /// The constraint residuals at x into the report's maxima (at accepted
  /// steps and at samples).
  void record_residuals(const double* x) {
    auto& c = rep_.constraints;
    c.max_position_residual = std::max(c.max_position_residual, model_.position_residual(x));
    c.max_velocity_residual = std::max(c.max_velocity_residual, model_.velocity_residual(x));
  }

  /// Which components of P and L (about the origin) the scene conserves
  /// (detail/momentum_symmetry.hpp): from the accelerations at the start
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

  void momentum(const double* x, Vector3d& P, Vector3d& L) const {
    P.setZero();
    L.setZero();
    for (int i = 0; i < model_.bodies(); ++i) {
      const Vector3d p = model_.mass()[static_cast<std::size_t>(i)] * at(x + model_.dim(), i);
      P += p;
      L += at(x, i).cross(p);
    }
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

  /// The energy the impacts up to time t have removed (J): samples taken
  /// before an impact, from the step that was cut at it, must not count it.
  double shift_at(double t) {
    while (!pending_.empty() && pending_.front().first <= t) {
      shift_ += pending_.front().second;
      pending_.erase(pending_.begin());
    }
    return shift_;
  }

  void log_event(double t, EventKind kind, const std::string& name, double J, double u_in, double u_out,
                 double T_before = 0, double T_after = 0) {
    if (!std::isfinite(J) || !std::isfinite(T_before) || !std::isfinite(T_after)) {
      std::ostringstream os;
      os.precision(17);
      os << "impact " << name << " at t = " << t << " gave a non-finite impulse or energy (J = " << J
         << " N s, kinetic energy " << T_before << " -> " << T_after
         << " J): its values overflow double precision, so the run was stopped";
      throw SimulationError(os.str(), t);
    }
    EventRecord e;
    e.t = t;
    e.kind = kind;
    e.name = name;
    e.impulse = J;
    e.approach_speed = u_in;
    e.separation_speed = u_out;
    e.kinetic_energy_before = T_before;
    e.kinetic_energy_after = T_after;
    rep_.events.push_back(std::move(e));
    if (kind == EventKind::impact) ++rep_.impacts;
  }

  /// Resolves every contact that is touching and approaching at t, fastest
  /// first, until none approaches (sequential pairwise impacts; each
  /// conserves momentum, and kinetic energy when e = 1), with the Zeno rule
  /// deciding which impacts end an accumulation. Afterwards a contact that
  /// took part (at t0: every touching one) and does not separate rests when
  /// its last impact was plastic (e = 0) or the forces press it shut, and
  /// resting contacts that separate lift off; the log records these changes
  /// (none at t0).
  /// `located` is the contact found closing; nullptr at t0.
  void resolve_at(double* x, double t, Contact* located) {
    const bool at_start = located == nullptr;
    const int dim = model_.dim();
    const double tol = lagrangian::detail::contact_touch_tolerance(x, dim);
    const double touch_speed = opt_.contact_touch_speed;
    const std::vector<Contact*> resting_before = model_.resting_contacts();
    model_.near_contacts(x, tol, near_);
    if (located && std::find(near_.begin(), near_.end(), located) == near_.end()) near_.push_back(located);
    auto contains = [](const std::vector<Contact*>& v, const Contact* c) {
      return std::find(v.begin(), v.end(), c) != v.end();
    };
    std::vector<Contact*> involved;
    if (at_start) involved = near_;
    if (located) involved.push_back(located);
    std::vector<Contact*> rested;   // by the Zeno rule, logged as such
    std::vector<Contact*> plastic;  // their last impact had e = 0: the bodies stick
    double impact_energy = 0;
    lagrangian::detail::ImpactCycle cycle;  // the impacts since the last cycle replaced by its limit
    for (int it = 0;; ++it) {
      if (it > 1000 * static_cast<int>(near_.size() + 1)) {
        std::ostringstream os;
        os.precision(17);
        os << "simultaneous impacts at t = " << t << " did not settle after " << it << " pairwise impacts";
        throw SimulationError(os.str(), t);
      }
      Contact* fastest = nullptr;
      double u_max = touch_speed;
      for (Contact* c : near_) {
        if (c->resting) continue;
        const double u = -c->rate(x, x + dim);
        if (u > u_max) {
          u_max = u;
          fastest = c;
        }
      }
      if (!fastest) break;
      Contact& c = *fastest;
      const double T_before = model_.kinetic(x);
      const auto pressed = [&] { return model_.pressed(x, c); };
      const bool zeno = lagrangian::detail::zeno_accumulation(c.history, u_max, t, opt_,
                                                              lagrangian::detail::predicate(pressed));
      const double e = zeno ? 0.0 : c.e;
      const double J = model_.impulse(x, c, e);
      const double T_after = model_.kinetic(x);
      impact_energy += T_after - T_before;
      rep_.impact_energy_loss += T_before - T_after;
      const double cutoff = zeno ? lagrangian::detail::zeno_cutoff(c.history, t, c.e) : std::nan("");
      c.history.record(u_max, t);
      const double u_out = c.rate(x, x + dim);
      log_event(t, zeno ? EventKind::rest : EventKind::impact, c.name, J, u_max, u_out, T_before, T_after);
      rep_.events.back().zeno_cutoff = cutoff;
      involved.push_back(&c);
      if (e == 0.0) plastic.push_back(&c);
      if (zeno) {
        model_.make_resting(c);
        rested.push_back(&c);
      }
      model_.wake_approaching(x, touch_speed, near_);
      // Impacts that cycle (a light sphere pinned between heavy ones and
      // walls) are replaced by their limit, as for models
      // (detail/impact_cycle.hpp).
      cycle.record(static_cast<int>(std::find(near_.begin(), near_.end(), &c) - near_.begin()), e);
      const auto round = cycle.due_round(static_cast<int>(near_.size()));
      if (!round.empty() && settle_cycle(x, t, round, impact_energy)) {
        for (const auto& imp : round) involved.push_back(near_[static_cast<std::size_t>(imp.contact)]);
        cycle.settled();
      }
    }
    // Contacts that took part and do not separate rest when their last
    // impact was plastic or the forces press them shut.
    for (Contact* c : involved)
      if (!c->resting && c->gap(x) <= tol && c->rate(x, x + dim) <= touch_speed &&
          (contains(plastic, c) || model_.pressed(x, *c)))
        model_.make_resting(*c);
    // Resting contacts that separate lift off.
    for (std::size_t k = model_.resting_contacts().size(); k-- > 0;)
      if (model_.resting_contacts()[k]->rate(x, x + dim) > touch_speed) model_.release(k);
    // The log: what changed.
    if (!at_start) {
      std::vector<Contact*> seen;
      for (Contact* c : involved) {
        if (contains(seen, c)) continue;
        seen.push_back(c);
        const bool was = contains(resting_before, c);
        if (c->resting && !was && !contains(rested, c))
          log_event(t, EventKind::rest, c->name, 0, 0, 0, model_.kinetic(x), model_.kinetic(x));
      }
      for (Contact* c : resting_before)
        if (!c->resting) log_event(t, EventKind::release, c->name, 0, 0, 0);
    }
    if (impact_energy != 0) pending_.emplace_back(t, impact_energy);
  }

  /// The limit of impacts that cycle among the contacts near_[k] of `round`
  /// (detail/impact_cycle.hpp), as ModelSystem::settle_cycle: the
  /// velocities in x jump to it when the rounds converge, the contacts left
  /// approaching by rounding are closed together (close_together), and each
  /// contact of the round gets one impact in the log with its share of the
  /// total impulse. Returns false (x unchanged) when the rounds do not settle.
  bool settle_cycle(double* x, double t, const std::vector<lagrangian::detail::ImpactCycle::Impact>& round,
                    double& impact_energy) {
    const int dim = model_.dim();
    std::vector<double> trial(x, x + 2 * dim), limit(static_cast<std::size_t>(dim));
    auto apply_round = [&](const double* in, double* out) {
      std::copy(in, in + dim, trial.begin() + dim);
      for (const auto& imp : round) model_.impulse(trial.data(), *near_[static_cast<std::size_t>(imp.contact)], imp.e);
      std::copy(trial.begin() + dim, trial.end(), out);
    };
    if (!lagrangian::detail::round_limit(dim, x + dim, lagrangian::detail::round_map(apply_round), limit.data()))
      return false;
    std::vector<Contact*> contacts;
    for (const auto& imp : round) {
      Contact* c = near_[static_cast<std::size_t>(imp.contact)];
      if (std::find(contacts.begin(), contacts.end(), c) == contacts.end()) contacts.push_back(c);
    }
    double speed = 0;
    for (int i = 0; i < dim; ++i) speed = std::max(speed, std::abs(x[dim + i]));
    // Contacts of the round left approaching by rounding: closed together.
    auto rate = [&](int k, const double* v) {
      std::copy(v, v + dim, trial.begin() + dim);
      return contacts[static_cast<std::size_t>(k)]->rate(trial.data(), trial.data() + dim);
    };
    auto plastic = [&](int k, double* v) {
      std::copy(v, v + dim, trial.begin() + dim);
      model_.impulse(trial.data(), *contacts[static_cast<std::size_t>(k)], 0.0);
      std::copy(trial.begin() + dim, trial.end(), v);
    };
    if (!lagrangian::detail::close_together(dim, limit.data(), static_cast<int>(contacts.size()), speed,
                                            lagrangian::detail::function_ref<double(int, const double*)>(rate),
                                            lagrangian::detail::function_ref<void(int, double*)>(plastic)))
      return false;
    std::copy(limit.begin(), limit.end(), trial.begin() + dim);
    // Each contact's impulse: Σ_k J_k n_k (on both bodies of a pair) = M Δv.
    Eigen::MatrixXd N = Eigen::MatrixXd::Zero(dim, static_cast<Eigen::Index>(contacts.size()));
    Eigen::VectorXd dp(dim);
    for (int i = 0; i < dim; ++i) dp[i] = model_.mass()[static_cast<std::size_t>(i / 3)] * (trial[dim + i] - x[dim + i]);
    for (std::size_t k = 0; k < contacts.size(); ++k) {
      const Contact& c = *contacts[k];
      const Vector3d nrm = c.normal(x);
      N.block<3, 1>(3 * c.a, static_cast<Eigen::Index>(k)) = nrm;
      if (c.pair) N.block<3, 1>(3 * c.b, static_cast<Eigen::Index>(k)) = -nrm;
    }
    const Eigen::VectorXd J = N.completeOrthogonalDecomposition().solve(dp);
    std::vector<double> approach(contacts.size());
    for (std::size_t k = 0; k < contacts.size(); ++k) approach[k] = -contacts[k]->rate(x, x + dim);
    const double T_before = model_.kinetic(x);
    std::copy(trial.begin() + dim, trial.end(), x + dim);
    const double T_after = model_.kinetic(x);
    for (std::size_t k = 0; k < contacts.size(); ++k)
      log_event(t, EventKind::impact, contacts[k]->name, J[static_cast<Eigen::Index>(k)], approach[k],
                contacts[k]->rate(x, x + dim), T_before, T_after);
    impact_energy += T_after - T_before;
    rep_.impact_energy_loss += T_before - T_after;
    model_.wake_approaching(x, opt_.contact_touch_speed, near_);
    return true;
  }

  mutable ParticleModel model_;
  const SimulationOptions& opt_;
  const ParticleOutput& output_;
  Eigen::VectorXd lambda_, forces_;  ///< at the last sample (empty without rows)
  const SampleTick& tick_;
  ParticleRun& out_;
  RunReport& rep_;
  std::vector<double> f0_, f1_, x_f_, buf_, scratch_;
  std::vector<double> sample_x_;  // a sample projected onto the constraint rows (2 dim)
  std::vector<double> lambda_end_;  ///< multipliers of the resting contacts at a step's end
  std::vector<Contact*> cand_, near_;
  /// A candidate contact to locate in a step: `key` orders them (the chord
  /// estimate of a crossing; the step's start for the others).
  struct Pending {
    double key;
    bool crossing;
    Contact* contact;
    GapRate a, b;
  };
  std::vector<Pending> order_;
  std::uint64_t contact_locations_ = 0;  ///< contacts located on a step's interpolant (root searches)
  StepPath path_;
  lagrangian::detail::EventProgress progress_;
  double E_last_ = 0;  ///< E at the last sample (J)
  double E0_ = 0, shift_ = 0;
  double drift_ = 0;  // J: max |E − E0 − shifts| so far (rescale_drift)
  lagrangian::detail::EnergyScale scale_;
  std::vector<std::pair<double, double>> pending_;  ///< (time, ΔT) of impacts not yet sampled past
  Vector3d P0_ = Vector3d::Zero(), L0_ = Vector3d::Zero();
};

}  // namespace

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
  for (const auto& b : scene.bodies)
    for (const char* ax : {".x", ".y", ".z"}) rep.coordinates.push_back(b.name + ax);
  rep.method = method.name;
  rep.adaptive = method.adaptive;
  rep.rtol = opt.rtol;
  rep.atol = opt.atol;
  rep.dt = opt.dt;
  rep.t0 = opt.t0;
  rep.t_end = opt.t_end;
  ParticleSystem system(scene, opt, output, tick, out);
  const int dim = system.coordinate_count();
  std::vector<double> x(static_cast<std::size_t>(2 * dim), 0.0);
  for (int i = 0; i < dim / 3; ++i)
    for (int k = 0; k < 3; ++k) {
      x[static_cast<std::size_t>(3 * i + k)] = scene.bodies[static_cast<std::size_t>(i)].position[k];
      x[static_cast<std::size_t>(dim + 3 * i + k)] = scene.bodies[static_cast<std::size_t>(i)].velocity[k];
    }
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
