// AD-derived q̈, p and M against independent hand derivations at seeded
// random states.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/LU>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/mechanics/detail/constant_mass.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/models/projectile.hpp"
#include "lagrangian/models/two_body.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;

constexpr double kRel = 1e-12;  // agreement asked of AD against the hand derivations
constexpr int kStates = 50;     // random states per model

template <class A, class B>
void expect_close(const Eigen::MatrixBase<A>& ad, const Eigen::MatrixBase<B>& hand, const char* what) {
  const double scale = std::max(hand.template lpNorm<Eigen::Infinity>(), 1e-300);
  EXPECT_LE((ad - hand).template lpNorm<Eigen::Infinity>(), kRel * scale) << what << ":\nAD\n" << ad << "\nhand\n" << hand;
}

/// Solves a 2×2 system by Cramer's rule (independent of the library's LLT).
Vec<double, 2> cramer(const Mat<double, 2>& M, const Vec<double, 2>& f) {
  const double det = M(0, 0) * M(1, 1) - M(0, 1) * M(1, 0);
  return {(f[0] * M(1, 1) - M(0, 1) * f[1]) / det, (M(0, 0) * f[1] - M(1, 0) * f[0]) / det};
}

template <class Model, class HandFn>
void check_model_against_hand(const Model& model, HandFn hand, double q_lo, double q_hi, double t = 0.0) {
  constexpr int n = lagrangian::coordinate_count_v<Model>;
  std::mt19937_64 rng(20261121);
  std::uniform_real_distribution<double> uq(q_lo, q_hi), uv(-3.0, 3.0), ut(0.0, 5.0);
  Workspace<n> ws;
  for (int s = 0; s < kStates; ++s) {
    Vec<double, n> q, qd;
    for (int i = 0; i < n; ++i) {
      q[i] = uq(rng);
      qd[i] = uv(rng);
    }
    const double tt = t < 0 ? ut(rng) : t;
    const auto h = hand(q, qd, tt);
    const Vec<double, n> qdd = accelerations(model, ws, q, qd, tt);
    expect_close(mass_matrix(model, q, qd, tt), h.M, "mass matrix");
    expect_close(momenta(model, q, qd, tt), h.p, "momenta");
    expect_close(qdd, h.qdd, "accelerations");
  }
}

template <int N>
struct Hand {
  Mat<double, N> M;
  Vec<double, N> p;
  Vec<double, N> qdd;
};

TEST(Dynamics, SimplePendulumMatchesHandDerivation) {
  const SimplePendulum m(1.3, 0.7, 9.81);
  check_model_against_hand(
      m,
      [&](const Vec<double, 1>& q, const Vec<double, 1>& qd, double) {
        Hand<1> h;
        h.M(0, 0) = m.m * m.l * m.l;
        h.p[0] = h.M(0, 0) * qd[0];
        h.qdd[0] = -(m.g / m.l) * std::sin(q[0]);
        return h;
      },
      -3.0, 3.0);
}

TEST(Dynamics, DoublePendulumMatchesHandDerivation) {
  const DoublePendulum m(1.5, 0.7, 1.1, 0.8, 9.81);
  check_model_against_hand(
      m,
      [&](const Vec<double, 2>& q, const Vec<double, 2>& qd, double) {
        const double d = q[0] - q[1];
        Hand<2> h;
        h.M << (m.m1 + m.m2) * m.l1 * m.l1, m.m2 * m.l1 * m.l2 * std::cos(d), m.m2 * m.l1 * m.l2 * std::cos(d),
            m.m2 * m.l2 * m.l2;
        h.p = h.M * qd;
        const Vec<double, 2> f(-m.m2 * m.l1 * m.l2 * qd[1] * qd[1] * std::sin(d) - (m.m1 + m.m2) * m.g * m.l1 * std::sin(q[0]),
                               m.m2 * m.l1 * m.l2 * qd[0] * qd[0] * std::sin(d) - m.m2 * m.g * m.l2 * std::sin(q[1]));
        h.qdd = cramer(h.M, f);
        return h;
      },
      -3.0, 3.0);
}

