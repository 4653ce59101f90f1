#pragma once
// ModelSystem: a Model as the System the driver runs (system.hpp), the only
// per-model part of simulate(): the right-hand side, the monitors reported
// at samples, constraint stabilisation, and the model's contacts and events.
// Its constraint and event members are defined in run_constraints.hpp and
// run_events.hpp.

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <optional>
#include <type_traits>
#include <vector>

#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/mechanics/detail/constant_mass.hpp"
#include "lagrangian/integrate/detail/energy_monitor.hpp"
#include "lagrangian/mechanics/detail/singular_values.hpp"
#include "lagrangian/integrate/detail/contact_rules.hpp"
#include "lagrangian/integrate/detail/contacts.hpp"
#include "lagrangian/integrate/detail/momentum_symmetry.hpp"
#include "lagrangian/integrate/detail/observer_ref.hpp"
#include "lagrangian/mechanics/detail/point_momenta.hpp"
#include "lagrangian/integrate/detail/point_momenta_monitor.hpp"
#include "lagrangian/integrate/detail/roots.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/impact.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/mechanics/properties.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/integrate/system.hpp"
#include "lagrangian/integrate/variational.hpp"

namespace lagrangian::detail {

/// Storage of the first-order state x = [q; q̇]: a fixed array, or a vector
/// for run-time sized models.
template <int N>
struct state_buffer {
  using type = std::array<double, 2 * N>;
};
template <>
struct state_buffer<Dynamic> {
  using type = std::vector<double>;
};
template <int N>
using StateBuffer = typename state_buffer<N>::type;

template <int N>
StateBuffer<N> make_buffer(int n) {
  if constexpr (N == Dynamic) {
    return StateBuffer<N>(static_cast<std::size_t>(2 * n), 0.0);
  } else {
    (void)n;
    return StateBuffer<N>{};
  }
}

/// h = p·q̇ − L, with p returned too.
template <class M>
double energy_and_momenta(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                          const Vec<double, coordinate_count_v<M>>& qd, double t,
                          Vec<double, coordinate_count_v<M>>& p) {
  p = momenta(model, q, qd, t);
  return p.dot(qd) - lagrangian_value(model, q, qd, t);
}

/// Splits x = [q; q̇] (2n values) into q and q̇.
template <int N>
void split_state(const double* x, Vec<double, N>& q, Vec<double, N>& qd) {
  const auto n = q.size();
  for (Eigen::Index i = 0; i < n; ++i) {
    q[i] = x[i];
    qd[i] = x[n + i];
  }
}

/// A compile-time size, or 0 for Dynamic.
constexpr int fixed_or_none(int size) { return size == Dynamic ? 0 : size; }

/// Per-run state of a constrained model's right-hand side.
template <class M>
struct ConstraintContext {
  /// Sized by the model's compile-time counts (none when run-time ones).
  ConstraintContext()
      : ConstraintContext(fixed_or_none(coordinate_count_v<M>), fixed_or_none(position_rows_v<M>),
                          fixed_or_none(constraint_count_v<M>)) {}
  explicit ConstraintContext(const M& model)
      : ConstraintContext(model_size(model), position_rows(model), constraint_count(model)) {}
  ConstraintContext(int n, int position_rows, int rows)
      : cw(n, rows), positions(position_rows, n), velocities(rows, rows), conditioning(rows, n) {}
  ConstraintWorkspace<coordinate_count_v<M>, constraint_count_v<M>> cw;
  /// Workspaces of the projections and of the conditioning monitor after each step.
  MinNormSolver positions;
  MinNormSolver velocities;
  SingularValues conditioning;
  double omega = 0;               ///< Baumgarte rate (1/s), 0 when not stabilising that way
  ActiveSet active = all_active;  ///< unilateral constraints in contact
};


/// A Model as a System: x = [q; q̇], ẋ = [q̇; q̈(q, q̇, t)] with q̈ from
/// accelerations() (or the model's own, or constrained_accelerations() with
/// its constraints), and at every sample the energy function
/// h = p·q̇ − L, the total energy T + V when the model has both, the momenta
/// of its cyclic coordinates, constraint residuals, particle momenta and
/// the model's reference solution, into the run's report and observer.
template <class M>
class ModelSystem final : public System {
 public:
  static constexpr int n = coordinate_count_v<M>;
  /// The model declares contacts or watched events (the event code is compiled only then).
  static constexpr bool has_events_v = unilateral_count_v<M> != 0 || event_count_v<M> > 0;
  using Observer = ObserverRef<n>;
  /// q̈ of the free motion from constant_mass_matrix: declared, no hand-coded
  /// accelerations, and no constraints other than contacts.
  static constexpr bool uses_constant_mass = constant_mass_matrix_v<M> && !has_explicit_accelerations_v<M> &&
                                             add_rows(holonomic_count_v<M>, pfaffian_count_v<M>) == 0;

