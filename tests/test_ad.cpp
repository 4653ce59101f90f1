// The AD scalar against Eigen's AutoDiffScalar and against finite differences.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <unsupported/Eigen/AutoDiff>

#include "lagrangian/ad.hpp"
#include "lagrangian/model.hpp"

namespace {

using lagrangian::ad::Jet;

// A composite function of three variables using the functions nested Eigen
// AutoDiffScalar supports.
template <class S>
S composite(const S& x, const S& y, const S& z) {
  using std::atan2;
  using std::cos;
  using std::exp;
  using std::log;
  using std::sin;
  using std::sqrt;
  return sin(x) * exp(y) + log(z) * sqrt(x * x + y * y) / (z + 1.0) + atan2(y, x) + cos(x * z) * z - y / (x * x + 2.0);
}

TEST(Jet, GradientMatchesEigenAutoDiff) {
  using E = Eigen::AutoDiffScalar<Eigen::Vector3d>;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(0.2, 2.0);
  for (int trial = 0; trial < 20; ++trial) {
    const double x = u(rng), y = u(rng), z = u(rng);
    const E ex(x, 3, 0), ey(y, 3, 1), ez(z, 3, 2);
    const E fe = composite(ex, ey, ez);
    using J = Jet<double, 3, 1>;
    const J fj = composite(J::variable(x, 0), J::variable(y, 1), J::variable(z, 2));
    EXPECT_NEAR(fj.v, fe.value(), 1e-14 * std::abs(fe.value()));
    for (int i = 0; i < 3; ++i) EXPECT_NEAR(fj.g[i], fe.derivatives()[i], 1e-13 * (1 + std::abs(fe.derivatives()[i])));
  }
}

TEST(Jet, HessianMatchesNestedEigenAutoDiff) {
  using Inner = Eigen::AutoDiffScalar<Eigen::Vector3d>;
  using Outer = Eigen::AutoDiffScalar<Eigen::Matrix<Inner, 3, 1>>;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.2, 2.0);
  for (int trial = 0; trial < 20; ++trial) {
    const double v[3] = {u(rng), u(rng), u(rng)};
    Outer o[3];
    for (int i = 0; i < 3; ++i) {
      o[i].value() = Inner(v[i], 3, i);
      o[i].derivatives().resize(3);
      for (int j = 0; j < 3; ++j) {
        o[i].derivatives()[j] = Inner(i == j ? 1.0 : 0.0);
        o[i].derivatives()[j].derivatives() = Eigen::Vector3d::Zero();  // fixed-size inner derivatives start uninitialised
      }
    }
    const Outer fe = composite(o[0], o[1], o[2]);
    using J = Jet<double, 3, 2>;
    const J fj = composite(J::variable(v[0], 0), J::variable(v[1], 1), J::variable(v[2], 2));
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(fj.g[i], fe.value().derivatives()[i], 1e-13 * (1 + std::abs(fj.g[i])));
      for (int j = 0; j < 3; ++j) {
        const double ref = fe.derivatives()[i].derivatives()[j];
        EXPECT_NEAR(fj.hess(i, j), ref, 1e-12 * (1 + std::abs(ref))) << "H(" << i << "," << j << ")";
      }
    }
  }
}