TEST(Dynamics, SphericalPendulumMatchesHandDerivation) {
  const SphericalPendulum m(0.9, 1.4, 9.81);
  check_model_against_hand(
      m,
      [&](const Vec<double, 2>& q, const Vec<double, 2>& qd, double) {
        const double s = std::sin(q[0]), c = std::cos(q[0]);
        Hand<2> h;
        h.M << m.m * m.l * m.l, 0, 0, m.m * m.l * m.l * s * s;
        h.p = h.M * qd;
        h.qdd << s * c * qd[1] * qd[1] - (m.g / m.l) * s, -2.0 * (c / s) * qd[0] * qd[1];
        return h;
      },
      0.2, 2.9);  // away from the poles, where M is singular
}

TEST(Dynamics, ElasticPendulumMatchesHandDerivation) {
  const ElasticPendulum m(0.8, 35.0, 1.2, 9.81);
  check_model_against_hand(
      m,
      [&](const Vec<double, 2>& q, const Vec<double, 2>& qd, double) {
        const double r = q[0], th = q[1];
        Hand<2> h;
        h.M << m.m, 0, 0, m.m * r * r;
        h.p = h.M * qd;
        h.qdd << r * qd[1] * qd[1] + m.g * std::cos(th) - (m.k / m.m) * (r - m.l0),
            -2.0 * qd[0] * qd[1] / r - (m.g / r) * std::sin(th);
        return h;
      },
      0.3, 2.5);
}

TEST(Dynamics, BeadOnRotatingHoopMatchesHandDerivation) {
  const BeadOnRotatingHoop m(0.2, 0.6, 5.0, 9.81);
  check_model_against_hand(
      m,
      [&](const Vec<double, 1>& q, const Vec<double, 1>& qd, double) {
        Hand<1> h;
        h.M(0, 0) = m.m * m.R * m.R;
        h.p[0] = h.M(0, 0) * qd[0];
        // m R² θ̈ = m R² ω² sinθ cosθ − m g R sinθ
        h.qdd[0] = std::sin(q[0]) * (m.omega * m.omega * std::cos(q[0]) - m.g / m.R);
        return h;
      },
      -3.0, 3.0);
}

TEST(Dynamics, KeplerPolarMatchesHandDerivation) {
  const KeplerPolar m(2.0, 3.0);
  check_model_against_hand(
      m,
      [&](const Vec<double, 2>& q, const Vec<double, 2>& qd, double) {
        const double r = q[0];
        Hand<2> h;
        h.M << m.m, 0, 0, m.m * r * r;
        h.p = h.M * qd;
        h.qdd << r * qd[1] * qd[1] - m.k / (m.m * r * r), -2.0 * qd[0] * qd[1] / r;
        return h;
      },
      0.3, 3.0);
}

TEST(Dynamics, CartPendulumMatchesHandDerivation) {
  const CartPendulum m(2.5, 0.7, 0.9, 12.0, 9.81);
  check_model_against_hand(
      m,
      [&](const Vec<double, 2>& q, const Vec<double, 2>& qd, double) {
        const double c = std::cos(q[1]), s = std::sin(q[1]);
        Hand<2> h;
        h.M << m.M + m.m, m.m * m.l * c, m.m * m.l * c, m.m * m.l * m.l;
        h.p = h.M * qd;
        const Vec<double, 2> f(m.m * m.l * s * qd[1] * qd[1] - m.k * q[0], -m.m * m.g * m.l * s);
        h.qdd = cramer(h.M, f);
        return h;
      },
      -2.0, 2.0);
}

TEST(Dynamics, DrivenPendulumMatchesHandDerivation) {
  // Explicit time dependence: exercises ∂²L/∂q̇∂t and ∂L/∂t.
  const DrivenPendulum m(0.5, 0.9, 0.07, 25.0, 9.81);
  check_model_against_hand(
      m,
      [&](const Vec<double, 1>& q, const Vec<double, 1>& qd, double t) {
        const double yd = -m.a * m.Omega * std::sin(m.Omega * t);
        const double ydd = -m.a * m.Omega * m.Omega * std::cos(m.Omega * t);
        Hand<1> h;
        h.M(0, 0) = m.m * m.l * m.l;
        h.p[0] = m.m * m.l * m.l * qd[0] + m.m * m.l * yd * std::sin(q[0]);
        h.qdd[0] = -(m.g + ydd) * std::sin(q[0]) / m.l;
        return h;
      },
      -3.0, 3.0, -1.0);
}

