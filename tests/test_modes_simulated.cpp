// The normal-mode frequencies of small_oscillations() against simulation:
// started at small amplitude along one mode shape, the double pendulum and
// the spring-mounted cart pendulum oscillate at the predicted frequency.
// The period is measured from interpolated zero crossings over 20 periods.
//
// The amplitude bounds the nonlinear shift. For a single pendulum the period
// grows by about θ0²/16 (relative), 6e-8 at θ0 = 1e-3 rad; the fast mode of
// the double pendulum shifts more: at a largest component of 1e-3 rad its
// period came out 9.3e-7 long, at 3e-4 rad about 11× less (the θ0² law), so
// the tests start at 3e-4, where every shift is below 1e-7. fehlberg78 at
// rtol 1e-13 keeps the integration error below that.

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "lagrangian/analysis/analysis.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/integrate/simulate.hpp"

using namespace lagrangian;
namespace lm = lagrangian::models;

namespace {

constexpr double kTwoPi = 6.283185307179586;

/// Root in [0, 1] of the cubic Hermite interpolant through (0, y0, d0) and
/// (1, y1, d1) (d scaled by the interval), by bisection.
double hermite_root(double y0, double y1, double d0, double d1) {
  auto f = [&](double s) {
    const double h00 = (1 + 2 * s) * (1 - s) * (1 - s), h10 = s * (1 - s) * (1 - s);
    const double h01 = s * s * (3 - 2 * s), h11 = s * s * (s - 1);
    return h00 * y0 + h10 * d0 + h01 * y1 + h11 * d1;
  };
  double lo = 0, hi = 1, flo = f(0);
  for (int i = 0; i < 80; ++i) {
    const double mid = 0.5 * (lo + hi), fm = f(mid);
    if ((fm < 0) == (flo < 0)) {
      lo = mid;
      flo = fm;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

/// Period of coordinate `i` from its upward zero crossings (one per period).
template <int N>
double measured_period(const std::vector<Sample<N>>& s, int i) {
  std::vector<double> up;
  for (std::size_t k = 0; k + 1 < s.size(); ++k) {
    const double y0 = s[k].q[i], y1 = s[k + 1].q[i];
    if (y0 < 0 && y1 >= 0) {
      const double h = s[k + 1].t - s[k].t;
      up.push_back(s[k].t + h * hermite_root(y0, y1, h * s[k].qd[i], h * s[k + 1].qd[i]));
    }
  }
  EXPECT_GE(up.size(), 10u);
  return (up.back() - up.front()) / static_cast<double>(up.size() - 1);
}

template <class M>
void check_mode_periods(const M& model, double amplitude) {
  constexpr int n = lagrangian::coordinate_count_v<M>;
  const Modes md = small_oscillations(model, Vec<double, n>::Zero());
  for (int j = 0; j < n; ++j) {
    const double predicted = kTwoPi / md.omega[j];
    State<n> x0;
    const Eigen::VectorXd shape = md.shapes.col(j);
    x0.q = amplitude * shape / shape.cwiseAbs().maxCoeff();
    SimulationOptions opt;
    opt.method = Method::fehlberg78;
    opt.t_end = 20.5 * predicted;
    opt.rtol = 1e-13;
    opt.atol = 1e-17;
    opt.output_interval = predicted / 400;
    Recorder<n> rec;
    simulate(model, x0, opt, rec);
    for (int i = 0; i < n; ++i) {
      const double p = measured_period(rec.samples, i);
      EXPECT_NEAR(p / predicted - 1, 0.0, 1e-6) << "mode " << j << " coordinate " << i << ": measured " << p
                                                 << " s, predicted " << predicted << " s";
      std::printf("mode %d (omega %.12g rad/s) coordinate %d: period measured %.12g s, predicted %.12g s, rel %.2e\n",
                  j, md.omega[j], i, p, predicted, p / predicted - 1);
    }
  }
}

}  // namespace

TEST(ModesSimulated, DoublePendulumOscillatesAtPredictedFrequencies) {
  const double g = 9.81, l = 1.0;
  const lm::DoublePendulum dp(1.0, 1.0, l, l, g);
  const Modes md = small_oscillations(dp, Vec<double, 2>::Zero());
  // ω² = (g/l)(2 ∓ √2) for equal masses and lengths.
  EXPECT_NEAR(md.omega_squared[0], g / l * (2 - std::sqrt(2.0)), 1e-12);
  EXPECT_NEAR(md.omega_squared[1], g / l * (2 + std::sqrt(2.0)), 1e-12);
  check_mode_periods(dp, 3e-4);
}

TEST(ModesSimulated, CartPendulumOscillatesAtPredictedFrequencies) {
  // Largest component (cart displacement or angle) 3e-4 m or rad.
  check_mode_periods(lm::CartPendulum(2.0, 1.0, 1.0, 10.0, 9.81), 3e-4);
}
