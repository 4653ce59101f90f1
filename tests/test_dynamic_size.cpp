// Models whose number of coordinates is known only at run time agree with
// the same models written with a compile-time size.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "runtime_chain.hpp"

namespace {

using namespace lagrangian;

using test_models::RuntimeChain;

template <int N>
void compare_with_fixed(std::mt19937_64& rng) {
  const models::PendulumChain<N> fixed(1.0, 1.0, 9.81);
  const RuntimeChain dyn{N};
  const State<N> s = test_models::random_chain_state<N>(rng);
  const Vec<double, N> q = s.q, qd = s.qd;
  const Eigen::VectorXd qx = q, qdx = qd;
  const double scale = accelerations(fixed, q, qd).template lpNorm<Eigen::Infinity>();
  EXPECT_LE((accelerations(dyn, qx, qdx) - accelerations(fixed, q, qd)).template lpNorm<Eigen::Infinity>(),
            1e-11 * scale)
      << "n = " << N;
  EXPECT_LE((mass_matrix(dyn, qx, qdx) - mass_matrix(fixed, q, qd)).norm(), 1e-12 * mass_matrix(fixed, q, qd).norm())
      << "n = " << N;
  EXPECT_LE((momenta(dyn, qx, qdx) - momenta(fixed, q, qd)).norm(), 1e-12 * momenta(fixed, q, qd).norm());
  EXPECT_NEAR(energy_function(dyn, qx, qdx), energy_function(fixed, q, qd), 1e-12 * std::abs(energy_function(fixed, q, qd)));
}

TEST(DynamicSize, DerivativesMatchFixedSizeAcrossBlockBoundaries) {
  std::mt19937_64 rng(99);
  compare_with_fixed<1>(rng);
  compare_with_fixed<3>(rng);
  compare_with_fixed<4>(rng);
  compare_with_fixed<5>(rng);
}

TEST(DynamicSize, NineLinksMatchTheChainsClosedForm) {
  // Three coordinate blocks (a full one between two others): against the
  // equal-mass chain written out (0-based i, j; c_ij = n − max(i, j) masses
  // hang at or below both links i and j):
  //   M_ij = m l² c_ij cos(θi − θj),  p = M θ̇,
  //   Σ_j M_ij θ̈j = −Σ_j m l² c_ij sin(θi − θj) θ̇j² − m g l (n − i) sin θi,
  //   h = ½ θ̇ᵀ M θ̇ − m g l Σ_i (n − i) cos θi.
  constexpr int n = 9;
  const RuntimeChain dyn{n};
  std::mt19937_64 rng(7);
  const State<n> s = test_models::random_chain_state<n>(rng);
  const Eigen::VectorXd q = s.q, qd = s.qd;
  const double m = dyn.m, l = dyn.l, g = dyn.g;
  Eigen::MatrixXd M(n, n);
  Eigen::VectorXd Q(n);
  double V = 0;
  for (int i = 0; i < n; ++i) {
    Q[i] = -m * g * l * (n - i) * std::sin(q[i]);
    V -= m * g * l * (n - i) * std::cos(q[i]);
    for (int j = 0; j < n; ++j) {
      const double c = n - std::max(i, j);
      M(i, j) = m * l * l * c * std::cos(q[i] - q[j]);
      Q[i] -= m * l * l * c * std::sin(q[i] - q[j]) * qd[j] * qd[j];
    }
  }
  EXPECT_LE((mass_matrix(dyn, q, qd) - M).norm(), 1e-12 * M.norm());
  EXPECT_LE((momenta(dyn, q, qd) - M * qd).norm(), 1e-12 * (M * qd).norm());
  EXPECT_LE((M * accelerations(dyn, q, qd) - Q).norm(), 1e-11 * Q.norm());
  const double h = 0.5 * qd.dot(M * qd) + V;
  EXPECT_NEAR(energy_function(dyn, q, qd), h, 1e-12 * (std::abs(h) + std::abs(V)));
}

TEST(DynamicSize, SimulationMatchesFixedSize) {
  constexpr int n = 3;  // the library's PendulumChain<3>
  const models::PendulumChain<n> fixed;
  const RuntimeChain dyn{n};
  State<n> x0;
  State<Dynamic> y0(n);
  for (int i = 0; i < n; ++i) {
    x0.q[i] = y0.q[i] = 0.3 - 0.15 * i;
  }
  for (const std::string method : {"dopri5", "rk4", "gauss_radau15", "rosenbrock4"}) {
    SimulationOptions o;
    o.method = method;
    o.t_end = 2.0;
    o.output_interval = 0.5;
    Recorder<n> a;
    Recorder<Dynamic> b;
    const RunReport ra = simulate(fixed, x0, o, a);
    const RunReport rb = simulate(dyn, y0, o, b);
    ASSERT_EQ(a.samples.size(), b.samples.size()) << method;
    for (std::size_t k = 0; k < a.samples.size(); ++k)
      EXPECT_LE((a.samples[k].q - Vec<double, n>(b.samples[k].q)).norm(), 1e-8) << method << " t = " << a.samples[k].t;
    EXPECT_LE(rb.energy_drift_max, 1e-7) << method;
    EXPECT_EQ(rb.coordinates.size(), static_cast<std::size_t>(n));
  }
}

TEST(DynamicSize, DissipationIsDifferentiatedBlockwise) {
  test_models::DampedRuntimeChain dyn{{6}};
  dyn.c = 0.7;
  Eigen::VectorXd q = Eigen::VectorXd::LinSpaced(6, 0.1, 0.6), qd = Eigen::VectorXd::LinSpaced(6, -1.0, 1.5);
  EXPECT_LE((nonconservative_forces(dyn, q, qd) + dyn.c * qd).norm(), 1e-14);
  State<Dynamic> s(6);
  s.q = q;
  s.qd = qd;
  SimulationOptions o;
  o.t_end = 5.0;
  const RunReport r = simulate(dyn, s, o);
  EXPECT_FALSE(r.conservative);
}

TEST(DynamicSize, StateSizeMismatchIsAClearError) {
  const RuntimeChain dyn{4};
  State<Dynamic> s(3);
  try {
    simulate(dyn, s, SimulationOptions{});
    FAIL() << "no error";
  } catch (const OptionError& e) {
    EXPECT_STREQ(e.what(), "initial state has 3 coordinates and 3 velocities; the model has 4");
  }
}

}  // namespace