  ModelSystem(const M& model, const SimulationOptions& opt, Observer obs, RunReport& report)
      : model_(model), opt_(opt), obs_(obs), report_(report), size_(model_size(model)) {
    if constexpr (has_constraints_v<M>) {
      if (lagrangian::has_constraints(model)) {
        if constexpr (runtime_constraint_counts_v<M>) {  // (fixed counts: sized already)
          context_ = ConstraintContext<M>(model);
          cw_ = constraint_workspace(model);
        }
        context_.omega = opt.stabilization == Stabilization::baumgarte ? opt.baumgarte_omega : 0.0;
        ctx_ = &context_;
      }
    }
  }
  ModelSystem(const ModelSystem&) = delete;
  ModelSystem& operator=(const ModelSystem&) = delete;

  int coordinate_count() const override { return size_; }

  /// Before the run, at its initial state: checks a constant_mass_matrix
  /// declaration and factors M (DynamicsError when it does not hold).
  void prepare(const State<n>& x0, double t0) {
    if constexpr (uses_constant_mass) constant_mass_.prepare(model_, rhs_ws_, x0.q, x0.qd, t0);
  }

  void rhs(const double* x, double* dxdt, double t) const override {
    if constexpr (n == Dynamic) {
      split_state(x, rhs_ws_.scratch_q, rhs_ws_.scratch_qd);
      accelerations_into(rhs_ws_.scratch_q, rhs_ws_.scratch_qd, t, rhs_ws_.scratch_qdd);
      for (int i = 0; i < size_; ++i) {
        dxdt[i] = x[size_ + i];
        dxdt[size_ + i] = rhs_ws_.scratch_qdd[i];
      }
    } else {
      Vec<double, n> q, qd, qdd;
      split_state(x, q, qd);
      accelerations_into(q, qd, t, qdd);
      for (int i = 0; i < n; ++i) {
        dxdt[i] = qd[i];
        dxdt[n + i] = qdd[i];
      }
    }
  }

