// The tangent flow of a particle scene (particle_engine.hpp): bodies in
// Cartesian coordinates under their declared force effects, held by their
// links and surfaces and meeting their contacts, with J = ∂a/∂(r, v) by
// automatic differentiation of the force kernels (particle_forces.hpp) and
// of the rows (particle_rows.hpp) on ad::Jet numbers, and the impacts'
// maps for the saltation matrix (analysis/saltation.hpp), as the
// TangentModel that lyapunov_spectrum() and floquet_multipliers() run.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "lagrangian/ad/eigen.hpp"
#include "lagrangian/ad/jet.hpp"
#include "lagrangian/analysis/floquet.hpp"
#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/mechanics/detail/min_norm_solver.hpp"
#include "lagrangian/scene/hard_spheres_tangent.hpp"
#include "particle_engine.hpp"
#include "particle_impact.hpp"
#include "particle_model.hpp"
#include "particle_parameters.hpp"

namespace lagrangian::scene::detail {
namespace {

using particles::ParticleModel;
using particles::Contact;
using particles::Parameter;
using particles::Row;
using particles::Vector3;

/// Directions per pass of the whole Jacobian.
constexpr int kWidth = 4;
using JetWide = ad::Jet<double, kWidth, 1>;
using JetOne = ad::Jet<double, 1, 1>;

/// The most bodies whose tangent flow is taken: 6N tangent vectors of 6N
/// values each, and J (3N × 6N) in 6N/4 passes of the force kernels.
constexpr std::size_t kMaxBodies = 100;

/// OptionError (`command: particle scene '<name>': …`) for a scene whose
/// tangent flow is not taken here: a gas (the event-driven engine's, or
/// none), more than kMaxBodies bodies. Read from the scene before anything
/// is built.
void require_tangent_flow_scene(const Scene& scene, const char* command) {
  std::string why;
  if (scene.gas) {
    why = std::string(command) == "floquet"
              ? "the Floquet multipliers of a gas are not derived (its motion has no period); its Lyapunov "
                "exponents and sensitivities are (lagrangian lyapunov, lagrangian sensitivity)"
              : "a gas has no force effects to differentiate: its tangent flow is the event-driven engine's "
                "(lyapunov_hard_spheres(), sensitivities_hard_spheres())";
  } else if (scene.bodies.size() > kMaxBodies) {
    why = "the tangent flow of a particle scene is taken for at most " + std::to_string(kMaxBodies) +
          " bodies; this one has " + std::to_string(scene.bodies.size());
  } else {
    return;
  }
  throw OptionError(std::string(command) + ": particle scene '" + scene.name + "': " + why);
}

/// A particle scene as a TangentModel: q = r (3N
/// positions, m), q̇ = v (m/s), p = m v, and q̈ = a(r, v) of its force
/// kernels (F = m a) held by the rows g(r) = 0 of its links and surfaces:
///   M q̈ = F + Cᵀλ,   C q̈ = −γ,
/// M = diag(m) ⊗ I₃, C = ∂g/∂r, γ = vᵀ ∂²g/∂r² v, and along a direction δ
/// of the state
///   M δq̈ = δF + δCᵀλ + Cᵀδλ,   C δq̈ = −δγ − δC q̈,
/// both solved through S = C M⁻¹ Cᵀ by its minimum-norm pseudo-inverse
/// (redundant rows allowed), as for a C++ model (analysis/detail/
/// tangent_solve.hpp) but with M diagonal and the sizes chosen at run time.
/// C, γ and F along the directions come from the rows and the kernels on
/// ad::Jets. Contacts (planes, a box's walls, sphere pairs) are crossed at
/// their impacts by Newton's law with the links' and surfaces' rows kept
/// (impact_map(): without rows, v_a⁺ = v_a + J n̂/m_a, v_b⁺ = v_b − J n̂/m_b,
/// J = −(1 + e) v / (1/m_a + 1/m_b), v = n̂ · (v_a − v_b) the approach
/// speed), whose derivatives in the state the saltation matrix takes come
/// from the same law on ad::Jets. In a scene without links and surfaces a
/// contact the tangent run lets rest (where a plain run does: its Zeno
/// rule, a plastic impact) joins the rows as φ = 0, as in a plain run,
/// until it lifts off (rest()); with them a rest stops the tangent run
/// (holding the gap would change the manifold the vectors are kept on).
/// The numbers and matrices of the passes are kept, sized when the rows
/// change.
class ParticleTangent {
 public:
  /// `scene` has passed require_tangent_flow_scene().
  explicit ParticleTangent(const Scene& scene)
      : model_(scene), name_(scene.name), x0_(initial_state(scene)), fixed_(model_.fixed_rows()), solver_(1) {
    contacts_ = model_.wall_contacts();
    const std::vector<int>& members = model_.pair_members();
    for (std::size_t p = 0; p < members.size(); ++p)
      for (std::size_t r = p + 1; r < members.size(); ++r)
        contacts_.push_back(model_.pair_contact(members[p], members[r]));
    const auto dim = static_cast<std::size_t>(model_.dim());
    wide_.resize(3 * dim);
    one_.resize(3 * dim);
    size_rows(fixed_);
  }
  ParticleTangent(const ParticleTangent&) = delete;
  ParticleTangent& operator=(const ParticleTangent&) = delete;