// Every <cmath> function the Jet provides, against central differences of
// the double version (first and second derivative).
TEST(Jet, UnaryFunctionsMatchFiniteDifferences) {
  using J = Jet<double, 1, 2>;
  struct Case {
    std::string name;
    std::function<double(double)> f;
    std::function<J(const J&)> fj;
    double x;
  };
  using namespace lagrangian::ad;
  const std::vector<Case> cases = {
      {"sin", [](double x) { return std::sin(x); }, [](const J& a) { return sin(a); }, 0.7},
      {"cos", [](double x) { return std::cos(x); }, [](const J& a) { return cos(a); }, 0.7},
      {"tan", [](double x) { return std::tan(x); }, [](const J& a) { return tan(a); }, 0.7},
      {"exp", [](double x) { return std::exp(x); }, [](const J& a) { return exp(a); }, 0.7},
      {"expm1", [](double x) { return std::expm1(x); }, [](const J& a) { return expm1(a); }, 0.7},
      {"log", [](double x) { return std::log(x); }, [](const J& a) { return log(a); }, 0.7},
      {"log1p", [](double x) { return std::log1p(x); }, [](const J& a) { return log1p(a); }, 0.7},
      {"log10", [](double x) { return std::log10(x); }, [](const J& a) { return log10(a); }, 0.7},
      {"log2", [](double x) { return std::log2(x); }, [](const J& a) { return log2(a); }, 0.7},
      {"sqrt", [](double x) { return std::sqrt(x); }, [](const J& a) { return sqrt(a); }, 0.7},
      {"cbrt", [](double x) { return std::cbrt(x); }, [](const J& a) { return cbrt(a); }, 0.7},
      {"asin", [](double x) { return std::asin(x); }, [](const J& a) { return asin(a); }, 0.4},
      {"acos", [](double x) { return std::acos(x); }, [](const J& a) { return acos(a); }, 0.4},
      {"atan", [](double x) { return std::atan(x); }, [](const J& a) { return atan(a); }, 0.7},
      {"sinh", [](double x) { return std::sinh(x); }, [](const J& a) { return sinh(a); }, 0.7},
      {"cosh", [](double x) { return std::cosh(x); }, [](const J& a) { return cosh(a); }, 0.7},
      {"tanh", [](double x) { return std::tanh(x); }, [](const J& a) { return tanh(a); }, 0.7},
      {"asinh", [](double x) { return std::asinh(x); }, [](const J& a) { return asinh(a); }, 0.7},
      {"acosh", [](double x) { return std::acosh(x); }, [](const J& a) { return acosh(a); }, 1.7},
      {"atanh", [](double x) { return std::atanh(x); }, [](const J& a) { return atanh(a); }, 0.4},
      {"abs(-)", [](double x) { return std::abs(x); }, [](const J& a) { return abs(a); }, -0.7},
      {"pow int 3", [](double x) { return std::pow(x, 3); }, [](const J& a) { return pow(a, 3); }, 0.7},
      {"pow int -2", [](double x) { return std::pow(x, -2); }, [](const J& a) { return pow(a, -2); }, 0.7},
      {"pow 2.5", [](double x) { return std::pow(x, 2.5); }, [](const J& a) { return pow(a, 2.5); }, 0.7},
      {"pow base", [](double x) { return std::pow(1.7, x); }, [](const J& a) { return pow(1.7, a); }, 0.7},
      {"pow jet^jet", [](double x) { return std::pow(x, x); }, [](const J& a) { return pow(a, a); }, 0.7},
      {"atan2(y,c)", [](double x) { return std::atan2(x, -0.3); }, [](const J& a) { return atan2(a, -0.3); }, 0.7},
      {"atan2(c,x)", [](double x) { return std::atan2(0.3, x); }, [](const J& a) { return atan2(0.3, a); }, -0.7},
      {"hypot", [](double x) { return std::hypot(x, 2 * x + 1); }, [](const J& a) { return hypot(a, 2.0 * a + 1.0); },
       0.7},
      {"1/x", [](double x) { return 1.0 / x; }, [](const J& a) { return 1.0 / a; }, 0.7},
  };
  for (const Case& c : cases) {
    const double h = 1e-4;
    const double f0 = c.f(c.x), fp = c.f(c.x + h), fm = c.f(c.x - h), fp2 = c.f(c.x + 2 * h), fm2 = c.f(c.x - 2 * h);
    const double d1 = (8 * (fp - fm) - (fp2 - fm2)) / (12 * h);           // O(h⁴)
    const double d2 = (16 * (fp + fm) - (fp2 + fm2) - 30 * f0) / (12 * h * h);  // O(h⁴), rounding ~1e-8
    const J r = c.fj(J::variable(c.x, 0));
    EXPECT_NEAR(r.v, f0, 1e-15 * (1 + std::abs(f0))) << c.name;
    EXPECT_NEAR(r.g[0], d1, 1e-9 * (1 + std::abs(d1))) << c.name;
    EXPECT_NEAR(r.hess(0, 0), d2, 1e-6 * (1 + std::abs(d2))) << c.name;
  }
}

