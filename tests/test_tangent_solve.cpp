// The last step of the tangent pass (analysis/detail/tangent_solve.hpp,
// compiled in src/analysis/tangent_solve.cpp): the Cholesky factors of M
// and the solves with them, and q̈ = M⁻¹ r with its derivative
// (J V)_c = M⁻¹ (r_{c+1} − ∂M_c q̈). Checked for every size n = 1 … 6
// against Eigen's LU with full pivoting (an independent factorisation), by
// the residual M x − b, and against central differences of
// q̈(s) = (M + s ∂M)⁻¹ (r₀ + s r₁); a matrix that is not positive definite
// must be refused with the state named. And MassCholesky
// (mechanics/detail/mass_cholesky.hpp), the same factors for every q̈ of a
// model with n > 2 coordinates, at run-time sizes and at fixed sizes
// beyond those the library compiles (its long rows take a vectorised dot
// product).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <Eigen/LU>
#include <Eigen/QR>

#include "lagrangian/analysis/detail/tangent_solve.hpp"

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;
using lagrangian::DynamicsError;
using lagrangian::Mat;
using lagrangian::Vec;
using lagrangian::detail::MassCholesky;
using lagrangian::detail::solve_tangent;
using lagrangian::detail::TangentCholesky;

/// A symmetric positive definite n × n matrix with eigenvalues spread over
/// `decades` decades, in a random orthonormal basis. The checks use Eigen's
/// decompositions on run-time sizes only (compiled once for every n).
MatrixXd positive_definite(int n, double decades, std::mt19937& rng) {
  std::normal_distribution<double> n01;
  MatrixXd a(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) a(i, j) = n01(rng);
  const MatrixXd basis = Eigen::HouseholderQR<MatrixXd>(a).householderQ();
  VectorXd spectrum(n);
  for (int i = 0; i < n; ++i) spectrum[i] = std::pow(10.0, -decades * i / std::max(1, n - 1));
  const MatrixXd m = basis * spectrum.asDiagonal() * basis.transpose();
  return (m + m.transpose()) / 2;
}

MatrixXd lu_solve(const MatrixXd& m, const MatrixXd& b) { return Eigen::FullPivLU<MatrixXd>(m).solve(b); }

template <int n>
void solves_match_lu(int columns, double decades, std::mt19937& rng) {
  SCOPED_TRACE("n = " + std::to_string(n) + ", " + std::to_string(columns) + " columns, 1e" +
               std::to_string(static_cast<int>(decades)) + " condition");
  const MatrixXd m = positive_definite(n, decades, rng);
  const MatrixXd b = MatrixXd::Random(n, columns);
  TangentCholesky<n> llt;
  const Vec<double, n> zero = Vec<double, n>::Zero();
  llt.factor(Mat<double, n>(m), zero, zero, 0.0);
  MatrixXd x(n, columns);
  llt.solve(b.data(), x.data(), columns);
  const MatrixXd expected = lu_solve(m, b);
  const double condition = std::pow(10.0, decades);
  EXPECT_LE((x - expected).norm(), 1e-14 * condition * expected.norm());
  EXPECT_LE((m * x - b).norm(), 1e-14 * m.norm() * x.norm());
  // In place: x may be b.
  MatrixXd in_place = b;
  llt.solve(in_place.data(), in_place.data(), columns);
  EXPECT_TRUE(in_place == x);
}

template <int n>
void every_width(std::mt19937& rng) {
  for (int columns : {1, 2, 3, 4, 5, 8, 13})
    for (double decades : {0.0, 4.0, 8.0}) solves_match_lu<n>(columns, decades, rng);
}

TEST(TangentCholesky, SolvesAgreeWithFullPivotingLuForEverySizeAndWidth) {
  std::mt19937 rng(20261202);
  every_width<1>(rng);
  every_width<2>(rng);
  every_width<3>(rng);
  every_width<4>(rng);
  every_width<5>(rng);
  every_width<6>(rng);
}