TEST(Dynamics, PendulumChainOfTwoEqualsDoublePendulum) {
  const PendulumChain<2> chain(1.0, 1.0, 9.81);
  const DoublePendulum dp(1.0, 1.0, 1.0, 1.0, 9.81);
  const Vec<double, 2> q(0.4, -1.2), qd(0.9, 2.1);
  expect_close(accelerations(chain, q, qd), accelerations(dp, q, qd), "chain vs double pendulum");
  expect_close(mass_matrix(chain, q, qd), mass_matrix(dp, q, qd), "chain vs double pendulum M");
}

TEST(Dynamics, PendulumChainMatchesHandDerivation) {
  // M_ij = (Σ_{k≥max(i,j)} m_k) l_i l_j cos(θi − θj);
  // rhs_i = −Σ_j (Σ_{k≥max(i,j)} m_k) l_i l_j sin(θi − θj) θ̇j² − (Σ_{k≥i} m_k) g l_i sin θi.
  constexpr int n = 6;
  const PendulumChain<n> chain(0.7, 0.4, 9.81);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  Vec<double, n> q, qd;
  for (int i = 0; i < n; ++i) {
    q[i] = u(rng);
    qd[i] = u(rng);
  }
  Mat<double, n> M;
  Vec<double, n> f;
  for (int i = 0; i < n; ++i) {
    f[i] = -(n - i) * chain.m[i] * chain.g * chain.l[i] * std::sin(q[i]);
    for (int j = 0; j < n; ++j) {
      const double mass_beyond = (n - std::max(i, j)) * chain.m[0];
      M(i, j) = mass_beyond * chain.l[i] * chain.l[j] * std::cos(q[i] - q[j]);
      f[i] -= mass_beyond * chain.l[i] * chain.l[j] * std::sin(q[i] - q[j]) * qd[j] * qd[j];
    }
  }
  expect_close(mass_matrix(chain, q, qd), M, "chain M");
  const Vec<double, n> qdd_hand = M.partialPivLu().solve(f);
  const double scale = qdd_hand.lpNorm<Eigen::Infinity>();
  // Condition number of M enters the comparison of two different solvers.
  EXPECT_LE((accelerations(chain, q, qd) - qdd_hand).lpNorm<Eigen::Infinity>(), 1e-10 * scale);
}

TEST(Dynamics, EnergyFunctionAndTotalEnergy) {
  // Natural, scleronomic: h = T + V.
  const DoublePendulum dp;
  const Vec<double, 2> q(0.3, -0.8), qd(1.1, -0.4);
  EXPECT_NEAR(energy_function(dp, q, qd), total_energy(dp, q, qd), 1e-13);
  // Rotating hoop: h = ½ m R² (θ̇² − ω² sin²θ) + V ≠ T + V.
  const BeadOnRotatingHoop hoop(0.2, 0.6, 5.0, 9.81);
  const Vec<double, 1> th(0.7), thd(1.3);
  const double s = std::sin(th[0]);
  const double h_hand = 0.5 * hoop.m * hoop.R * hoop.R * (thd[0] * thd[0] - hoop.omega * hoop.omega * s * s) -
                        hoop.m * hoop.g * hoop.R * std::cos(th[0]);
  EXPECT_NEAR(energy_function(hoop, th, thd), h_hand, 1e-14);
  EXPECT_GT(std::abs(total_energy(hoop, th, thd) - h_hand), 0.1);
  EXPECT_NEAR(lagrangian_value(dp, q, qd), kinetic_energy(dp, q, qd) - potential_energy(dp, q), 1e-14);
}

