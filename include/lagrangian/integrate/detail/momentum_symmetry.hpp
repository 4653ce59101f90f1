#pragma once
// Which components of a particle system's total momenta its symmetries
// conserve, judged at the start of a run from the forces and the contacts
// the system has (compiled once: src/integrate/momentum_symmetry.cpp).

#include <array>
#include <string>

#include "lagrangian/integrate/detail/roots.hpp"
#include "lagrangian/integrate/report.hpp"

namespace lagrangian::detail {

/// Noether's theorem for a particle system, tested rather than assumed. The
/// total linear momentum P = Σ m v changes along an axis only when the
/// external forces have a part along it, and the angular momentum
/// L = Σ m (r − r₀) × v about an axis through r₀ only when they have a
/// moment about it (internal forces come in equal, opposite, collinear
/// pairs). Both rates are summed at a few probe states — the start and
/// states perturbed from it — from the system's own accelerations,
///   Ṗ = Σ m a,   L̇ = Σ m (r − r₀) × a   (the v × v terms vanish),
/// so gravity, drag, springs to fixed points and constraint forces of fixed
/// surfaces all show up without being named. Impulses of contacts with fixed
/// surfaces are judged the same way from the impulse's direction at the
/// contact point. A component whose rate exceeds 1e-9 of the scale of its
/// terms (Σ m |a| for P) at any probe is not conserved; the rest are.
class MomentumSymmetry {
 public:
  enum class Source { force, contact };

  explicit MomentumSymmetry(const std::array<double, 3>& r0) : r0_(r0) {}

  /// One term of a probe: a particle of mass m (kg) at r (m) with
  /// acceleration a (m/s²) for Source::force; for Source::contact, m = 1 and
  /// a the direction of a fixed surface's impulse on the particle, r the
  /// point it acts at.
  void add(double m, const double* r, const double* a);
  /// Ends a probe: its sums are judged and cleared.
  void end_probe(Source source);

  /// Writes the verdicts into report (linear_momentum_conserved,
  /// angular_momentum_conserved and the reasons for the others).
  void write(RunReport& report) const;

 private:
  std::array<double, 3> r0_;
  std::array<double, 3> p_{}, l_{};
  double p_scale_ = 0, l_scale_ = 0;
  std::array<bool, 3> p_force_{}, p_contact_{}, l_force_{}, l_contact_{};
};

/// The states a run's symmetries are probed at: x0 (m values) at t0, then
/// four states with every value moved by up to 10 % of (1 + |x0_i|), at
/// times spread over [t0, t_end) — the same states every run. Calls
/// probe(x, t) for each.
void for_each_probe_state(const double* x0, int m, double t0, double t_end,
                          FunctionRef<void(const double*, double)> probe);

}  // namespace lagrangian::detail