/// q̈ and J V from solve_tangent() against central differences of
/// q̈(s) = (M + s ∂M_c)⁻¹ (r₀ + s r_{c+1}) along each direction c.
template <int n, int K>
void tangent_matches_differences(std::mt19937& rng) {
  SCOPED_TRACE("n = " + std::to_string(n) + ", K = " + std::to_string(K));
  // M's eigenvalues 1 … 0.1 and ∂M of norm about 0.1: M + s ∂M stays far
  // from singular over the differences' steps (s = ±1e-5).
  const MatrixXd m = positive_definite(n, 1.0, rng);
  const MatrixXd r = MatrixXd::Random(n, K + 1);
  std::array<Mat<double, n>, K> dm;
  for (auto& d : dm) {
    const MatrixXd a = MatrixXd::Random(n, n);
    d = 0.05 * (a + a.transpose());  // ∂M is symmetric, not definite
  }
  const auto dmass = [&](int c) -> const Mat<double, n>& { return dm[c]; };
  const Vec<double, n> q = Vec<double, n>::Constant(0.25), qd = Vec<double, n>::Constant(-0.5);
  Vec<double, n> qdd;
  Eigen::Matrix<double, n, K> jv;
  solve_tangent<n, K>(Mat<double, n>(m), Eigen::Matrix<double, n, K + 1>(r), dmass, q, qd, 1.5, qdd, jv);
  const VectorXd qdd_lu = lu_solve(m, r.col(0));
  EXPECT_LE((VectorXd(qdd) - qdd_lu).norm(), 1e-13 * qdd_lu.norm());
  const double h = 1e-5;
  for (int c = 0; c < K; ++c) {
    const MatrixXd dmc = dm[c];
    const VectorXd jvc = jv.col(c), rc = r.col(c + 1);
    // The defining equation M (J V)_c + ∂M_c q̈ = r_{c+1}, then the differences.
    EXPECT_LE((m * jvc + dmc * VectorXd(qdd) - rc).norm(), 1e-14 * (1 + rc.norm())) << "direction " << c;
    const auto at = [&](double s) -> VectorXd { return lu_solve(m + s * dmc, r.col(0) + s * rc); };
    const VectorXd difference = (at(h) - at(-h)) / (2 * h);
    EXPECT_LE((jvc - difference).norm(), 1e-8 * (1 + difference.norm())) << "direction " << c;
  }
}

TEST(TangentSolve, DerivativeOfTheAccelerationsMatchesCentralDifferences) {
  std::mt19937 rng(7);
  tangent_matches_differences<1, 2>(rng);
  tangent_matches_differences<2, 1>(rng);
  tangent_matches_differences<2, 4>(rng);
  tangent_matches_differences<3, 6>(rng);
  tangent_matches_differences<4, 9>(rng);
  tangent_matches_differences<6, 12>(rng);
  tangent_matches_differences<6, 13>(rng);
}

/// factor() of `m` must throw DynamicsError naming the tangent flow and the state.
template <int n>
void refused(const Mat<double, n>& m, const std::string& what) {
  SCOPED_TRACE(what);
  TangentCholesky<n> llt;
  const Vec<double, n> q = Vec<double, n>::Constant(0.125), qd = Vec<double, n>::Constant(3.0);
  try {
    llt.factor(m, q, qd, 2.5);
    ADD_FAILURE() << "factor() accepted it";
  } catch (const DynamicsError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("tangent flow: the mass matrix M = d2L/dqd2 is singular or not positive definite"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("t = 2.5, q = [0.125"), std::string::npos) << message;
    EXPECT_NE(message.find("qd = [3"), std::string::npos) << message;
  }
}

TEST(TangentCholesky, RefusesWhatIsNotPositiveDefinite) {
  Mat<double, 3> m = Mat<double, 3>::Identity();
  m(2, 2) = -1;
  refused<3>(m, "indefinite");
  // Singular: M_33 − (1 1) [2 1; 1 2]⁻¹ (1 1)ᵀ = 2/3 − 2/3 = 0.
  m << 2, 1, 1, 1, 2, 1, 1, 1, 2.0 / 3.0;
  refused<3>(m, "singular");
  m = Mat<double, 3>::Identity();
  m(1, 0) = m(0, 1) = std::numeric_limits<double>::quiet_NaN();
  refused<3>(m, "not a number off the diagonal");
  m = Mat<double, 3>::Identity();
  m(0, 0) = std::numeric_limits<double>::infinity();
  refused<3>(m, "infinite");
  refused<1>(Mat<double, 1>::Zero(), "zero, one coordinate");
  // Positive, but its factors' ratio (1e-7.5)² = 1e-15 below singular_mass_tolerance = 1e-14.
  Mat<double, 2> thin = Mat<double, 2>::Identity();
  thin(1, 1) = 1e-15;
  refused<2>(thin, "beyond the singular-mass tolerance");
}