  lagrangian::detail::TangentModel tangent_model() const {
    lagrangian::detail::TangentModel tm;
    tm.model = this;
    tm.n = model_.dim();
    tm.evaluate = &evaluate;
    tm.momentum = &momentum;
    tm.evaluate_direction = &evaluate_direction;
    if (fixed_ > 0) {
      tm.manifold = 2 * fixed_;
      tm.manifold_holonomic = fixed_;
      for (const Row& row : model_.rows()) tm.manifold_names.push_back(row.name);
      for (const Row& row : model_.rows()) tm.manifold_names.push_back(row.name + " (rate)");
      tm.manifold_rows = &manifold_rows;
      tm.project = &project;
    }
    if (!contacts_.empty()) {
      tm.contacts = static_cast<int>(contacts_.size());
      for (const Contact& c : contacts_) {
        tm.contact_names.push_back(c.name);
        tm.restitution.push_back(c.e);
      }
      tm.gaps = &gaps;
      tm.impact = &impact;
      if (fixed_ == 0) tm.rest = &rest;
      tm.impact_alone_while_resting = true;  // Newton's law of the one contact, as a plain run's (impulse())
    }
    return tm;
  }
  /// The columns of the scene's parameters (scene_parameters(), whose
  /// names it returns) can follow: `tm`, made by tangent_model(), gets the
  /// hooks that give them.
  std::vector<std::string> use_parameters(const Scene& scene, lagrangian::detail::TangentModel& tm) {
    parameters_ = scene_parameters(scene, model_);
    tm.evaluate_parameter = &evaluate_parameter;
    if (fixed_ > 0) tm.parameter_manifold = &parameter_manifold;
    if (!contacts_.empty()) {
      tm.parameter_impact = &parameter_impact;
      tm.rest_holds_parameters = true;  // rest() holds the contact in the one model every pass evaluates
    }
    std::vector<std::string> names;
    for (const SceneParameter& p : parameters_) names.push_back(p.name);
    return names;
  }
  const double* q0() const { return x0_.data(); }
  const double* qd0() const { return x0_.data() + model_.dim(); }