  /// Sets up the monitors. Contacts that touch and approach at t0 are
  /// resolved first (impacts at t0), which may change x.
  void start(double* x, double t0) override {
    State<n> x0(size_);
    split_state(x, x0.q, x0.qd);
    Columns columns{coordinate_names(model_), {}, has_kinetic_potential_v<M>, coordinate_units(model_), {}};
    if constexpr (has_constraints_v<M>) {
      if (ctx_) start_constraints(x0, columns);
    }
    if constexpr (event_count_v<M> > 0) specs_ = event_specs(model_);
    if constexpr (has_particles_v<M>) {
      int k = 0;
      for (const Particle& part : model_.particles()) {
        if (!(part.mass > 0) || !std::isfinite(part.mass))
          throw ParameterError(model_name(model_) + ": particle " + std::to_string(k) + " has mass " +
                               std::to_string(part.mass) + "; it must be positive and finite");
        for (int i : part.axes)
          if (i < -1 || i >= size_)
            throw ParameterError(model_name(model_) + ": particle " + std::to_string(k) + " names coordinate " +
                                 std::to_string(i) + ", outside [0, " + std::to_string(size_) + ")");
        ++k;
      }
    }
    if constexpr (has_events_v) event_buf_.assign(static_cast<std::size_t>(2 * size_), 0.0);
    const std::vector<int> cyclic = cyclic_coordinates(model_, x0, t0);
    cyclic_.assign(cyclic.begin(), cyclic.end());
    if constexpr (has_point_masses_v<M>) {
      has_points_ = point_mass_count(model_) > 0;
      if (has_points_) probe_momentum_symmetry(x0, t0);
    }
    Vec<double, n> p(size_);
    const double h0 = energy_and_momenta(model_, x0.q, x0.qd, t0, p);  // after any impact at t0
    if constexpr (has_kinetic_potential_v<M>)
      energy_.start(report_, h0, model_.kinetic(x0.q, x0.qd, t0), model_.potential(x0.q, t0));
    else
      energy_.start(report_, h0);
    for (int i : cyclic_) report_.conserved_momenta.push_back({columns.coordinates[static_cast<std::size_t>(i)], p[i], 0, 0});
    if (obs_.begin) obs_.begin(obs_.object, columns);
    for (int i = 0; i < size_; ++i) {
      x[i] = x0.q[i];
      x[size_ + i] = x0.qd[i];
    }
  }

  void sample(double t, const double* x) override {
    Sample<n> s;
    s.t = t;
    s.q.resize(size_);
    s.qd.resize(size_);
    split_state(x, s.q, s.qd);
    if constexpr (has_constraints_v<M>) {
      if (ctx_) project_sample(s);
    }
    Vec<double, n> p(size_);
    s.energy = energy_and_momenta(model_, s.q, s.qd, t, p);
    if (!std::isfinite(s.energy)) throw_non_finite_energy(t, s.energy, x, size_);
    if constexpr (has_kinetic_potential_v<M>) {
      const double kinetic = model_.kinetic(s.q, s.qd, t), potential = model_.potential(s.q, t);
      s.total_energy = kinetic + potential;
      energy_.sample(report_, t, s.energy, kinetic, potential);
    } else {
      energy_.sample(report_, t, s.energy);
    }
    if constexpr (has_constraints_v<M>) {
      if (ctx_) sample_constraints(s);
    }
    if constexpr (has_point_masses_v<M>) {
      if (has_points_) sample_particles(s);
    }
    if constexpr (has_reference_v<M>) {
      if (s.t == opt_.t0) {
        reference_initial_.q = s.q;
        reference_initial_.qd = s.qd;
      }
      const State<n> ref = model_.reference(reference_initial_, s.t - opt_.t0);
      report_.has_reference = true;
      report_.reference_error_final = (s.q - ref.q).template lpNorm<Eigen::Infinity>();
      report_.reference_error_max = std::max(report_.reference_error_max, report_.reference_error_final);
    }
    for (std::size_t k = 0; k < cyclic_.size(); ++k) {
      MomentumDrift& d = report_.conserved_momenta[k];
      d.final_abs_drift = std::abs(p[cyclic_[k]] - d.initial);
      d.max_abs_drift = std::max(d.max_abs_drift, d.final_abs_drift);
      d.rate_max = std::max(d.rate_max, std::abs(s.qd[cyclic_[k]]));
    }
    report_.coordinate_scale = std::max(report_.coordinate_scale, s.q.template lpNorm<Eigen::Infinity>());
    obs_(s);
  }

  void finish(double t, const double* x, bool sample_end) override {
    if (sample_end) sample(t, x);
    energy_.finish(report_, t);
  }