// Ordinary C++ in user model code: literals, auto, pow, abs, branches,
// compound assignment, using-declarations, Eigen vectors of the scalar.
template <class S>
S ordinary_user_code(const lagrangian::Vec<S, 2>& q) {
  using std::abs;
  using std::cos;
  using std::pow;
  S acc = 0;
  S other = 0.0;
  auto c = cos(q[0]);
  auto sq = pow(q[1], 2);
  acc += 3 * c * sq;
  acc -= abs(q[0] - 2);
  if (q[1] > 0) acc *= 2;
  other = acc / 4;
  other += 1;
  const lagrangian::Vec<S, 2> v = q * 2.0;
  return other + v.dot(q) + pow(q[0], 3) - 2 * q.squaredNorm();
}

TEST(Jet, OrdinaryUserCodeCompilesAndDifferentiates) {
  using J = Jet<double, 2, 2>;
  const double x = 0.3, y = 1.1;
  lagrangian::Vec<J, 2> qj;
  qj << J::variable(x, 0), J::variable(y, 1);
  const J r = ordinary_user_code(qj);
  const double fd = ordinary_user_code<double>(lagrangian::Vec<double, 2>(x, y));
  EXPECT_DOUBLE_EQ(r.v, fd);
  // For x < 2, y > 0: f = 1.5 cos x y² + x/2 + x³ (the dot and squaredNorm
  // cancel), so ∂f/∂x = −1.5 sin x y² + 1/2 + 3x², ∂f/∂y = 3 cos x y,
  // ∂²f/∂x² = −1.5 cos x y² + 6x, ∂²f/∂x∂y = −3 sin x y, ∂²f/∂y² = 3 cos x.
  EXPECT_NEAR(r.g[0], -1.5 * std::sin(x) * y * y + 0.5 + 3 * x * x, 1e-14);
  EXPECT_NEAR(r.g[1], 3 * std::cos(x) * y, 1e-14);
  EXPECT_NEAR(r.hess(0, 0), -1.5 * std::cos(x) * y * y + 6 * x, 1e-13);
  EXPECT_NEAR(r.hess(0, 1), -3 * std::sin(x) * y, 1e-14);
  EXPECT_NEAR(r.hess(1, 1), 3 * std::cos(x), 1e-14);
}

TEST(Jet, NestedJetsGiveHigherDerivatives) {
  // Inner first-order jet in x, outer second-order jet in x: the outer
  // Hessian's inner gradient is the third derivative.
  using Inner = Jet<double, 1, 1>;
  using Outer = Jet<Inner, 1, 2>;
  const double x = 0.6;
  Outer a(Inner::variable(x, 0));
  a.g[0] = Inner(1.0);
  const Outer f = sin(a) * 2 + a * a * a;  // f''' = −2 cos x + 6
  EXPECT_NEAR(f.hess(0, 0).g[0], -2 * std::cos(x) + 6, 1e-14);
  EXPECT_NEAR(f.hess(0, 0).v, -2 * std::sin(x) + 6 * x, 1e-14);
  const Outer s = 0;  // literals convert through the nesting
  EXPECT_EQ(s.v.v, 0.0);
}