 private:
  /// q̈ and ∂q̈/∂(q, q̇) (n × 2n, column-major) in passes of kWidth
  /// directions; without a drag or rows the velocity columns are 0 and not
  /// passed.
  static void evaluate(const void* self, const double* q, const double* qd, double, double* qdd, double* jacobian) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    const int n = s.model_.dim();
    const int directions = s.model_.velocity_dependent() || s.m_ > 0 ? 2 * n : n;
    if (directions == n) std::fill(jacobian + n * n, jacobian + 2 * n * n, 0.0);  // n ≤ 300: no overflow
    JetWide *r = s.wide_.data(), *v = r + n, *a = v + n;
    for (int first = 0; first < directions; first += kWidth) {
      for (int i = 0; i < n; ++i) {
        r[i] = JetWide(q[i]);
        v[i] = JetWide(qd[i]);
      }
      const int width = std::min(kWidth, directions - first);
      for (int k = 0; k < width; ++k) {
        const int d = first + k;
        (d < n ? r[d] : v[d - n]).g[static_cast<std::size_t>(k)] = 1.0;
      }
      s.accelerations(r, v, a, width, first == 0);
      for (int k = 0; k < width; ++k)
        for (int i = 0; i < n; ++i) jacobian[(first + k) * n + i] = a[i].g[static_cast<std::size_t>(k)];
      if (first == 0)
        for (int i = 0; i < n; ++i) qdd[i] = a[i].v;
    }
  }
  /// q̈ and (∂q̈/∂(q, q̇)) w along one direction w (2n values).
  static void evaluate_direction(const void* self, const double* q, const double* qd, double, const double* w,
                                 double* qdd, double* jw) {
    static_cast<const ParticleTangent*>(self)->along(q, qd, w, {}, qdd, jw);
  }
  /// q̈ and (∂q̈/∂(q, q̇)) w + ∂q̈/∂p for the scene's parameter number
  /// `parameter` (use_parameters()).
  static void evaluate_parameter(const void* self, const double* q, const double* qd, double, const double* w,
                                 int parameter, double* qdd, double* jw) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    s.along(q, qd, w, s.parameters_[static_cast<std::size_t>(parameter)].which, qdd, jw);
  }
  /// The impact map of contact j along the parameter (impact_along_parameter()).
  static double parameter_impact(const void* self, const double* q, const double* qd, double, int j, int parameter,
                                 bool plastic, double* dqd_plus) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    return impact_along_parameter(s.model_, s.contacts_[static_cast<std::size_t>(j)],
                                  s.parameters_[static_cast<std::size_t>(parameter)].which, q, qd, plastic,
                                  dqd_plus);
  }
  /// ∂h/∂p of the links' and surfaces' rows (rows_along_parameter()); returns p.
  static double parameter_manifold(const void* self, const double* q, const double* qd, double, int parameter,
                                   double* out) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    const SceneParameter& p = s.parameters_[static_cast<std::size_t>(parameter)];
    rows_along_parameter(s.model_, s.fixed_, p.which, q, qd, out);
    return p.value;
  }
  /// q̈ and its derivative along the direction w of the state and, when
  /// `p` is a parameter, along p.
  void along(const double* q, const double* qd, const double* w, const Parameter& p, double* qdd, double* jw) const {
    const int n = model_.dim();
    JetOne *r = one_.data(), *v = r + n, *a = v + n;
    for (int i = 0; i < n; ++i) {
      r[i] = JetOne(q[i]);
      r[i].g[0] = w[i];
      v[i] = JetOne(qd[i]);
      v[i].g[0] = w[n + i];
    }
    accelerations(r, v, a, 1, true, p);
    for (int i = 0; i < n; ++i) {
      qdd[i] = a[i].v;
      jw[i] = a[i].g[0];
    }
  }
  /// ∂p/∂(q, q̇) = [0 | diag(m ⊗ 1₃)] (n × 2n, column-major), p = m v.
  /// With `dl_dq`, ∂L/∂q = −∂V/∂q = m a(r, v), the force kernels' forces
  /// (drag included: a scene with drag conserves no energy; the rows'
  /// forces Cᵀλ are not part of ∂L/∂q).
  static void momentum(const void* self, const double* q, const double* qd, double, double* out, double* dl_dq) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    const int n = s.model_.dim();
    std::fill(out, out + 2 * n * n, 0.0);
    for (int i = 0; i < n; ++i) out[(n + i) * n + i] = s.model_.mass()[static_cast<std::size_t>(i / 3)];
    if (dl_dq == nullptr) return;
    JetOne *r = s.one_.data(), *v = r + n, *a = v + n;
    for (int i = 0; i < n; ++i) {
      r[i] = JetOne(q[i]);
      v[i] = JetOne(qd[i]);
    }
    s.model_.force_accelerations(r, v, a);
    for (int i = 0; i < n; ++i) dl_dq[i] = s.model_.mass()[static_cast<std::size_t>(i / 3)] * a[i].v;
  }
  /// The rows h = (g, ġ) of the links and surfaces, ġ = ∇g · (v_a − v_b),
  /// and ∂h/∂(q, q̇) (2m × 2n, column-major): each row by ad::Jets along the
  /// six positions of its two bodies.
  static void manifold_rows(const void* self, const double* q, const double* qd, double, double* residual,
                            double* jacobian) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    const int n = s.model_.dim(), m = s.fixed_;
    Eigen::Map<Eigen::MatrixXd> jac(jacobian, 2 * m, 2 * n);
    jac.setZero();
    JetSix* r = s.six_.data();
    for (int i = 0; i < n; ++i) r[i] = JetSix(q[i]);
    for (int i = 0; i < m; ++i) {
      const Row& row = s.model_.rows()[static_cast<std::size_t>(i)];
      const int bodies[2] = {row.a, row.b};
      for (int side = 0; side < 2; ++side)
        for (int c = 0; c < 3 && bodies[side] >= 0; ++c)
          r[3 * bodies[side] + c].g[static_cast<std::size_t>(3 * side + c)] = 1.0;
      const JetSix g = row.value(r);
      const Vector3<JetSix> grad = row.grad(r);
      JetSix rate(0.0);
      for (int c = 0; c < 3; ++c)
        rate += grad[c] * (qd[3 * row.a + c] - (row.b >= 0 ? qd[3 * row.b + c] : 0.0));
      residual[i] = g.v;
      residual[m + i] = rate.v;
      for (int side = 0; side < 2; ++side) {
        if (bodies[side] < 0) continue;
        const double sign = side == 0 ? 1.0 : -1.0;
        for (int c = 0; c < 3; ++c) {
          const int col = 3 * bodies[side] + c;
          const auto d = static_cast<std::size_t>(3 * side + c);
          jac(i, col) = g.g[d];
          jac(m + i, col) = rate.g[d];
          jac(m + i, n + col) = sign * grad[c].v;
          r[col].g[d] = 0.0;
        }
      }
    }
  }
  /// The state projected onto the rows: positions onto g = 0
  /// (M-weighted Gauss–Newton, ‖g‖∞ ≤ 1e-12 (1 + ‖r‖∞)), then velocities
  /// onto C v = 0; ConstraintError when the positions do not get there.
  static void project(const void* self, double* q, double* qd, double) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    const int n = s.model_.dim();
    std::copy(q, q + n, s.x_.begin());
    std::copy(qd, qd + n, s.x_.begin() + n);
    constexpr double tolerance = 1e-12;
    s.model_.project(s.x_.data(), tolerance);
    const double scale = 1.0 + Eigen::Map<const Eigen::VectorXd>(s.x_.data(), n).lpNorm<Eigen::Infinity>();
    const double residual = s.model_.position_residual(s.x_.data());
    if (!(residual <= 10 * tolerance * scale)) {
      const Row* worst = &s.model_.rows().front();
      for (const Row& row : s.model_.rows())
        if (std::abs(row.value(s.x_.data())) > std::abs(worst->value(s.x_.data()))) worst = &row;
      std::ostringstream os;
      os << "particle scene '" << s.name_ << "': the projection onto the links and surfaces left |g| = " << residual
         << " on row '" << worst->name << "' (tolerance " << tolerance * scale << ")";
      throw ConstraintError(os.str());
    }
    std::copy(s.x_.begin(), s.x_.begin() + n, q);
    std::copy(s.x_.begin() + n, s.x_.end(), qd);
  }

  /// Contact j rests (`shut`): its gap φ_j = 0 joins the rows after the
  /// links and surfaces, as in a plain run (ParticleModel::make_resting), so
  /// q̈ and its derivatives are those of the motion holding it; or it lifts
  /// off and leaves them.
  static void rest(const void* self, int j, bool shut) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    particles::Contact& c = s.model_.contact(s.contacts_[static_cast<std::size_t>(j)].id);
    if (shut) {
      s.model_.make_resting(c);
    } else {
      const std::vector<particles::Contact*>& resting = s.model_.resting_contacts();
      const auto it = std::find(resting.begin(), resting.end(), &c);
      if (it == resting.end()) throw std::logic_error("ParticleTangent::rest: contact " + c.name + " is not resting");
      s.model_.release(static_cast<std::size_t>(it - resting.begin()));
    }
    s.size_rows(static_cast<int>(s.model_.rows().size()));
  }
  /// The contacts' gaps φ (m) and rates φ̇ (m/s).
  static void gaps(const void* self, const double* q, const double* qd, double, double* gap, double* rate) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    for (std::size_t j = 0; j < s.contacts_.size(); ++j) {
      const Contact& c = s.contacts_[j];
      const int b = c.pair ? c.b : c.a;  // (a wall reads no second body)
      const lagrangian::detail::GapRate g =
          c.gap_rate(particles::at(q, c.a), particles::at(qd, c.a), particles::at(q, b), particles::at(qd, b));
      gap[j] = g.gap;
      rate[j] = g.rate;
    }
  }
  /// The impact map of contact j with coefficient e at (q, q̇⁻), the rows
  /// of the links and surfaces kept (impact_map()): q̇⁺, ∂q̇⁺/∂(q, q̇, t)
  /// (n × (2n + 1), column-major; the rows do not move, so the last
  /// column is 0), G = ∂φ/∂q, γ (φ̈ = G q̈ + γ); returns the approach speed v.
  static double impact(const void* self, const double* q, const double* qd, double, int j, double e, double* qd_plus,
                       double* jacobian, double* gap_gradient, double* gamma) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    const Contact& c = s.contacts_[static_cast<std::size_t>(j)];
    const int n = s.model_.dim();
    const double v = impact_map(s.model_, c, q, qd, e, qd_plus, jacobian);
    double* time_column = jacobian + static_cast<std::ptrdiff_t>(n) * (2 * n);
    std::fill(time_column, time_column + n, 0.0);
    // G: n̂ on body a, −n̂ on body b; γ: a wall's gap n̂·(r_a − p) − R has
    // none; a pair's |d| − R has (|ḋ|² − (n̂·ḋ)²)/|d|.
    std::fill(gap_gradient, gap_gradient + n, 0.0);
    const Vector3<double> normal = c.normal(q);
    for (int k = 0; k < 3; ++k) {
      gap_gradient[3 * c.a + k] = normal[k];
      if (c.pair) gap_gradient[3 * c.b + k] = -normal[k];
    }
    *gamma = 0.0;
    if (c.pair) {
      const Vector3<double> d = particles::at(q, c.a) - particles::at(q, c.b);
      const Vector3<double> dv = particles::at(qd, c.a) - particles::at(qd, c.b);
      *gamma = (dv.squaredNorm() - v * v) / d.norm();
    }
    return v;
  }

  /// a: q̈ on numbers J that carry `width` directions, from the force
  /// kernels and, with rows, their multipliers (the class comment); a pass
  /// of one direction may seed a parameter `p` of the scene too. The
  /// values (C, S and its factors, λ, q̈) are the same in every pass of one
  /// evaluation: `values` false reuses those of the pass before.
  template <class J>
  void accelerations(const J* r, const J* v, J* a, int width, bool values = true, const Parameter& p = {}) const {
    model_.force_accelerations(r, v, a, p);
    if (m_ == 0) return;
    const int n = model_.dim();
    // C, γ and the free accelerations F/m, with their derivatives.
    for (int k = 0; k < width; ++k) dc_[static_cast<std::size_t>(k)].setZero();
    if (values) c_.setZero();
    for (int i = 0; i < m_; ++i) {
      const Row& row = model_.rows()[static_cast<std::size_t>(i)];
      const Vector3<J> grad = row.grad(r, p);
      const J gamma = row.gamma(r, v);
      gamma_(i, 0) = gamma.v;
      for (int k = 0; k < width; ++k) gamma_(i, k + 1) = gamma.g[static_cast<std::size_t>(k)];
      for (int c = 0; c < 3; ++c) {
        if (values) {
          c_(i, 3 * row.a + c) += grad[c].v;
          if (row.b >= 0) c_(i, 3 * row.b + c) -= grad[c].v;
        }
        for (int k = 0; k < width; ++k) {
          const double dg = grad[c].g[static_cast<std::size_t>(k)];
          dc_[static_cast<std::size_t>(k)](i, 3 * row.a + c) += dg;
          if (row.b >= 0) dc_[static_cast<std::size_t>(k)](i, 3 * row.b + c) -= dg;
        }
      }
    }
    for (int i = 0; i < n; ++i) {
      free_(i, 0) = a[i].v;
      for (int k = 0; k < width; ++k) free_(i, k + 1) = a[i].g[static_cast<std::size_t>(k)];
    }
    if (values) {
      minv_ct_.noalias() = model_.inverse_masses().asDiagonal() * c_.transpose();
      schur_.noalias() = c_ * minv_ct_;
      solver_.factorize(schur_.data());
      // λ = S⁺ (−γ − C a_F), q̈ = a_F + M⁻¹Cᵀλ.
      rhs_ = -gamma_.col(0);
      rhs_.noalias() -= c_ * free_.col(0);
      solver_.solve(rhs_.data(), lambda_.data());
      qdd_ = free_.col(0);
      qdd_.noalias() += minv_ct_ * lambda_;
    }
    for (int i = 0; i < n; ++i) a[i].v = qdd_[i];
    // δq̈ = u + M⁻¹Cᵀδλ, u = δa_F + M⁻¹δCᵀλ + δ(M⁻¹) Cᵀλ,
    // δλ = S⁺ (−δγ − δC q̈ − C u); δ(M⁻¹) is −1/m_i² on body i's three
    // coordinates when its mass m_i is the seeded parameter.
    for (int k = 0; k < width; ++k) {
      const Eigen::MatrixXd& dc = dc_[static_cast<std::size_t>(k)];
      scratch_.noalias() = dc.transpose() * lambda_;
      u_ = free_.col(k + 1) + model_.inverse_masses().cwiseProduct(scratch_);
      if (p.kind == Parameter::Kind::mass) {
        const double inverse = model_.inverse_masses()[3 * p.index];
        u_.segment<3>(3 * p.index).noalias() -=
            inverse * inverse * (c_.middleCols<3>(3 * p.index).transpose() * lambda_);
      }
      rhs_ = -gamma_.col(k + 1);
      rhs_.noalias() -= dc * qdd_;
      rhs_.noalias() -= c_ * u_;
      solver_.solve(rhs_.data(), dlambda_.data());
      u_.noalias() += minv_ct_ * dlambda_;
      for (int i = 0; i < n; ++i) a[i].g[static_cast<std::size_t>(k)] = u_[i];
    }
  }

  /// The passes' workspace for m rows (m_): sized when the number of rows
  /// changes to one it does not hold (a contact opened and held again for a
  /// multiplier finds it sized), not per evaluation.
  void size_rows(int m) const {
    m_ = m;
    if (m == 0 || m == sized_) return;
    sized_ = m;
    const int n = model_.dim();
    six_.resize(static_cast<std::size_t>(n));
    x_.resize(static_cast<std::size_t>(2 * n));
    c_.setZero(m, n);
    dc_.assign(kWidth, Eigen::MatrixXd::Zero(m, n));
    gamma_.setZero(m, kWidth + 1);
    minv_ct_.setZero(n, m);
    schur_.setZero(m, m);
    free_.setZero(n, kWidth + 1);
    qdd_.setZero(n);
    u_.setZero(n);
    scratch_.setZero(n);
    rhs_.setZero(m);
    lambda_.setZero(m);
    dlambda_.setZero(m);
    solver_ = lagrangian::detail::MinNormSolver(m);
  }

  using JetSix = ad::Jet<double, 6, 1>;  // the positions of a row's two bodies
  mutable ParticleModel model_;  // its kernels count their evaluations; it holds the resting contacts' rows
  std::string name_;             // the scene's
  mutable std::vector<JetWide> wide_;
  mutable std::vector<JetOne> one_;
  std::vector<double> x0_;
  std::vector<Contact> contacts_;  // walls and planes, then the sphere pairs
  std::vector<SceneParameter> parameters_;  // those whose columns are asked for (use_parameters())
  int fixed_;                      // rows of the links and surfaces
  mutable int m_ = 0;              // rows now: those and the resting contacts'
  mutable int sized_ = 0;          // rows the workspace below is sized for
  // The passes' workspace (the class comment's names).
  mutable std::vector<JetSix> six_;
  mutable std::vector<double> x_;
  mutable Eigen::MatrixXd c_, gamma_, minv_ct_, schur_, free_;
  mutable std::vector<Eigen::MatrixXd> dc_;
  mutable Eigen::VectorXd qdd_, u_, scratch_, rhs_, lambda_, dlambda_;
  mutable lagrangian::detail::MinNormSolver solver_;
};