TEST(Dynamics, RayleighDissipationAndForces) {
  // Damped, forced oscillator: m ẍ = −k x − c ẋ + F.
  const double m = 2.0, k = 8.0, c = 0.6, F = 1.5;
  auto osc = with_forces(
      with_dissipation(make_model<1>(
                           "oscillator", {"x"},
                           [m](const auto&, const auto& qd, const auto&) { return 0.5 * m * qd[0] * qd[0]; },
                           [k](const auto& q, const auto&) { return 0.5 * k * q[0] * q[0]; }),
                       [c](const auto&, const auto& qd) { return 0.5 * c * qd[0] * qd[0]; }),
      [F](const auto& q, const auto&, const auto&) {
        using S = typename std::decay_t<decltype(q)>::Scalar;
        return Vec<S, 1>(S(F));
      });
  const Vec<double, 1> x(0.3), v(-1.2);
  EXPECT_NEAR(accelerations(osc, x, v)[0], (-k * x[0] - c * v[0] + F) / m, 1e-14);
  EXPECT_NEAR(nonconservative_forces(osc, x, v)[0], -c * v[0] + F, 1e-14);
}

// A model that gives L directly instead of T and V.
struct DirectKepler {
  static constexpr int dof = 2;
  KeplerPolar inner{1.5, 2.0};
  template <class S>
  S lagrangian(const Vec<S, 2>& q, const Vec<S, 2>& qd, const S& t) const {
    return inner.kinetic(q, qd, t) - inner.potential(q, t);
  }
};

TEST(Dynamics, DirectLagrangianEqualsKineticMinusPotential) {
  const Vec<double, 2> q(1.3, 0.2), qd(0.4, 0.9);
  const DirectKepler d;
  expect_close(accelerations(d, q, qd), accelerations(d.inner, q, qd), "direct L");
  EXPECT_NEAR(energy_function(d, q, qd), total_energy(d.inner, q, qd), 1e-14);
}

// A model states its number of coordinates as `coordinate_count` (as the
// built-in SimplePendulum does); the older spelling `dof` is still read. The
// same pendulum written both ways gives the same q̈ and the same run, to the bit.
struct PendulumOnlyDof {
  static constexpr int dof = 1;
  SimplePendulum p;
  template <class S>
  S kinetic(const Vec<S, 1>& q, const Vec<S, 1>& qd, const S& t) const {
    return p.kinetic(q, qd, t);
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S& t) const {
    return p.potential(q, t);
  }
};

TEST(ModelSpelling, CoordinateCountAndTheOlderDofAgree) {
  static_assert(coordinate_count_v<SimplePendulum> == 1);
  static_assert(coordinate_count_v<PendulumOnlyDof> == 1);
  static_assert(coordinate_count_v<DoublePendulum> == 2);
  const SimplePendulum a(1.3, 0.7, 9.81);
  const PendulumOnlyDof b{a};
  State<1> x0;
  x0.q << 1.1;
  x0.qd << -0.4;
  // q̈ = −(g/l) sin q for a simple pendulum, from both.
  EXPECT_NEAR(accelerations(a, x0.q, x0.qd, 0.0)[0], -(a.g / a.l) * std::sin(1.1), 1e-12);
  EXPECT_EQ(accelerations(a, x0.q, x0.qd, 0.0)[0], accelerations(b, x0.q, x0.qd, 0.0)[0]);
  SimulationOptions o;
  o.t_end = 3.0;
  o.output_interval = -1;
  const RunReport ra = simulate(a, x0, o), rb = simulate(b, x0, o);
  EXPECT_EQ(ra.steps, rb.steps);
  EXPECT_EQ(ra.energy_final, rb.energy_final);
  EXPECT_LE(ra.energy_drift_max, 1e-8);
}

// -- models declaring constant_mass_matrix (T = ½ q̇ᵀ M q̇ + bᵀq̇ + c with
// constant M, b, c): their q̈ against Newton's law written out by hand, the
// run's results against the same model without the declaration, and a false
// declaration stopping the run with an error that names it.

namespace lm = lagrangian::models;

/// The same model with the declaration withdrawn: the general equations of
/// motion (one AD pass for M, ∂L/∂q and the mixed term, then M⁻¹).
template <class M>
struct General : M {
  static constexpr bool constant_mass_matrix = false;
  explicit General(M m) : M(std::move(m)) {}
};

