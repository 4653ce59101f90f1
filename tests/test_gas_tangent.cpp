// The tangent flow of the event-driven hard-sphere engine
// (scene/hard_spheres_tangent.hpp): its state transition matrix against a
// closed form and against central differences of plain runs, the
// exponents' sum against Liouville's theorem (0 when elastic, (2/T) Σ ln e
// over the impacts when not), the conjugate pairing and the two zero
// exponents of an elastic gas, and MEGNO of a regular motion.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/scene/hard_spheres.hpp"
#include "lagrangian/scene/hard_spheres_tangent.hpp"

namespace {

using lagrangian::HardSphere;
using lagrangian::HardSphereOptions;
using lagrangian::HardSphereSystem;

/// n spheres of radius 0.05 m on a grid of 0.2 m in the unit box (up to
/// 64; above, 125 in a box of 1.1 m), masses 1 … 2 kg, velocities of about
/// 1 m/s in directions from a fixed sequence.
HardSphereSystem gas(int n, double pair_e = 1.0, double box_e = 1.0) {
  HardSphereSystem s;
  const int m = n <= 64 ? 4 : 5;
  s.box_max = Eigen::Vector3d::Constant(n <= 64 ? 1.0 : 1.1);
  std::uint64_t state = 12345;
  auto next = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0 - 0.5;  // in [-0.5, 0.5)
  };
  for (int i = 0; i < n; ++i) {
    HardSphere h;
    h.radius = 0.05;
    h.mass = 1.0 + 0.25 * (i % 5);
    h.position = Eigen::Vector3d(0.15 + 0.2 * (i % m), 0.15 + 0.2 * ((i / m) % m), 0.15 + 0.2 * (i / (m * m)));
    h.velocity = Eigen::Vector3d(next(), next(), next()) * 2.0;
    s.spheres.push_back(h);
  }
  s.pair_restitution = pair_e;
  s.box_restitution = box_e;
  return s;
}

/// Three spheres of radius 0.1 m, 1, 1.5 and 2 kg, in a box of 0.6 m:
/// crowded enough for impacts between them every few tenths of a second.
HardSphereSystem crowded(double pair_e = 1.0, double box_e = 1.0) {
  HardSphereSystem s;
  s.box_max = Eigen::Vector3d::Constant(0.6);
  const Eigen::Vector3d at[3] = {{0.15, 0.15, 0.15}, {0.45, 0.2, 0.35}, {0.25, 0.45, 0.42}};
  const Eigen::Vector3d v[3] = {{1.1, 0.7, -0.4}, {-0.8, 0.9, 0.6}, {0.5, -1.2, -0.7}};
  for (int i = 0; i < 3; ++i) {
    HardSphere h;
    h.radius = 0.1;
    h.mass = 1.0 + 0.5 * i;
    h.position = at[i];
    h.velocity = v[i];
    s.spheres.push_back(h);
  }
  s.pair_restitution = pair_e;
  s.box_restitution = box_e;
  return s;
}

HardSphereOptions over(double t_end, double output_interval = 0.0) {
  HardSphereOptions o;
  o.t_end = t_end;
  o.output_interval = output_interval;
  return o;
}

/// x(t_end) = (r, v) of a plain run.
Eigen::VectorXd final_state(const HardSphereSystem& s, const HardSphereOptions& o) {
  const int n = static_cast<int>(s.spheres.size());
  Eigen::VectorXd x(6 * n);
  lagrangian::run_hard_spheres(s, o, [&](double, const std::vector<HardSphere>& spheres) {
    for (int i = 0; i < n; ++i) {
      x.segment<3>(3 * i) = spheres[static_cast<std::size_t>(i)].position;
      x.segment<3>(3 * n + 3 * i) = spheres[static_cast<std::size_t>(i)].velocity;
    }
  });
  return x;
}

