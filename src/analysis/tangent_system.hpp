#pragma once
// Internal: the state with k tangent vectors beside it, as one System for
// the driver (lyapunov.cpp, floquet.cpp, sensitivity.cpp); its members are
// compiled once, in tangent_system.cpp.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/QR>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/integrate/detail/contact_rules.hpp"
#include "lagrangian/integrate/system.hpp"
#include "manifold.hpp"
#include "resting_contacts.hpp"

namespace lagrangian::detail {

/// ẋ = f(x, t) with k tangent vectors: the n(1 + k) coordinates
/// (q, δq_1, …, δq_k) and their rates (q̇, δq̇_1, …, δq̇_k), so that
/// d/dt δq_j = δq̇_j comes from the driver's layout and
///   d/dt δq̇_j = (∂q̈/∂q) δq_j + (∂q̈/∂q̇) δq̇_j.
/// With `benettin` (Lyapunov exponents) the tangent vectors start as the
/// first k canonical unit vectors (for a model with holonomic or Pfaffian
/// constraints: the first k vectors of a basis of the constraint manifold's
/// tangent space orthonormal in the reduced canonical coordinates
/// (Uᵀ δq, Uᵀ δp), U a basis of ker ∂g/∂q, in which it is factored; a
/// renormalisation projects the state onto the manifold and the vectors
/// onto its tangent space first) and Benettin's renormalisation is the
/// system's one event: after an accepted step in which a tangent vector's
/// length changed by more than a factor e since the last one, or `longest`
/// seconds after it, the canonical tangent matrix Z = P W
/// (P = [[I, 0], ∂p/∂x]) is factored Z = QR, log R_jj is added to sum j and
/// W becomes P⁻¹ Q. The driver then restarts the stepper from the new
/// state, as after any event. MEGNO is summed over every accepted step.
/// Without it (the monodromy matrix, sensitivities) they start as the first
/// k unit vectors of the state (δq, δq̇) and are never touched: at the end
/// they are the first k columns of the flow's Jacobian ∂x(t)/∂x(t0) (for a
/// model with holonomic or Pfaffian constraints they start as the basis B0
/// of manifold_basis(), k its d columns, and end as Φ B0; a recorded sample
/// holds Φ B0 B0ᵀ). After them come the columns s_j = ∂x/∂p_j of the
/// model's parameters `parameters` (sensitivity.hpp), from 0, with
///   d/dt δq̇ = (∂q̈/∂q) δq + (∂q̈/∂q̇) δq̇ + ∂q̈/∂p_j.
/// With `record`, every sample keeps its time, state and columns.
/// A model's contacts are located at the end of every accepted step by the
/// plain run's rules (contact_rules.hpp, on the step's interpolant); at the
/// earliest impact the step end moves there, q̇ becomes q̇⁺ and every column
/// w becomes S w (saltation.hpp), a parameter's column S w + R_p + a ∂φ/∂p / v
/// (sensitivity.hpp); MEGNO's ℓ jumps with the first vector's
/// length. Where the plain run lets a contact rest (its Zeno rule, a
/// plastic impact) the impact with e = 0 is crossed into the motion that
/// holds it shut (resting_contacts.hpp), whose saltation matrix removes
/// δφ_j and δφ̇_j: Benettin's vectors are renormalised at once and those
/// that vanished left out (exponents −∞); at its lift-off (λ_j = 0, the
/// rates agree) the columns cross unchanged. Refused with SimulationError:
/// a rest on a model without TangentModel::rest, or with parameter columns
/// that it does not hold (TangentModel::rest_holds_parameters),
/// a touch not faster than contact_touch_speed, an impact while a contact
/// rests that resting_contacts.hpp does not allow, a grazing contact, two
/// contacts closing or touching at once.
class TangentSystem final : public System {
 public:
  TangentSystem(const TangentModel& model, int k, double longest, bool benettin, std::vector<int> parameters = {},
                bool record = false);
  ~TangentSystem() override;

  int coordinate_count() const override { return model_.n * (1 + columns_); }

  void rhs(const double* x, double* dxdt, double t) const override;

  void start(double* x, double t0) override;
  void sample(double t, const double* x) override;
  void finish(double t, const double* x, bool sample_end) override;

  bool has_events() const override { return benettin_ || model_.contacts > 0; }
  bool handle_events(double t_old, const double* x_old, double& t, double* x,
                     const StepInterpolant& interpolant) override;