TEST(Jet, ComparisonsUseValues) {
  using J = Jet<double, 2, 1>;
  const J a = J::variable(1.0, 0), b = J::variable(2.0, 1);
  EXPECT_TRUE(a < b);
  EXPECT_TRUE(a < 1.5);
  EXPECT_TRUE(0 < a);
  EXPECT_TRUE(a == 1.0);
  EXPECT_EQ(lagrangian::ad::max(a, b).g[1], 1.0);
  EXPECT_EQ(lagrangian::ad::value_of(a * b), 2.0);
}

}  // namespace

// -- EomJet: every part against a full second-order Jet ------------------------

namespace eom {

// A non-natural Lagrangian that exercises every path of EomJet: single-
// coordinate numbers promoted to full storage, more squares than pending
// terms (so they are summed into rows), symmetric terms with different
// velocity supports, functions and quotients of velocity-dependent numbers,
// two-argument functions on mixed levels, explicit time, compound assignment.
template <class S, int N>
S messy_lagrangian(const std::array<S, N>& q, const std::array<S, N>& v, const S& t) {
  using std::atan2;
  using std::cos;
  using std::exp;
  using std::hypot;
  using std::pow;
  using std::sin;
  using std::sqrt;
  S T = 0, V = 0, vx = 0, vy = 0;
  for (int k = 0; k < N; ++k) {
    vx += (1.0 + 0.1 * k) * cos(q[k]) * v[k];
    vy += sin(q[k]) * v[k];
    T += (0.5 + 0.05 * k) * (vx * vx + vy * vy);
    V += 9.81 * (1.0 + k) * (1.0 - cos(q[k]));
  }
  const S cross = v[0] * v[N - 1] * cos(q[0] - q[N - 1]) + vx * vy;
  const S speed = sqrt(T + 1.0);
  const S angle = atan2(vy + 0.3, vx + 1.7);
  const S h = hypot(v[1] + 0.5, q[2]);
  const S gyro = q[0] * v[1] - q[1] * v[0];
  const S drive = sin(2.0 * t) * q[N - 1] * v[N - 2];
  const S w = pow(v[2] + 2.0, 3) / (1.5 + q[3] * q[3]);
  const S e = exp(0.1 * v[0]) * v[3];
  S r = T + 0.3 * cross + 0.2 * speed + 0.1 * angle * v[1] + 0.05 * h + gyro + drive + 0.01 * w + 0.02 * e - V;
  r *= 1.1;
  r /= 1.05;
  r -= 0.5 * t;
  return -(-r);
}

template <int N, class E = lagrangian::ad::EomJet<N>>
void check_parts_against_jet(unsigned seed) {
  constexpr int M = 2 * N + 1;  // q, q̇, t
  using R = Jet<double, M, 2>;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int trial = 0; trial < 10; ++trial) {
    std::array<double, N> q, v;
    for (int k = 0; k < N; ++k) {
      q[k] = u(rng);
      v[k] = u(rng);
    }
    const double t = u(rng);
    std::array<E, N> qe, ve;
    std::array<R, N> qr, vr;
    for (int k = 0; k < N; ++k) {
      qe[k] = E::position(q[k], v[k], k);
      ve[k] = E::velocity(v[k], k);
      qr[k] = R::variable(q[k], k);
      vr[k] = R::variable(v[k], N + k);
    }
    E le = messy_lagrangian<E, N>(qe, ve, E::time(t));
    const R lr = messy_lagrangian<R, N>(qr, vr, R::variable(t, 2 * N));
    auto near = [](double a, double b) { return std::abs(a - b) <= 1e-12 * (1.0 + std::abs(b)); };
    EXPECT_TRUE(near(le.v, lr.v)) << le.v << " vs " << lr.v;
    double d = lr.g[2 * N];  // dL/ds = Σ ∂L/∂q_j q̇_j + ∂L/∂t
    for (int j = 0; j < N; ++j) d += lr.g[j] * v[j];
    EXPECT_TRUE(near(le.d, d)) << le.d << " vs " << d;
    Eigen::Matrix<double, N, N> H;
    le.hessian_to(H);
    for (int i = 0; i < N; ++i) {
      EXPECT_TRUE(near(le.grad_q(i), lr.g[i])) << "dL/dq" << i;
      EXPECT_TRUE(near(le.grad_qd(i), lr.g[N + i])) << "dL/dqd" << i;
      double c = lr.hess(N + i, 2 * N);
      for (int j = 0; j < N; ++j) c += lr.hess(N + i, j) * v[j];
      EXPECT_TRUE(near(le.mixed(i), c)) << "mixed " << i << ": " << le.mixed(i) << " vs " << c;
      for (int j = 0; j < N; ++j) {
        EXPECT_TRUE(near(H(i, j), lr.hess(N + i, N + j))) << "M(" << i << "," << j << ")";
        EXPECT_TRUE(near(le.hess(i, j), lr.hess(N + i, N + j))) << "hess(" << i << "," << j << ")";
      }
    }
  }
}

}  // namespace eom

