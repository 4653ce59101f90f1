// AD-derived q̈, p and M against independent hand derivations at seeded
// random states.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/LU>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/pendulums.hpp"

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

}  // namespace