/// A gas scene with its spheres expanded, for the event-driven engine's
/// tangent flow (scene/hard_spheres_tangent.hpp); OptionError for a gas
/// that engine does not run (force effects, or engine = "ode").
Scene expanded_gas(const Scene& scene, const char* command) {
  Scene s = scene;
  s.expand_gas();
  if (s.run.engine == "ode" || !event_driven_eligible(s))
    throw OptionError(std::string(command) + ": particle scene '" + scene.name +
                      "': the tangent flow of a gas is taken on the event-driven engine (spheres flying free "
                      "between sphere, box and plane contacts, no force effect" +
                      (s.run.engine == "ode" ? std::string("); this scene asks for engine = \"ode\"")
                                             : std::string("); this scene declares other effects")));
  return s;
}

}  // namespace

LyapunovResult particle_lyapunov(const Scene& scene, const LyapunovOptions& options) {
  if (scene.gas) {
    const Scene gas = expanded_gas(scene, "lyapunov");
    return lyapunov_hard_spheres(hard_sphere_system(gas), hard_sphere_options(gas, options.run), options.exponents,
                                 options.interval);
  }
  require_tangent_flow_scene(scene, "lyapunov");
  const ParticleTangent tangent(scene);
  return lagrangian::detail::lyapunov_spectrum(tangent.tangent_model(), tangent.q0(), tangent.qd0(), options);
}

