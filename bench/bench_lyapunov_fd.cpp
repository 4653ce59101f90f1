// Lyapunov exponents at equal accuracy: the variational equations by AD
// (lyapunov_spectrum()) against finite differences of plain runs, the way
// one would compute them without derivatives: the state and k nearby
// copies of it, 1 + k runs of simulate() (2n + 1 = 5 for the whole spectrum
// of the double pendulum), the copies' differences renormalised by
// Gram–Schmidt (a QR factorisation) every `tau` seconds.
//
// The motion: the chaotic double pendulum (θ1 = θ2 = 2 rad from rest) over
// T = 10 s, dopri5, atol = rtol / 100. Both methods measure the tangent
// vectors in the canonical coordinates (q, p), p = ∂L/∂q̇, and start them
// along the first k unit vectors of (δq, δp), so both estimate the same
// finite-time exponents: (1/T) log R_jj of the QR factorisation of the
// first k columns of ∂(q, p)(T)/∂(q, p)(0), which do not depend on when
// the renormalisations happen (the product of the R factors is the R factor
// of the product). The reference is lyapunov_spectrum() at rtol 1e-13; its
// distance to the same at 1e-12 is printed as its own uncertainty.
//
// Finite differences: a copy starts at (q, p) + ε e_j and after each interval
// its difference from the state, ((q_j − q), (p_j − p)) / ε, is one column
// of D = QR; log R_jj is added to sum j and the copies restart at
// (q + ε Q_qj, p + ε Q_pj), their velocities from p = M(q) q̇. The error of
// the estimate has two parts, one growing with ε (the flow is not linear
// over a distance ε) and one with rtol / ε (each run's own integration error
// divided by ε): every ε in a range is tried at every rtol.
//
// Printed: every run (time, error against the reference, runs' steps), then
// for each accuracy the cheapest run of each method that reaches it, with
// the plain run's time at the same rtol. Times: the fastest of REPEATS
// runs, all in this process (docs/performance.md).
// Usage: bench_lyapunov_fd [REPEATS] (default 3)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/QR>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/integrate/observers.hpp"
#include "lagrangian/integrate/simulate.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace {

using lagrangian::models::DoublePendulum;
using State = lagrangian::State<2>;
using Vec2 = lagrangian::Vec<double, 2>;
using Vec4 = Eigen::Matrix<double, 4, 1>;

constexpr double kT = 10.0;

lagrangian::SimulationOptions run_options(double rtol, double t0, double t_end) {
  lagrangian::SimulationOptions o;
  o.method = lagrangian::Method::dopri5;
  o.rtol = rtol;
  o.atol = rtol / 100;
  o.t0 = t0;
  o.t_end = t_end;
  o.output_interval = -1;  // the first and last states only
  return o;
}

/// The state at t_end of a plain run from `s` at t0; adds its steps.
State advance(const DoublePendulum& model, const State& s, double rtol, double t0, double t_end,
              unsigned long long& steps) {
  lagrangian::Recorder<2> rec;
  const lagrangian::RunReport r = lagrangian::simulate(model, s, run_options(rtol, t0, t_end), rec);
  steps += r.steps;
  State out;
  out.q = rec.samples.back().q;
  out.qd = rec.samples.back().qd;
  return out;
}

/// (q, p) of a state.
Vec4 canonical(const DoublePendulum& model, const State& s) {
  Vec4 z;
  z << s.q, lagrangian::momenta(model, s.q, s.qd);
  return z;
}

/// The state at (q, p): q̇ = M(q)⁻¹ p.
State from_canonical(const DoublePendulum& model, const Vec4& z) {
  State s;
  s.q = z.head<2>();
  const Vec2 zero = Vec2::Zero();
  s.qd = lagrangian::mass_matrix(model, s.q, zero).lu().solve(Vec2(z.tail<2>()));
  return s;
}

struct Estimate {
  std::vector<double> spectrum;
  unsigned long long steps = 0;  // accepted steps of all the runs
  double seconds = 0;
};

/// Benettin's method on 1 + k plain runs: the copies' differences over ε.
Estimate finite_differences(const DoublePendulum& model, const State& s0, int k, double rtol, double eps, double tau) {
  Estimate e;
  std::vector<double> sums(static_cast<std::size_t>(k), 0.0);
  State x = s0;
  std::vector<State> copies;
  const Vec4 z0 = canonical(model, s0);
  for (int j = 0; j < k; ++j)  // along the first k unit vectors of (δq, δp)
    copies.push_back(from_canonical(model, z0 + eps * Vec4::Unit(j)));
  Eigen::Matrix<double, 4, Eigen::Dynamic> d(4, k);
  for (double t = 0; t < kT * (1 - 1e-12);) {
    const double t_next = std::min(kT, t + tau);
    x = advance(model, x, rtol, t, t_next, e.steps);
    const Vec4 z = canonical(model, x);
    for (int j = 0; j < k; ++j) {
      State& c = copies[static_cast<std::size_t>(j)];
      c = advance(model, c, rtol, t, t_next, e.steps);
      d.col(j) = (canonical(model, c) - z) / eps;
    }
    const Eigen::HouseholderQR<Eigen::Matrix<double, 4, Eigen::Dynamic>> qr(d);
    const Eigen::MatrixXd r = qr.matrixQR().topRows(k).triangularView<Eigen::Upper>();
    const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(4, k);
    for (int j = 0; j < k; ++j) {
      sums[static_cast<std::size_t>(j)] += std::log(std::abs(r(j, j)));
      copies[static_cast<std::size_t>(j)] = from_canonical(model, z + eps * Vec4(q.col(j)));
    }
    t = t_next;
  }
  for (double s : sums) e.spectrum.push_back(s / kT);
  std::sort(e.spectrum.begin(), e.spectrum.end(), std::greater<>());
  return e;
}