template <class M>
Vec<double, coordinate_count_v<M>> fast_qdd(const M& model, const Vec<double, coordinate_count_v<M>>& q,
                                            const Vec<double, coordinate_count_v<M>>& qd, double t) {
  constexpr int n = coordinate_count_v<M>;
  lagrangian::detail::ConstantMassAccelerations<M> fast;
  Workspace<n> ws;
  fast.prepare(model, ws, q, qd, t);
  Vec<double, n> out;
  fast(model, ws, q, qd, t, out);
  return out;
}

TEST(ConstantMass, TwoBodiesAccelerateAsNewtonsLawOfGravitation) {
  // q̈₁ = k (r₂ − r₁)/(m₁ r³), q̈₂ = −k (r₂ − r₁)/(m₂ r³), in long double.
  const double m1 = 1.0, m2 = 1e-3, k = 1e-3;
  const lm::TwoBody<3> model(m1, m2, lm::NewtonianGravity{k});
  static_assert(constant_mass_matrix_v<lm::TwoBody<3>>);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst_fast = 0, worst_general = 0;
  for (int trial = 0; trial < 50; ++trial) {
    Vec<double, 6> q, qd;
    for (int i = 0; i < 6; ++i) {
      q[i] = u(rng);
      qd[i] = u(rng);
    }
    using L = long double;
    L d[3], r2 = 0;
    for (int c = 0; c < 3; ++c) {
      d[c] = L(q[3 + c]) - L(q[c]);
      r2 += d[c] * d[c];
    }
    const L f = L(k) / (r2 * std::sqrt(r2));
    const Vec<double, 6> fast = fast_qdd(model, q, qd, 0.0);
    const Vec<double, 6> general = accelerations(General(model), q, qd, 0.0);
    for (int c = 0; c < 3; ++c)
      for (const auto& [i, exact] : {std::pair{c, f * d[c] / m1}, std::pair{3 + c, -f * d[c] / m2}}) {
        const double scale = static_cast<double>(f * std::sqrt(r2) / m2);
        worst_fast = std::max(worst_fast, static_cast<double>(std::abs(fast[i] - exact)) / scale);
        worst_general = std::max(worst_general, static_cast<double>(std::abs(general[i] - exact)) / scale);
      }
  }
  std::printf("q̈ against Newton's law, relative to the largest |q̈|: constant M %.2e, general %.2e\n", worst_fast,
              worst_general);
  EXPECT_LE(worst_fast, 1e-15);
  EXPECT_LE(worst_general, 1e-15);
}

/// Two carts on a line joined by a spring, their kinetic energy with a
/// cross term and a term linear in the velocities (a gyroscopic-free b:
/// constant, so it changes p but not the motion):
///   T = ½ m₁ ẋ₁² + ½ m₂ ẋ₂² + c ẋ₁ẋ₂ + b ẋ₁,  V = ½ k (x₂ − x₁ − l)².
/// M = [[m₁, c], [c, m₂]], so M q̈ = −∂V/∂q.
struct CoupledCarts {
  static constexpr int coordinate_count = 2;
  static constexpr bool constant_mass_matrix = true;
  double m1 = 2, m2 = 3, c = 0.5, b = 0.7, k = 40, l = 1;
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * m1 * qd[0] * qd[0] + 0.5 * m2 * qd[1] * qd[1] + c * qd[0] * qd[1] + b * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 2>& q, const S&) const {
    const S s = q[1] - q[0] - l;
    return 0.5 * k * s * s;
  }
};

TEST(ConstantMass, ACrossTermInTIsSolvedWithTheFullMassMatrix) {
  const CoupledCarts carts;
  const Vec<double, 2> q(0.1, 1.4), qd(0.3, -0.2);
  // −∂V/∂q = k s (1, −1), s = x₂ − x₁ − l; Cramer's rule for M q̈ = that.
  const double s = q[1] - q[0] - carts.l, f0 = carts.k * s, f1 = -carts.k * s;
  const double det = carts.m1 * carts.m2 - carts.c * carts.c;
  const Vec<double, 2> exact((carts.m2 * f0 - carts.c * f1) / det, (carts.m1 * f1 - carts.c * f0) / det);
  const Vec<double, 2> fast = fast_qdd(carts, q, qd, 0.0);
  EXPECT_LE((fast - exact).norm(), 1e-14 * exact.norm());
  EXPECT_LE((accelerations(General(carts), q, qd, 0.0) - exact).norm(), 1e-14 * exact.norm());
}

