// The AD scalar against Eigen's AutoDiffScalar and against finite differences.
#include <gtest/gtest.h>

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