  /// Impacts crossed so far (a rest by the Zeno rule is not one).
  int impacts() const { return impacts_; }
  /// Contacts that came to rest, and resting contacts that lifted off.
  int rests() const { return resting_.rests(); }
  int releases() const { return resting_.releases(); }
  /// The run's options: its contact_touch_speed (a contact touching slower
  /// is not an impact) and Zeno rule (zeno_speed_ratio, zeno_min_interval:
  /// where a plain run lets a contact rest), contact_rules.hpp.
  void set_run(const SimulationOptions& run) { run_ = run; }

  /// The last renormalisation, at the end of the run at t.
  void close(double* x, double t);

  /// With `record`: the samples' times, states (q, q̇) and columns (above).
  const std::vector<double>& times() const { return times_; }
  const std::vector<Eigen::VectorXd>& states() const { return states_; }
  const std::vector<Eigen::MatrixXd>& recorded_columns() const { return columns_taken_; }

  /// The tangent matrix W = [δx_1 … δx_k] (2n × k, and the parameters'
  /// columns after them) held in x.
  const Eigen::MatrixXd& tangents(const double* x);

  std::uint64_t evaluations() const { return evaluations_; }
  double megno() const { return megno_; }
  double megno_mean(double t) const { return t > t0_ ? megno_integral_ / (t - t0_) : 0.0; }
  const std::vector<double>& sums() const { return sums_; }
  int renormalisations() const { return renormalisations_; }
  double shortest() const { return shortest_; }
  double longest() const { return longest_taken_; }

 private:
  /// Column j ≥ 1 of x (δq_j, δq̇_j) into direction_.
  void load_direction(const double* x, int j) const;
  /// The columns W (2n × columns) from x (their δq after q, their δq̇ after
  /// q̇, each n × columns column-major) and back.
  void load(const double* x);
  void store(double* x) const;
  /// P at the state of x, in p_ (its lower n rows ∂p/∂(q, q̇)) and the
  /// Cholesky factor of M = ∂p/∂q̇.
  void canonical(const double* x, double t);
  /// ∂p/∂(q, q̇) (n × 2n) of the last canonical().
  Eigen::Map<const Eigen::MatrixXd> dp_dx() const {
    return Eigen::Map<const Eigen::MatrixXd>(p_.data(), model_.n, 2 * model_.n);
  }
  /// W = P⁻¹ Z: δq = Z_q, δq̇ = M⁻¹ (Z_p − (∂p/∂q) Z_q).
  Eigen::MatrixXd from_canonical(const Eigen::MatrixXd& z) const;
  /// ℓ = ln |δx_1| of the first tangent vector as if never renormalised:
  /// its length in (q, q̇) plus the logs of the factors R_11 it was divided
  /// by (a renormalisation only scales it).
  double log_length(const double* x) const;
  /// MEGNO over the step [a, b] (s = t − t0): with I = ∫ s dℓ,
  ///   I(b) − I(a) = s_b ℓ_b − s_a ℓ_a − ∫ ℓ ds   (Simpson, ℓ at the
  ///   interpolated midpoint),  Y = 2 I / s,  ∫ Y ds by the trapezoid rule.
  void megno_step(double a, double b, const double* x, const StepInterpolant& interpolant);
  /// The tangent vectors' lengths in (q, q̇) just after a renormalisation
  /// (unit length in (q, p)): the next one is due when one of them has
  /// grown or shrunk by a factor e from there.
  void remember_lengths();
  void renormalise(double* x, double t);

  /// The live tangent vectors (live_: those no rest removed) in canonical
  /// coordinates (δq, δp = (∂p/∂q) δq + M δq̇), factored into qr_.
  void live_canonical(const Eigen::Map<const Eigen::MatrixXd>& dp);
  /// Just after a rest's saltation matrix (renormalise()): the vectors whose
  /// image lies, to rounding, in the span of those before them — S removed
  /// their part outside it (|R_jj| ≤ 1e-7 of the largest column; the
  /// columns were orthonormal at the last renormalisation and e = 0's S
  /// has entries of order 1, so a vector it keeps has |R_jj| far above
  /// that). They leave (dead_), at most two per rest; with fewer than 2n
  /// vectors, or the first one, SimulationError: the rest removed a vector
  /// that Benettin's method needs. Returns whether one left.
  bool collapse(double t);