  bool has_constraints() const override { return ctx_ != nullptr; }
  /// Constrained models: projection (when chosen) and residual monitoring
  /// after an accepted step ending at t with state x; true when x changed.
  bool stabilize(double* x, double t, bool allow_projection) override;
  void extra_rhs_evaluation() override {
    if (ctx_) ++report_.constraints.extra_rhs_evaluations;
  }

  bool has_events() const override {
    if constexpr (unilateral_count_v<M> == Dynamic) {
      return event_count_v<M> > 0 || (ctx_ && unilateral_count(model_) > 0);  // contacts counted at run time
    } else {
      return has_events_v;
    }
  }
  /// Events in the step just taken from (t_old, x_old) to (t, x): lift-off
  /// of resting contacts (their multiplier turns negative), contacts closing
  /// (the gap φ falls through zero, or dips below zero and back inside the
  /// step), and watched event functions crossing zero in their direction.
  /// Each crossing is located with Boost.Math's TOMS 748 on the step's
  /// continuous extension `interp` (dopri5's dense output, or a Fehlberg 7(8)
  /// sub-step from the step's start), the bracket narrowed to
  /// event_time_tolerance · max(1 s, |t|). The earliest event is applied:
  /// the step end moves to it (t and x are overwritten) and true is
  /// returned, so the caller restarts its stepper there; later events in
  /// the step are found by the following steps, so events are handled in
  /// time order. Truly simultaneous contacts are resolved together by
  /// resolve_contacts().
  bool handle_events(double t_old, const double* x_old, double& t, double* x,
                     const StepInterpolant& interp) override {
    if constexpr (!has_events_v) {
      (void)t_old, (void)x_old, (void)t, (void)x, (void)interp;
      return false;
    } else {
      return locate_events(t_old, x_old, t, x, interp);
    }
  }
  bool stopped() const override { return stopped_; }

  /// The explicit methods compiled here with rhs() inlined, for models
  /// wrapped in lagrangian::Inlined (inlined.hpp).
  bool integrate_inlined(Run& run, std::vector<double>& x) override {
    if constexpr (inline_rhs_v<M>) {
      M::run_explicit(run, *this, model_, x);
      return true;
    } else {
      (void)run, (void)x;
      return false;
    }
  }

  /// The variational integrator (variational.hpp), for models that opted in
  /// to the structure-preserving methods; built at the first step from x.
  void variational_step(double t, double h, double* x) override {
    if constexpr (structure_preserving_v<M> && variational_supported_v<M>) {
      if (!variational_) {
        State<n> s;
        split_state(x, s.q, s.qd);
        variational_.emplace(model_, s, t, discrete_rule_from_string(opt_.discrete_rule),
                             NewtonSettings{opt_.newton_tolerance, opt_.newton_max_iterations});
      }
      VariationalIntegrator<M>& vi = *variational_;
      try {
        vi.step(h);
      } catch (...) {
        count_variational_work();
        throw;
      }
      count_variational_work();
      for (int i = 0; i < n; ++i) {
        x[i] = vi.q()[i];
        x[n + i] = vi.qd()[i];
      }
    } else {
      System::variational_step(t, h, x);
    }
  }