Estimate variational(const DoublePendulum& model, const State& s0, int k, double rtol) {
  lagrangian::LyapunovOptions o;
  o.run = run_options(rtol, 0.0, kT);
  o.exponents = k;
  const lagrangian::LyapunovResult r = lagrangian::lyapunov_spectrum(model, s0, o);
  Estimate e;
  e.spectrum = r.spectrum;
  e.steps = r.steps;
  e.seconds = r.seconds;
  return e;
}

double error_of(const Estimate& e, const std::vector<double>& reference) {
  double worst = 0;
  for (std::size_t j = 0; j < e.spectrum.size(); ++j)
    worst = std::max(worst, std::abs(e.spectrum[j] - reference[j]));
  return worst;
}

/// The fastest of `repeats` calls of `f` (its result kept from the last).
template <class F>
Estimate fastest(int repeats, F&& f) {
  Estimate best;
  double seconds = std::numeric_limits<double>::infinity();
  for (int r = 0; r < repeats; ++r) {
    const auto start = std::chrono::steady_clock::now();
    best = f();
    seconds = std::min(seconds, std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  best.seconds = seconds;
  return best;
}

struct Row {
  int k;
  bool fd;
  double rtol, eps, seconds, error;
  unsigned long long steps;
};

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 3;
  const DoublePendulum model;
  State s0;
  s0.q << 2.0, 2.0;
  s0.qd << 0.0, 0.0;
  const double tau = 0.5;
  const std::vector<double> rtols = {1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12};
  const std::vector<double> epsilons = {1e-4, 1e-5, 1e-6, 1e-7, 1e-8};

  std::printf("double pendulum from (2, 2) rad at rest, T = %g s, dopri5, atol = rtol/100; finite differences "
              "renormalised every %g s\n", kT, tau);
  std::vector<double> plain(rtols.size());
  for (std::size_t i = 0; i < rtols.size(); ++i) {
    const Estimate p = fastest(repeats, [&] {
      Estimate e;
      (void)advance(model, s0, rtols[i], 0.0, kT, e.steps);
      return e;
    });
    plain[i] = p.seconds;
    std::printf("plain run, rtol %.0e: %.3f ms, %llu steps\n", rtols[i], 1e3 * p.seconds, p.steps);
  }
  std::vector<Row> rows;
  for (int k : {1, 4}) {
    const std::vector<double> reference = variational(model, s0, k, 1e-13).spectrum;
    const std::vector<double> check = variational(model, s0, k, 1e-12).spectrum;
    std::printf("\nk = %d: reference (rtol 1e-13)", k);
    for (double l : reference) std::printf(" %.10f", l);
    std::printf(" 1/s; rtol 1e-12 differs by %.1e\n", error_of(Estimate{check, 0, 0}, reference));
    for (std::size_t i = 0; i < rtols.size(); ++i) {
      const Estimate v = fastest(repeats, [&] { return variational(model, s0, k, rtols[i]); });
      rows.push_back({k, false, rtols[i], 0, v.seconds, error_of(v, reference), v.steps});
      std::printf("  variational, rtol %.0e: %8.3f ms (%5.1fx the plain run), error %.1e, %llu steps\n", rtols[i],
                  1e3 * v.seconds, v.seconds / plain[i], rows.back().error, v.steps);
      for (double eps : epsilons) {
        const Estimate f = fastest(repeats, [&] { return finite_differences(model, s0, k, rtols[i], eps, tau); });
        rows.push_back({k, true, rtols[i], eps, f.seconds, error_of(f, reference), f.steps});
        std::printf("  differences, rtol %.0e, eps %.0e: %8.3f ms (%5.1fx), error %.1e, %llu steps\n", rtols[i], eps,
                    1e3 * f.seconds, f.seconds / plain[i], rows.back().error, f.steps);
      }
    }
  }
  std::printf("\nthe cheapest run of each method within an error (1/s, the largest over the k exponents):\n");
  for (int k : {1, 4}) {
    for (double target : {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8}) {
      const Row* best[2] = {nullptr, nullptr};
      for (const Row& r : rows) {
        if (r.k != k || r.error > target) continue;
        const Row*& b = best[r.fd ? 1 : 0];
        if (b == nullptr || r.seconds < b->seconds) b = &r;
      }
      std::printf("  k = %d, error <= %.0e:", k, target);
      if (best[0] != nullptr)
        std::printf(" variational %.3f ms (rtol %.0e)", 1e3 * best[0]->seconds, best[0]->rtol);
      else
        std::printf(" variational: none");
      if (best[1] != nullptr)
        std::printf(", differences %.3f ms (rtol %.0e, eps %.0e)", 1e3 * best[1]->seconds, best[1]->rtol,
                    best[1]->eps);
      else
        std::printf(", differences: none");
      if (best[0] != nullptr && best[1] != nullptr)
        std::printf(": differences / variational %.2f", best[1]->seconds / best[0]->seconds);
      std::printf("\n");
    }
  }
}