TEST(TangentCholesky, AcceptsAPositiveDefiniteMatrixWithinTheTolerance) {
  Mat<double, 2> m = Mat<double, 2>::Identity();
  m(1, 1) = 1e-13;  // the factors' ratio² 1e-13 ≥ 1e-14
  TangentCholesky<2> llt;
  const Vec<double, 2> zero = Vec<double, 2>::Zero();
  EXPECT_NO_THROW(llt.factor(m, zero, zero, 0.0));
  const double b[2] = {2.0, 3e-13};
  double x[2];
  llt.solve(b, x);
  EXPECT_NEAR(x[0], 2.0, 1e-15);
  EXPECT_NEAR(x[1], 3.0, 1e-12);
}

/// MassCholesky<N> of an n × n M against LU with full pivoting, for a few
/// column counts, through the pointer form and the matrix form.
template <int N>
void mass_cholesky_matches_lu(int n, std::mt19937& rng) {
  SCOPED_TRACE("N = " + std::to_string(N) + ", n = " + std::to_string(n));
  const MatrixXd m = positive_definite(n, 6.0, rng);
  MassCholesky<N> llt;
  ASSERT_TRUE(llt.compute(Mat<double, N>(m), lagrangian::singular_mass_tolerance));
  EXPECT_EQ(llt.size(), n);
  for (int columns : {1, 3, 4, 7}) {
    const MatrixXd b = MatrixXd::Random(n, columns);
    MatrixXd x = b;
    llt.solve(x.data(), x.data(), columns);
    const MatrixXd expected = lu_solve(m, b);
    EXPECT_LE((x - expected).norm(), 1e-14 * 1e6 * expected.norm()) << columns << " columns";
    EXPECT_LE((m * x - b).norm(), 1e-14 * m.norm() * x.norm()) << columns << " columns";
  }
  // The matrix form, one column and n × 2.
  const Eigen::Matrix<double, N, 1> b1 = VectorXd::Random(n);
  const Eigen::Matrix<double, N, 1> x1 = llt.solve(b1);
  EXPECT_LE((m * VectorXd(x1) - VectorXd(b1)).norm(), 1e-14 * m.norm() * x1.norm());
  const Eigen::Matrix<double, N, 2> b2 = MatrixXd::Random(n, 2);
  const Eigen::Matrix<double, N, 2> x2 = llt.solve(b2.transpose().transpose());
  EXPECT_LE((m * MatrixXd(x2) - MatrixXd(b2)).norm(), 1e-14 * m.norm() * x2.norm());
}

TEST(MassCholesky, SolvesAgreeWithFullPivotingLuAtRunTimeAndLargeFixedSizes) {
  std::mt19937 rng(31);
  for (int n : {1, 2, 3, 7, 8, 9, 12, 40}) mass_cholesky_matches_lu<Eigen::Dynamic>(n, rng);
  mass_cholesky_matches_lu<1>(1, rng);
  mass_cholesky_matches_lu<9>(9, rng);
  mass_cholesky_matches_lu<12>(12, rng);  // not among the library's sizes: compiled here
  mass_cholesky_matches_lu<40>(40, rng);
}

TEST(MassCholesky, RefusesWhatIsNotPositiveDefiniteAtRunTimeSize) {
  const double tolerance = lagrangian::singular_mass_tolerance;
  MassCholesky<Eigen::Dynamic> llt;
  MatrixXd m = MatrixXd::Identity(10, 10);
  EXPECT_TRUE(llt.compute(m, tolerance));
  m(9, 9) = -1;
  EXPECT_FALSE(llt.compute(m, tolerance)) << "indefinite";
  m = MatrixXd::Identity(10, 10);
  m(9, 0) = m(0, 9) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(llt.compute(m, tolerance)) << "not a number in the last row";
  m = MatrixXd::Identity(10, 10);
  m(4, 4) = 1e-15;
  EXPECT_FALSE(llt.compute(m, tolerance)) << "pivot ratio 1e-15";
  m(4, 4) = 1e-13;
  EXPECT_TRUE(llt.compute(m, tolerance)) << "pivot ratio 1e-13";
  // Singular in its last three rows: M_99 − (1 1) [2 1; 1 2]⁻¹ (1 1)ᵀ = 2/3 − 2/3 = 0.
  m = MatrixXd::Identity(10, 10);
  m.bottomRightCorner(3, 3) << 2, 1, 1, 1, 2, 1, 1, 1, 2.0 / 3.0;
  EXPECT_FALSE(llt.compute(m, tolerance)) << "singular";
}

}  // namespace