FloquetResult particle_floquet(const Scene& scene, const FloquetOptions& options) {
  require_tangent_flow_scene(scene, "floquet");
  const ParticleTangent tangent(scene);
  return lagrangian::detail::floquet_multipliers(tangent.tangent_model(), tangent.q0(), tangent.qd0(), options);
}

SensitivityResult particle_sensitivities(const Scene& scene, const SensitivityOptions& options) {
  if (scene.gas) {
    if (!options.parameters.empty())
      throw OptionError("sensitivity: particle scene '" + scene.name + "': --parameter " +
                        options.parameters.front() +
                        ": a gas's sensitivities are those of its initial state (its event-driven tangent flow "
                        "carries no parameter columns)");
    const Scene gas = expanded_gas(scene, "sensitivity");
    return sensitivities_hard_spheres(hard_sphere_system(gas), hard_sphere_options(gas, options.run));
  }
  require_tangent_flow_scene(scene, "sensitivity");
  ParticleTangent tangent(scene);
  lagrangian::detail::TangentModel tm = tangent.tangent_model();
  std::vector<int> indices;
  std::vector<std::string> names;
  if (!options.parameters.empty()) {
    names = tangent.use_parameters(scene, tm);
    indices = lagrangian::detail::parameter_indices(options.parameters, names);
  }
  return lagrangian::detail::sensitivities(tm, tangent.q0(), tangent.qd0(), indices, names, options);
}

Eigen::MatrixXd particle_acceleration_jacobian(const Scene& scene, const std::vector<double>& x,
                                               Eigen::VectorXd* a) {
  require_tangent_flow_scene(scene, "particle_acceleration_jacobian");
  const ParticleTangent tangent(scene);
  const lagrangian::detail::TangentModel tm = tangent.tangent_model();
  const int n = tm.n;
  if (static_cast<int>(x.size()) != 2 * n)
    throw OptionError("particle_acceleration_jacobian: x has " + std::to_string(x.size()) + " values; the scene's " +
                      "state has " + std::to_string(2 * n));
  Eigen::MatrixXd j(n, 2 * n);
  Eigen::VectorXd qdd(n);
  tm.evaluate(tm.model, x.data(), x.data() + n, 0.0, qdd.data(), j.data());
  if (a != nullptr) *a = qdd;
  return j;
}

}  // namespace lagrangian::scene::detail