 private:
  void accelerations_into(const Vec<double, n>& q, const Vec<double, n>& qd, double t, Vec<double, n>& qdd) const {
    if constexpr (has_constraints_v<M>) {
      if (ctx_) {
        if constexpr (uses_constant_mass) {
          if (!ctx_->active.any(unilateral_count(model_))) {  // contacts only, none touching: free motion
            constant_mass_(model_, rhs_ws_, q, qd, t, qdd);
            ctx_->cw.multipliers.setZero();
            ctx_->cw.constraint_forces.setZero();
            return;
          }
        }
        constrained_accelerations(model_, rhs_ws_, ctx_->cw, q, qd, t, qdd, ctx_->omega, ctx_->active);
        return;
      }
    }
    // A model whose constraints are counted at run time may have none.
    if constexpr (!has_constraints_v<M> || runtime_constraint_counts_v<M>) {
      if constexpr (has_explicit_accelerations_v<M>) {
        model_.accelerations(q, qd, t, qdd);
      } else if constexpr (uses_constant_mass) {
        constant_mass_(model_, rhs_ws_, q, qd, t, qdd);
      } else {
        free_accelerations(model_, rhs_ws_, q, qd, t, qdd);
      }
    }
  }
  void count_variational_work() {
    if constexpr (structure_preserving_v<M> && variational_supported_v<M>) {
      report_.newton_iterations = variational_->newton_iterations();
      report_.rhs_evaluations = variational_->lagrangian_evaluations();
    }
  }
  const ActiveSet& active() const { return ctx_ ? ctx_->active : all_active; }
  // Instantiated only for models with events (called from handle_events).
  bool locate_events(double t_old, const double* x_old, double& t, double* x, const StepInterpolant& interp);
  /// The model's contacts as the contact rules see them (run_events.hpp).
  class Contacts;
  /// Resolves the impacts at (x, t) by detail::resolve_contacts: `trigger`
  /// is the contact found closing.
  void resolve_contacts(double* x, double t, int trigger);
  /// Tracks σ_r/σ_1 of the bilateral constraint Jacobian (r = rank at t0)
  /// at accepted steps and samples, and warns once when it falls below
  /// 1e-3: a singular configuration is near (the multipliers grow without
  /// bound there, and the motion may switch assembly branches).
  template <class CS>
  void monitor_conditioning(CS cs, double t);

  /// P = Σ m v and L = Σ m (r − r₀) × v of the point masses at a sample.
  void sample_particles(const Sample<n>& s) {
    point_motions(model_, s.q.data(), s.qd.data(), nullptr, s.t, 1.0, points_);
    momenta_.clear();
    for (const PointMotion& pm : points_) momenta_.add(pm.mass, pm.r.data(), pm.v.data());
    momenta_.record(report_);
  }

  /// ∂φ/∂q of every contact at (q, t): column i is φ̇ along q̇ = e_i less
  /// ∂φ/∂t (one first-order AD pass each).
  Eigen::Matrix<double, unilateral_count_v<M>, n> contact_jacobian(const Vec<double, n>& q, double t) const {
    constexpr int u = unilateral_count_v<M>;
    const int count = unilateral_count(model_);
    Eigen::Matrix<double, u, n> G(count, size_);
    Vec<double, n> dir = Vec<double, n>::Zero(size_);
    Vec<double, u> gap(count), rate0(count), rate(count);
    contact_gaps(model_, q, dir, t, gap, rate0);
    for (int i = 0; i < size_; ++i) {
      dir[i] = 1;
      contact_gaps(model_, q, dir, t, gap, rate);
      dir[i] = 0;
      G.col(i) = rate - rate0;
    }
    return G;
  }