  /// x with 6 significant digits, for messages.
  static std::string number(double x) { return short_number(x); }
  std::string contact(int j) const { return contact_name(model_, j); }
  /// The earliest contact closing in the step (t_old, t], located by the
  /// plain run's rules (locate_closing: crossings, dips of the gap, a
  /// contact leaving and coming back within the step): false when none;
  /// otherwise the step end moves to the impact (t, x), MEGNO is taken to
  /// it, the impact law applied to q̇ and the saltation matrix to every
  /// column; where a plain run lets the contact rest (the Zeno rule, a
  /// plastic impact) the impact is plastic and the contact rests from then
  /// on (TangentModel::rest). SimulationError for a rest the model cannot
  /// hold (above), a touch slower than contact_touch_speed, an impulse
  /// that sets a resting contact approaching or separating slowly
  /// (RestingContacts::lifted_by(); one that lifts it off releases it), two contacts
  /// closing or touching at one instant, a grazing contact and one found
  /// penetrated.
  bool cross_impact(double t_old, const double* x_old, double& t, double* x, const StepInterpolant& interpolant);

  TangentModel model_;
  int k_, columns_;
  std::vector<int> parameters_;
  bool record_;
  std::vector<double> times_;
  std::vector<Eigen::VectorXd> states_;
  std::vector<Eigen::MatrixXd> columns_taken_;
  double longest_;
  bool benettin_;
  mutable std::vector<double> qdd_, jacobian_;
  mutable std::vector<double> direction_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n));
  mutable std::uint64_t evaluations_ = 0;
  Eigen::MatrixXd w_, start_basis_;  // start_basis_: B0 on a manifold
  std::vector<double> p_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n * model_.n));
  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr_;
  std::vector<double> sums_, lengths_ = std::vector<double>(static_cast<std::size_t>(k_), 1.0);
  double last_ = 0, t0_ = 0;
  // MEGNO: ℓ at the last step end, its offset, I, Y and ∫ Y ds.
  double ell_ = 0, ell_offset_ = 0, megno_i_ = 0, megno_ = 0, megno_integral_ = 0;
  std::vector<double> mid_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n * (1 + columns_)));
  // Contacts: gaps at the step's ends and inside it, the impact map, the
  // accelerations either side, S and the columns after it.
  std::vector<double> gap_old_ = std::vector<double>(static_cast<std::size_t>(model_.contacts)),
                      gap_new_ = gap_old_, gap_at_ = gap_old_, rate_old_ = gap_old_, rate_new_ = gap_old_,
                      rate_at_ = gap_old_;
  std::vector<int> lifting_;  // resting contacts an impulse lifts off (reserved for every contact)
  SimulationOptions run_;
  std::vector<ContactHistory> history_ = std::vector<ContactHistory>(static_cast<std::size_t>(model_.contacts));
  EventProgress progress_;
  std::vector<double> qd_plus_ = std::vector<double>(static_cast<std::size_t>(model_.n)),
                      impact_jacobian_ = std::vector<double>(static_cast<std::size_t>(model_.n * (2 * model_.n + 1))),
                      gap_gradient_ = qd_plus_, qdd_minus_ = qd_plus_, qdd_plus_ = qd_plus_, scratch_ = qd_plus_,
                      zero_ = std::vector<double>(static_cast<std::size_t>(2 * model_.n)),
                      saltation_ = std::vector<double>(static_cast<std::size_t>(4 * model_.n * model_.n)),
                      salt_scratch_ = zero_;
  Eigen::MatrixXd jumped_;
  TangentManifold manifold_{model_, model_.n * (1 + columns_)};  // (models with holonomic or Pfaffian rows)
  int impacts_ = 0;
  // Resting contacts (TangentModel::rest); Benettin's vectors a rest
  // removed, the others (live_), and a renormalisation due after a rest.
  RestingContacts resting_{model_, model_.n * (1 + columns_)};
  std::vector<char> dead_ = std::vector<char>(static_cast<std::size_t>(k_), 0);
  std::vector<int> live_;
  bool rest_due_ = false;
  int renormalisations_ = 0;
  double shortest_ = std::numeric_limits<double>::infinity();
  double longest_taken_ = 0;
};

}  // namespace lagrangian::detail