// N = 4 takes the small-system path (full storage, immediate Hessian
// updates); N = 7 single-coordinate storage and pending rank-one terms.
TEST(EomJet, EveryPartMatchesSecondOrderJetSmallSystem) { eom::check_parts_against_jet<4>(11); }
TEST(EomJet, EveryPartMatchesSecondOrderJetLargerSystem) { eom::check_parts_against_jet<7>(12); }
// N = 14: the Hessian parts in a pooled block, summed into its lower
// triangle; and 7 directions of numbers with room for 16 whose width is set
// at run time (rounded up to 8: the eighth direction is never seeded).
TEST(EomJet, EveryPartMatchesSecondOrderJetPooledHessian) { eom::check_parts_against_jet<14>(13); }
TEST(EomJet, EveryPartMatchesSecondOrderJetRunTimeWidth) {
  const lagrangian::ad::WidthScope width(7);
  eom::check_parts_against_jet<7, lagrangian::ad::EomJet<16, true>>(14);
}

// x += x and x -= x on a number holding pending Hessian terms: 2x and 0.
template <class E>
void check_self_accumulation() {
  const E a = E::velocity(0.7, 0), b = E::velocity(-1.3, 1), q = E::position(0.4, 0.7, 2);
  E x = a * b + sin(q) * a * a;  // level 2, pending terms
  const E twice = 2.0 * x;
  E y = x;
  x += x;
  y -= y;
  EXPECT_EQ(x.v, twice.v);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(x.grad_qd(i), twice.grad_qd(i));
    EXPECT_EQ(x.mixed(i), twice.mixed(i));
    EXPECT_EQ(y.grad_qd(i), 0.0);
    for (int j = 0; j < 3; ++j) {
      EXPECT_DOUBLE_EQ(x.hess(i, j), twice.hess(i, j));
      EXPECT_EQ(y.hess(i, j), 0.0);
    }
  }
  EXPECT_NE(twice.hess(0, 1), 0.0);
}
TEST(EomJet, AddingANumberToItselfDoublesIt) {
  check_self_accumulation<lagrangian::ad::EomJet<6>>();
  check_self_accumulation<lagrangian::ad::EomJet<20>>();
}

// The memoised sine and cosine return exactly what <cmath> returns, however
// the arguments repeat and collide in the memo.
TEST(EomJet, MemoisedSinCosAreBitIdentical) {
  using E = lagrangian::ad::EomJet<6>;
  static_assert(E::memoize_trig);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  std::vector<double> xs(200);
  for (double& x : xs) x = u(rng);
  for (int pass = 0; pass < 3; ++pass)
    for (double x : xs) {
      const E a = E::position(x, 0.3, 1);
      EXPECT_EQ(sin(a).v, std::sin(x));
      EXPECT_EQ(cos(a).v, std::cos(x));
      EXPECT_EQ(cos(a).grad_q(1), -std::sin(x));
    }
}
