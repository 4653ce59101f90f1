#pragma once
// Internal: the 15th-order Gauss–Radau integrator for second-order systems
// q̈ = f(q, q̇, t) (method "gauss_radau15"), after Everhart (1985, "An
// efficient integrator that uses Gauss-Radau spacings", in Dynamics of
// Comets, IAU Coll. 83, 185) and Rein & Spiegel (2015, MNRAS 446, 1424,
// "IAS15"). Compiled once in src/integrate/gauss_radau.cpp.
//
// Over a step of size Δt from t₀, with s = (t − t₀)/Δt ∈ [0, 1], the
// acceleration is a polynomial of degree 7,
//   q̈(s) = a₀ + b₀ s + b₁ s² + … + b₆ s⁷,
// and integrating it twice gives the state inside the step:
//   q̇(s) = q̇₀ + Δt s (a₀ + b₀ s/2 + b₁ s²/3 + … + b₆ s⁷/8),
//   q(s)  = q₀ + q̇₀ Δt s + Δt² s² (a₀/2 + b₀ s/6 + b₁ s²/12 + … + b₆ s⁷/72).
// The b are fixed by collocation at the 7 Gauss–Radau nodes h₁ … h₇ of
// [0, 1] (with h₀ = 0: the 8-point Radau rule, exact to degree 14, so the
// step's error is O(Δt¹⁶)): in Newton's form
//   q̈(s) = a₀ + g₁ s + g₂ s (s − h₁) + … + g₇ s (s − h₁)…(s − h₆),
// each g_k is a divided difference of the accelerations at the nodes, and
// since the accelerations at the nodes depend on the state there, which
// depends on the b, the b are found by fixed-point iteration from a
// prediction (the previous step's polynomial, re-expanded about the new
// step). The same polynomial gives the dense output. |b₆|/|q̈|, the size of
// the last term, measures the step's error and sets the next step,
//   Δt_new = Δt (ε / (max|b₆| / max|q̈|))^(1/7),  (max|q̈| over the step's nodes)
// with ε the run's rtol (Rein & Spiegel 2015, §3.3). The state is summed
// with Kahan's compensation, so that the round-off of the sums does not
// grow with the number of steps.

#include <array>
#include <cstdint>
#include <vector>

#include "lagrangian/detail/roots.hpp"

namespace lagrangian::detail {

/// f(x, ẋ, t) of the first-order system x = [q; q̇] (2n values): the
/// stepper uses the second half of ẋ, q̈.
using FirstOrderRhs = FunctionRef<void(const double* x, double* dxdt, double t)>;

class GaussRadau15 {
 public:
  /// h₀ = 0 and the Gauss–Radau nodes h₁ … h₇ on [0, 1]: the roots of
  /// (P₇(u) + P₈(u))/(1 + u), u = 2h − 1, with Pₖ Legendre's polynomials.
  static const std::array<double, 8>& nodes();

  /// A stepper for n coordinates (state of 2n values).
  explicit GaussRadau15(int n);

  /// Starts from the state x (2n values): no compensation, no prediction.
  void start(const double* x);
  /// The state was changed between steps to x: by a projection onto the
  /// constraints (`discontinuous` false: the previous step's polynomial
  /// still predicts the next) or by an impact (true: it does not).
  void moved(const double* x, bool discontinuous);

  /// What an attempted step found.
  struct Attempt {
    int iterations = 0;           ///< predictor–corrector iterations
    double corrector_change = 0;  ///< max |Δb₆| / max |q̈| of the last iteration
    bool converged = false;       ///< the iteration reached round-off
    double error = 0;             ///< max |b₆| / max |q̈|, the step's error measure
  };
  /// Iterates the polynomial of a step of size dt from time t (the state is
  /// left as it was; accept() advances it).
  Attempt attempt(FirstOrderRhs f, double t, double dt);
  /// The next step after a step of size dt whose error measure was `error`,
  /// for the tolerance eps: dt (eps/error)^(1/7), at most 4 dt.
  static double next_step(double dt, double error, double eps);
  /// Advances the state over the step just attempted (size dt) and predicts
  /// the polynomial of the next.
  void accept(double dt);

  /// The state (2n values) after the last accepted step.
  void state(double* x) const;
  /// The state (2n values) at the fraction s ∈ [0, 1] of the last accepted
  /// step, from its polynomial.
  void dense(double s, double* x) const;

 private:
  void predict(double dt);

  int n_;
  std::vector<double> q_, v_, cq_, cv_;   // state and its compensation (q − cq is the sum)
  std::vector<double> a0_;                // q̈ at the start of the step
  bool a0_valid_ = false;
  std::vector<double> b_, g_, e_;         // 7 × n each: b_k of the attempt, Newton g_k, its prediction
  std::vector<double> b_last_, e_last_;   // the last accepted step's b and its prediction
  double dt_last_ = 0;
  bool have_last_ = false;
  // The last accepted step, for dense output.
  std::vector<double> q0_, v0_, cq0_, cv0_, a00_;
  std::vector<double> x_, dx_;            // 2n: a node's state and its derivative
};

}  // namespace lagrangian::detail