  /// Which components of P and L the particle system's symmetries conserve
  /// (integrate/detail/momentum_symmetry.hpp), judged from q̈ and the contacts'
  /// impulse directions at the start state x0 and four states perturbed from
  /// it, at times spread over the run. (The momenta of cyclic coordinates
  /// need no such test: cyclic_coordinates() leaves out those a constraint
  /// or contact touches.)
  void probe_momentum_symmetry(const State<n>& x0, double t0) {
    MomentumSymmetry sym(opt_.angular_momentum_point);
    std::vector<double> start(static_cast<std::size_t>(2 * size_)), dxdt(start.size());
    for (int i = 0; i < size_; ++i) {
      start[static_cast<std::size_t>(i)] = x0.q[i];
      start[static_cast<std::size_t>(size_ + i)] = x0.qd[i];
    }
    auto probe = [&](const double* x, double t) {
      Vec<double, n> q(size_), qd(size_);
      for (int i = 0; i < size_; ++i) {
        q[i] = x[i];
        qd[i] = x[size_ + i];
      }
      // Each point at q with its acceleration (weighted by its mass) or,
      // for a contact, the velocity change its impulse gives.
      auto add_points = [&](bool weighted, bool acceleration) {
        for (const PointMotion& pm : points_)
          sym.add(weighted ? pm.mass : 1.0, pm.r.data(), acceleration ? pm.a.data() : pm.v.data());
      };
      bool evaluated = true;
      try {
        rhs(x, dxdt.data(), t);
      } catch (const Error&) {
        evaluated = false;  // a singular state among the probes: judged at the others
      }
      if (evaluated) {
        point_motions(model_, q.data(), qd.data(), dxdt.data() + size_, t, 1.0, points_);
        add_points(true, true);
        sym.end_probe(MomentumSymmetry::Source::force);
      }
      if constexpr (unilateral_count_v<M> != 0) {
        const auto G = contact_jacobian(q, t);
        for (int j = 0; j < unilateral_count(model_); ++j) {
          if constexpr (has_mass_points_v<M>) {
            // Points placed by functions of q: the impulse's Δq̇ (bilateral
            // constraints held) moves each point by (∂r/∂q) Δq̇ per unit.
            Vec<double, n> dqd;
            try {
              dqd = unit_impulse_response(model_, q, qd, t, G.row(j));
            } catch (const Error&) {
              continue;  // a singular state: judged at the others
            }
            point_motions(model_, q.data(), dqd.data(), nullptr, t, 0.0, points_);
            add_points(true, false);
          } else {
            // Particles (r = q, M diagonal by their masses): the impulse
            // acts along ∂φ/∂q at each particle.
            const Vec<double, n> row = G.row(j).transpose();
            point_motions(model_, q.data(), row.data(), nullptr, t, 0.0, points_);
            add_points(false, false);
          }
          sym.end_probe(MomentumSymmetry::Source::contact);
        }
      }
    };
    for_each_probe_state(start.data(), 2 * size_, t0, opt_.t_end, function_ref<void(const double*, double)>(probe));
    sym.write(report_);
  }

  void start_constraints(State<n>& x0, Columns& columns);
  /// The contacts at t0 (run_constraints.hpp); the resting ones.
  ActiveSet start_contacts(State<n>& x0, ConstraintState<n, constraint_count_v<M>>& cs, double qs);
  /// Residuals of the constraint state cs into the report (run_constraints.hpp).
  template <class CS>
  void record_residuals(CS cs, bool at_step);
  /// The model's only constraints are contacts: nothing to hold in free flight.
  static constexpr bool only_contacts_v = add_rows(holonomic_count_v<M>, pfaffian_count_v<M>) == 0;
  void sample_constraints(Sample<n>& s);
  /// With projection (the default stabilization), a sample taken from the
  /// dense output between two steps is projected onto the constraints as
  /// the steps are, so that samples meet the same tolerance as steps; the
  /// integration's own state is left as it is.
  void project_sample(Sample<n>& s);
  /// Projects (q, q̇) onto the active constraints at t: positions by Newton
  /// steps to projection_tolerance, then velocities; returns the position
  /// iterations. A projection that fails stops the run (SimulationError).
  int project_onto_constraints(Vec<double, n>& q, Vec<double, n>& qd, double t);

  Vec<double, event_count_v<M>> watched_at(const double* x, double t) const {
    if constexpr (event_count_v<M> > 0) {
      Vec<double, n> q(size_), qd(size_);
      split_state(x, q, qd);
      return model_.events(q, qd, t);
    } else {
      (void)x, (void)t;
      return {};
    }
  }
  std::string contact_name(int j) const {
    return report_.constraints.names[static_cast<std::size_t>(holonomic_count(model_) + j)];
  }
  /// d²φ_j/dt² = G_j q̈ + γ_j with q̈ from the current active set (contact j
  /// itself inactive): negative when the forces press the contact shut.
  double gap_acceleration(const Vec<double, n>& q, const Vec<double, n>& qd, double t, int j);