/// Three coupled oscillators, T = ½ q̇ᵀ M q̇ and V = ½ qᵀ K q with a full
/// (tridiagonal) M: q̈ = −M⁻¹ K q, here against Eigen's LU solve.
struct CoupledOscillators {
  static constexpr int coordinate_count = 3;
  static constexpr bool constant_mass_matrix = true;
  Eigen::Matrix3d M{{2.0, 0.3, 0.0}, {0.3, 3.0, 0.2}, {0.0, 0.2, 1.0}};
  Eigen::Matrix3d K{{5.0, -1.0, 0.0}, {-1.0, 4.0, -2.0}, {0.0, -2.0, 3.0}};
  template <class S>
  S kinetic(const Vec<S, 3>&, const Vec<S, 3>& qd, const S&) const {
    S t = S(0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) t += 0.5 * M(i, j) * qd[i] * qd[j];
    return t;
  }
  template <class S>
  S potential(const Vec<S, 3>& q, const S&) const {
    S v = S(0);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) v += 0.5 * K(i, j) * q[i] * q[j];
    return v;
  }
};

TEST(ConstantMass, AFullMassMatrixIsFactoredOnce) {
  const CoupledOscillators model;
  const Vec<double, 3> q(0.3, -0.7, 1.1), qd(0.2, 0.1, -0.4);
  const Eigen::Vector3d exact = model.M.lu().solve(-(model.K * q));
  EXPECT_LE((fast_qdd(model, q, qd, 0.0) - exact).norm(), 1e-14 * exact.norm());
}

TEST(ConstantMass, RunsAgreeWithAndWithoutTheDeclaration) {
  // The projectile with quadratic drag (forces from the Rayleigh function),
  // the pendulum and a bouncing ball: the same run, declared and withdrawn.
  SimulationOptions o;
  o.method = Method::dopri5;
  o.rtol = 1e-11;
  o.atol = 1e-13;
  o.t_end = 3.0;
  o.output_interval = 0.5;
  const auto compare = [&](const auto& model, const auto& x0) {
    constexpr int n = coordinate_count_v<std::decay_t<decltype(model)>>;
    Recorder<n> a, b;
    simulate(model, x0, o, a);
    simulate(General(model), x0, o, b);
    EXPECT_EQ(a.samples.size(), b.samples.size());
    double worst = a.samples.size() == b.samples.size() ? 0.0 : 1.0;
    for (std::size_t i = 0; i < std::min(a.samples.size(), b.samples.size()); ++i)
      worst = std::max({worst, (a.samples[i].q - b.samples[i].q).norm(), (a.samples[i].qd - b.samples[i].qd).norm()});
    return worst;
  };
  State<2> ball;
  ball.q << 0, 0;
  ball.qd << 12, 9;
  const double drag = compare(lm::Projectile<lm::Drag::quadratic>(0.5, 9.81, 0.0, 0.02), ball);
  State<1> swing;
  swing.q << 2.5;
  swing.qd << 0;
  const double pendulum = compare(lm::SimplePendulum(1.0, 0.8, 9.81), swing);
  // A ball bouncing on a tilted plane (e = 0.8): free flight between the
  // contacts on the constant-M path, each impact by the constrained one.
  State<3> ball3;
  ball3.q << 0, 0, 1;
  ball3.qd << 0.5, -0.2, 0;
  const double bounces = compare(lm::BallAndPlane(1.0, 0.1, 0.8, 9.81, {0.1, 0.0, 1.0}), ball3);
  std::printf("declared against withdrawn: projectile with drag %.2e, pendulum %.2e, bouncing ball %.2e\n", drag,
              pendulum, bounces);
  EXPECT_LE(drag, 1e-12);
  EXPECT_LE(pendulum, 1e-12);
  EXPECT_LE(bounces, 1e-10);
}