/// The start moved by h along state coordinate j.
HardSphereSystem moved(HardSphereSystem s, int j, double h) {
  const int n = static_cast<int>(s.spheres.size());
  HardSphere& b = s.spheres[static_cast<std::size_t>((j % (3 * n)) / 3)];
  (j < 3 * n ? b.position : b.velocity)[j % 3] += h;
  return s;
}

// One sphere in a box: between its walls each coordinate flies freely and is
// reflected, so ∂r(T)/∂r0 = D, ∂r/∂v0 = T D, ∂v/∂v0 = D, ∂v/∂r0 = 0 with
// D = diag(±1): −1 on the axes with an odd number of bounces (the sign of
// v_k(T)/v_k(0) in the plain run).
TEST(GasTangent, OneSphereInABoxHasTheClosedFormTransitionMatrix) {
  HardSphereSystem s;
  HardSphere h;
  h.radius = 0.1;
  h.position = Eigen::Vector3d(0.3, 0.6, 0.45);
  h.velocity = Eigen::Vector3d(2.3, -1.7, 0.9);
  s.spheres.push_back(h);
  const double T = 1.0;
  const lagrangian::SensitivityResult r = lagrangian::scene::sensitivities_hard_spheres(s, over(T));
  const Eigen::VectorXd x = final_state(s, over(T));
  Eigen::Matrix3d D = Eigen::Matrix3d::Zero();
  for (int k = 0; k < 3; ++k) D(k, k) = x[3 + k] / h.velocity[k] > 0 ? 1.0 : -1.0;
  EXPECT_LT(D.trace(), 3.0);  // the motion bounced off some walls an odd number of times
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(6, 6);
  expected.block<3, 3>(0, 0) = D;
  expected.block<3, 3>(0, 3) = T * D;
  expected.block<3, 3>(3, 3) = D;
  ASSERT_EQ(r.sensitivities.size(), 2u);
  EXPECT_GT(r.impacts, 4);
  EXPECT_LT((r.sensitivities.back() - expected).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((r.states.back() - x).cwiseAbs().maxCoeff(), 1e-15);
}

/// Largest |Φ − Φ_fd| over max |Φ|, Φ_fd by central differences of plain
/// runs with step h along each of the 6N start coordinates.
double against_differences(const HardSphereSystem& s, const HardSphereOptions& o, double h) {
  const lagrangian::SensitivityResult r = lagrangian::scene::sensitivities_hard_spheres(s, o);
  const Eigen::MatrixXd& phi = r.sensitivities.back();
  double worst = 0;
  for (int j = 0; j < phi.cols(); ++j) {
    const Eigen::VectorXd fd = (final_state(moved(s, j, h), o) - final_state(moved(s, j, -h), o)) / (2 * h);
    worst = std::max(worst, (phi.col(j) - fd).cwiseAbs().maxCoeff());
  }
  return worst / phi.cwiseAbs().maxCoeff();
}

/// Impacts of a plain run: between two spheres, and in all.
std::pair<int, int> impacts(const HardSphereSystem& s, const HardSphereOptions& o) {
  std::pair<int, int> count{0, 0};
  lagrangian::run_hard_spheres(s, o, {}, [&](const lagrangian::HardSphereImpact& e) {
    count.first += e.b >= 0 ? 1 : 0;
    ++count.second;
  });
  return count;
}

// Twelve spheres of unequal masses, elastic and inelastic (e = 0.8 between
// spheres, 0.9 at the walls), with impacts between spheres and at the
// walls: every column of the transition matrix against central
// differences of the engine's own runs (no impact changes order over ±h).
TEST(GasTangent, TransitionMatrixMatchesCentralDifferences) {
  const HardSphereOptions o = over(1.2);
  for (const HardSphereSystem& s : {gas(12), gas(12, 0.8, 0.9)}) {
    const auto [pairs, all] = impacts(s, o);
    EXPECT_GE(pairs, 3) << "e = " << s.pair_restitution;
    EXPECT_GE(all - pairs, 10) << "e = " << s.pair_restitution;
    EXPECT_LT(against_differences(s, o, 1e-7), 1e-7) << "e = " << s.pair_restitution;
  }
}

// MEGNO against its definition evaluated by brute force: ℓ(t) = ln |Φ(t) e₁|
// sampled every 0.2 ms (the transition matrix at the samples), Y(t) =
// (2/t) ∫₀ᵗ s dℓ = 2 (ℓ(t) − (1/t) ∫₀ᵗ ℓ) and ⟨Y⟩ = (1/T) ∫₀ᵀ Y, the
// integrals by the trapezoid rule (ℓ jumps at each impact: the samples'
// spacing bounds the error).
TEST(GasTangent, MegnoIsItsDefinition) {
  for (const HardSphereSystem& s : {crowded(), crowded(0.8, 0.9)}) {
    const double T = 4.0;
    const auto [pairs, all] = impacts(s, over(T));
    EXPECT_GE(pairs, 6) << "e = " << s.pair_restitution << ", " << all << " impacts";
    const lagrangian::LyapunovResult r = lagrangian::scene::lyapunov_hard_spheres(s, over(T), 1);
    const lagrangian::SensitivityResult phi = lagrangian::scene::sensitivities_hard_spheres(s, over(T, 2e-4));
    double area = 0, mean = 0, y_last = 0, ell_last = 0;
    for (std::size_t i = 1; i < phi.times.size(); ++i) {
      const double t = phi.times[i], dt = t - phi.times[i - 1];
      const double ell = std::log(phi.sensitivities[i].col(0).norm());
      area += 0.5 * (ell + ell_last) * dt;
      const double y = 2.0 * (ell - area / t);
      mean += 0.5 * (y + y_last) * dt;
      ell_last = ell;
      y_last = y;
    }
    mean /= T;
    EXPECT_GT(std::abs(y_last), 1.0) << "e = " << s.pair_restitution;
    EXPECT_NEAR(r.megno, y_last, 2e-4 * std::abs(y_last)) << "e = " << s.pair_restitution;
    EXPECT_NEAR(r.megno_mean, mean, 2e-4 * std::abs(mean)) << "e = " << s.pair_restitution;
  }
}

// Liouville: each saltation matrix has determinant e², so the whole
// spectrum sums to (2/T) Σ ln e over the impacts — e from the plain run's
// event log (separation over approach speed, the TC model's elastic
// impacts included) — and to 0 for an elastic gas.
TEST(GasTangent, SpectrumSumIsThePhaseSpaceContraction) {
  const HardSphereSystem s = gas(12, 0.8, 0.9);
  const double T = 4.0;
  const lagrangian::LyapunovResult r = lagrangian::scene::lyapunov_hard_spheres(s, over(T));
  const lagrangian::RunReport plain = lagrangian::run_hard_spheres(s, over(T));
  double expected = 0;
  for (const lagrangian::EventRecord& e : plain.events) expected += 2 * std::log(e.separation_speed / e.approach_speed);
  expected /= T;
  ASSERT_EQ(static_cast<int>(plain.events.size()), r.impacts);
  EXPECT_GT(r.impacts, 50);
  EXPECT_LT(expected, -1.0);
  EXPECT_NEAR(r.sum, expected, 1e-12 * std::abs(expected));
  ASSERT_EQ(r.spectrum.size(), 72u);
  const lagrangian::LyapunovResult elastic = lagrangian::scene::lyapunov_hard_spheres(gas(12), over(T));
  EXPECT_LT(std::abs(elastic.sum), 1e-11);
}

// An elastic gas is Hamiltonian: its exponents pair, λ_i + λ_{6N+1−i} → 0,
// two of them (along the flow and across the energy shell) → 0, and the
// largest is positive; the largest alone (one tangent vector) is the whole
// spectrum's first.
TEST(GasTangent, ElasticGasSpectrumPairsAndHasTwoZeros) {
  const HardSphereSystem s = gas(20);
  const lagrangian::LyapunovResult r = lagrangian::scene::lyapunov_hard_spheres(s, over(200.0));
  const std::vector<double>& l = r.spectrum;
  ASSERT_EQ(l.size(), 120u);
  EXPECT_GT(l.front(), 1.0);
  double pairing = 0;
  for (std::size_t i = 0; i < l.size(); ++i) pairing = std::max(pairing, std::abs(l[i] + l[l.size() - 1 - i]));
  EXPECT_LT(pairing, 0.03 * l.front());
  std::vector<double> size(l.size());
  std::transform(l.begin(), l.end(), size.begin(), [](double x) { return std::abs(x); });
  std::sort(size.begin(), size.end());
  EXPECT_LT(size[1], 0.01 * l.front());
  EXPECT_GT(size[2], 0.05 * l.front());
  const lagrangian::LyapunovResult one = lagrangian::scene::lyapunov_hard_spheres(s, over(200.0), 1);
  ASSERT_EQ(one.spectrum.size(), 1u);
  EXPECT_NEAR(one.spectrum[0], l.front(), 1e-9 * l.front());
  EXPECT_EQ(one.impacts, r.impacts);
}

// MEGNO of a chaotic gas grows as λ1 t / 2 (its time mean, Cincotta & Simó
// 2000); of two equal spheres on one line, whose impacts only exchange
// their displacements (and a wall flips one), the first vector keeps its
// length: Y = 0 and the exponent 0.
TEST(GasTangent, MegnoOfChaoticAndOfExchangingMotions) {
  const double T = 100.0;
  const lagrangian::LyapunovResult chaotic = lagrangian::scene::lyapunov_hard_spheres(gas(20), over(T), 1);
  EXPECT_NEAR(chaotic.megno_mean / (chaotic.spectrum[0] * T / 2), 1.0, 0.05);
  HardSphereSystem s;
  HardSphere a, b;
  a.radius = b.radius = 0.1;
  a.position = Eigen::Vector3d(0.25, 0.5, 0.5);
  b.position = Eigen::Vector3d(0.7, 0.5, 0.5);
  a.velocity = Eigen::Vector3d(1.3, 0, 0);
  b.velocity = Eigen::Vector3d(-0.4, 0, 0);
  s.spheres = {a, b};
  const lagrangian::LyapunovResult line = lagrangian::scene::lyapunov_hard_spheres(s, over(T), 1);
  EXPECT_GT(line.impacts, 100);
  EXPECT_LT(std::abs(line.megno_mean), 1e-9);
  EXPECT_LT(std::abs(line.spectrum[0]), 1e-12);
}

/// `f` throws OptionError whose message contains `part`.
template <class F>
void expect_refusal(F&& f, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no OptionError (expected one naming '" << part << "')";
  } catch (const lagrangian::OptionError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(GasTangent, RefusesWhatItDoesNotDerive) {
  const HardSphereSystem s = gas(4);
  expect_refusal([&] { (void)lagrangian::scene::lyapunov_hard_spheres(s, over(1.0), 25); },
                 "exponents must be in [0, 24]");
  expect_refusal([&] { (void)lagrangian::scene::lyapunov_hard_spheres(gas(4, 0.0), over(1.0)); },
                 "pair_restitution = 0");
  expect_refusal([&] { (void)lagrangian::scene::lyapunov_hard_spheres(s, over(1.0), 0, -1.0); }, "interval must be");
  expect_refusal([&] { (void)lagrangian::scene::lyapunov_hard_spheres(gas(120), over(1.0)); }, "at most 600 vectors");
  expect_refusal([&] { (void)lagrangian::scene::sensitivities_hard_spheres(gas(120), over(1.0)); },
                 "at most 100 spheres");
}

}  // namespace