  /// An event without an impulse: logs it with the kinetic energy at x.
  void log_simple(EventKind kind, const std::string& name, double t, const double* x) {
    EventRecord rec;
    rec.t = t;
    rec.kind = kind;
    rec.name = name;
    Vec<double, n> q(size_), qd(size_);
    split_state(x, q, qd);
    if constexpr (!has_kinetic_potential_v<M>) evaluate(model_, ws_, q, qd, t);  // M for ½ q̇ᵀMq̇
    rec.kinetic_energy_before = rec.kinetic_energy_after = detail::kinetic_for_log(model_, ws_, q, qd, t);
    report_.events.push_back(rec);
  }
  /// After an impact: the energy references move by the energy the impact
  /// took, so the drift monitors keep measuring integration error only.
  void shift_reference_energy(const Vec<double, n>& q, const Vec<double, n>& qd, double t, double h_before,
                              double kinetic_change) {
    energy_.shift(t, energy_function(model_, q, qd, t) - h_before, kinetic_change);
  }

  const M& model_;
  const SimulationOptions& opt_;
  Observer obs_;
  RunReport& report_;
  int size_;
  mutable Workspace<n> rhs_ws_{model_size(model_)};  ///< the right-hand side's
  /// M factored once, for models declaring constant_mass_matrix (their
  /// free motion, when their only constraints are contacts)
  mutable std::conditional_t<uses_constant_mass, ConstantMassAccelerations<M>, None> constant_mass_{};
  Workspace<n> ws_{model_size(model_)};              ///< monitors' and events'
  [[no_unique_address]] std::conditional_t<has_constraints_v<M>, ConstraintContext<M>, None> context_{};
  ConstraintContext<M>* ctx_ = nullptr;  ///< &context_ for constrained models
  static constexpr int u_ = unilateral_count_v<M>;  ///< contacts (Dynamic: counted at run time)
  template <class T>
  using PerContact = std::conditional_t<u_ == Dynamic, std::vector<T>, std::array<T, u_ == Dynamic ? 0 : u_>>;
  PerContact<double> restitution_{};
  PerContact<ContactHistory> history_{};  ///< for the Zeno rule
  /// Gaps and rates at one state (run_events.hpp; run-time sized storage, sized once).
  Vec<double, u_> gap_in_, rate_in_;
  /// Made at the start when the model has contacts.
  [[no_unique_address]] std::conditional_t<u_ != 0, std::unique_ptr<Contacts>, None> contacts_{};
  /// Location of contact and watched events (models with events only).
  [[no_unique_address]] std::conditional_t<has_events_v, ContactEvents, None> contact_events_{};
  std::vector<EventSpec> specs_;
  std::vector<double> event_buf_;
  bool stopped_ = false;
  [[no_unique_address]] std::conditional_t<has_reference_v<M>, State<n>, None> reference_initial_{};
  [[no_unique_address]] std::conditional_t<has_constraints_v<M>, ConstraintWorkspace<n, constraint_count_v<M>>, None>
      cw_{};
  std::vector<int> cyclic_;
  bool has_points_ = false;           // point masses to sum (particles or mass points)
  std::vector<PointMotion> points_;  // their motions (storage reused)
  PointMomenta momenta_{opt_.angular_momentum_point};
  EnergyMonitor energy_;  ///< h and E = T + V against their start, impacts' shifts applied
  bool warned_conditioning_ = false;
  [[no_unique_address]] std::conditional_t<structure_preserving_v<M> && variational_supported_v<M>,
                                           std::optional<VariationalIntegrator<M>>, None>
      variational_;
};

}  // namespace lagrangian::detail

#include "lagrangian/integrate/detail/run_constraints.hpp"  // IWYU pragma: export
#include "lagrangian/integrate/detail/run_events.hpp"  // IWYU pragma: export