/// The double pendulum (T depends on θ₁ − θ₂), declared constant.
struct Declared : lm::DoublePendulum {
  static constexpr bool constant_mass_matrix = true;
  Declared() : lm::DoublePendulum() {}
};

/// T = m c² (1 − √(1 − ẋ²/c²)): depends on ẋ alone but is not quadratic.
struct Relativistic {
  static constexpr int coordinate_count = 1;
  static constexpr bool constant_mass_matrix = true;
  double m = 1, c = 3;
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S&) const {
    using std::sqrt;
    return m * c * c * (1.0 - sqrt(1.0 - qd[0] * qd[0] / (c * c)));
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    return 0.5 * q[0] * q[0];
  }
};

/// T = ½ m₀ (1 + t) ẋ²: the coefficient of ẋ changes with t.
struct Growing {
  static constexpr int coordinate_count = 1;
  static constexpr bool constant_mass_matrix = true;
  template <class S>
  S kinetic(const Vec<S, 1>&, const Vec<S, 1>& qd, const S& t) const {
    return 0.5 * (1.0 + t) * qd[0] * qd[0];
  }
  template <class S>
  S potential(const Vec<S, 1>& q, const S&) const {
    return 0.5 * q[0] * q[0];
  }
};

/// A ball on a plane whose inertia grows with height: a contact model that
/// inherits the declaration but breaks it.
struct HeavierHigher : lm::BallAndPlane {
  HeavierHigher() : lm::BallAndPlane() {}
  template <class S>
  S kinetic(const Vec<S, 3>& q, const Vec<S, 3>& qd, const S&) const {
    return 0.5 * m * (1.0 + 0.1 * q[2] * q[2]) * (qd[0] * qd[0] + qd[1] * qd[1] + qd[2] * qd[2]);
  }
};

// False declarations: each stops the run at its start with a DynamicsError
// naming the declaration and what is wrong.
template <class M>
std::string failure(const M& model, const State<coordinate_count_v<M>>& x0) {
  SimulationOptions o;
  o.t_end = 1.0;
  try {
    simulate(model, x0, o);
  } catch (const DynamicsError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(ConstantMass, ADoublePendulumDeclaredConstantIsRefused) {
  // T depends on θ₁ − θ₂; started with θ₁ = θ₂, where dT/dq vanishes at
  // the first state, so only the check at a shifted configuration sees it.
  State<2> x0;
  x0.q << 0.4, 0.4;
  x0.qd << 0, 0;
  const std::string what = failure(Declared{}, x0);
  EXPECT_NE(what.find("declares constant_mass_matrix"), std::string::npos) << what;
  EXPECT_NE(what.find("dT/dq[0] is not zero"), std::string::npos) << what;
}

TEST(ConstantMass, AContactModelsDeclarationIsCheckedToo) {
  // Contacts only: the free motion between them takes the constant-M path,
  // so the declaration is checked before the run as for any model.
  State<3> x0;
  x0.q << 0, 0, 1;
  x0.qd << 0, 0, 0;
  const std::string what = failure(HeavierHigher{}, x0);
  EXPECT_NE(what.find("declares constant_mass_matrix"), std::string::npos) << what;
  EXPECT_NE(what.find("T's coefficient of qd[0] changes with q or t"), std::string::npos) << what;
}

TEST(ConstantMass, ARelativisticKineticEnergyDeclaredConstantIsRefused) {
  State<1> x0;
  x0.q << 1;
  x0.qd << 0;
  const std::string what = failure(Relativistic{}, x0);
  EXPECT_NE(what.find("its mass matrix M = d2T/dqd2 changes with the state"), std::string::npos) << what;
}

TEST(ConstantMass, AMassChangingInTimeDeclaredConstantIsRefused) {
  State<1> x0;
  x0.q << 1;
  x0.qd << 0;
  const std::string what = failure(Growing{}, x0);
  EXPECT_NE(what.find("T's coefficient of qd[0] changes with q or t"), std::string::npos) << what;
}

}  // namespace
