// The minimum-norm least-squares solver behind the constraint forces,
// projections, impacts and implicit steps (mechanics/detail/min_norm_solver.hpp),
// checked against the pseudo-inverse from Eigen's SVD, an independent
// factorisation: regular square systems (solved through LU with full
// pivoting), nearly singular and singular ones, and rectangular ones
// (solved through the complete orthogonal decomposition).
#include <gtest/gtest.h>

#include <random>

#include <Eigen/SVD>

#include "lagrangian/mechanics/detail/min_norm_solver.hpp"

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

/// x = A⁺ b by the SVD, singular values below 1e-12 σ_1 dropped.
VectorXd pseudo_inverse_solve(const MatrixXd& a, const VectorXd& b) {
  Eigen::JacobiSVD<MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  svd.setThreshold(1e-12);
  return svd.solve(b);
}

/// A rows × cols matrix of rank r with singular values 1, …, 10^(−decades).
MatrixXd with_spectrum(int rows, int cols, int r, double decades, std::mt19937& rng) {
  std::normal_distribution<double> n01;
  auto random_orthonormal = [&](int n) {
    MatrixXd g(n, n);
    for (int i = 0; i < n * n; ++i) g.data()[i] = n01(rng);
    return MatrixXd(Eigen::HouseholderQR<MatrixXd>(g).householderQ());
  };
  const MatrixXd u = random_orthonormal(rows), v = random_orthonormal(cols);
  MatrixXd s = MatrixXd::Zero(rows, cols);
  for (int i = 0; i < r; ++i) s(i, i) = std::pow(10.0, -decades * i / std::max(r - 1, 1));
  return u * s * v.transpose();
}

struct Case {
  int rows, cols, rank;
  double decades;  ///< the spread of the nonzero singular values
};

TEST(MinNormSolver, AgreesWithThePseudoInverse) {
  std::mt19937 rng(20261125);
  std::normal_distribution<double> n01;
  const Case cases[] = {{1, 1, 1, 0}, {2, 2, 2, 1},  {3, 3, 3, 4},  {6, 6, 6, 2},   {12, 12, 12, 3},
                        {4, 4, 3, 1}, {5, 5, 2, 0},  {6, 6, 6, 11}, {3, 5, 3, 1},   {5, 3, 3, 2},
                        {2, 6, 1, 0}, {7, 4, 2, 1},  {40, 40, 40, 2}, {30, 30, 29, 1}};
  for (const Case& c : cases) {
    for (int trial = 0; trial < 5; ++trial) {
      const MatrixXd a = with_spectrum(c.rows, c.cols, c.rank, c.decades, rng);
      VectorXd b(c.rows);
      for (int i = 0; i < c.rows; ++i) b[i] = n01(rng);
      lagrangian::detail::MinNormSolver solver(c.rows, c.cols);
      EXPECT_EQ(solver.factorize(a.data()), c.rank) << c.rows << "x" << c.cols << " rank " << c.rank;
      VectorXd x(c.cols);
      solver.solve(b.data(), x.data());
      const VectorXd expected = pseudo_inverse_solve(a, b);
      // Forward error bound: condition number (10^decades) times rounding.
      const double tol = 1e-13 * std::pow(10.0, c.decades) * c.cols;
      EXPECT_LE((x - expected).norm(), tol * (1.0 + expected.norm()))
          << c.rows << "x" << c.cols << " rank " << c.rank << " spread 1e" << c.decades;
    }
  }
}

TEST(MinNormSolver, RegularSquareSystemsAreSolvedExactlyAndRepeatedly) {
  // A x = b with an exact integer solution, then a second right-hand side
  // on the same factors, then a different matrix of the same size.
  lagrangian::detail::MinNormSolver solver(3);
  MatrixXd a(3, 3);
  a << 0, 2, 1,  //
      1, 0, 0,   //
      3, 1, 4;   // a zero leading entry: needs a pivot interchange
  ASSERT_EQ(solver.factorize(a.data()), 3);
  const VectorXd x_true = (VectorXd(3) << 1, -2, 3).finished();
  VectorXd b = a * x_true, x(3);
  solver.solve(b.data(), x.data());
  EXPECT_LE((x - x_true).lpNorm<Eigen::Infinity>(), 1e-15);
  const VectorXd y_true = (VectorXd(3) << -0.5, 0.25, 8).finished();
  b = a * y_true;
  solver.solve(b.data(), x.data());
  EXPECT_LE((x - y_true).lpNorm<Eigen::Infinity>(), 1e-14);
  MatrixXd singular(3, 3);
  singular << 1, 2, 3,  //
      2, 4, 6,          //
      1, 0, 1;
  EXPECT_EQ(solver.factorize(singular.data()), 2);
  b << 1, 2, 0;  // consistent: the minimum-norm solution solves it
  solver.solve(b.data(), x.data());
  EXPECT_LE((singular * x - b).norm(), 1e-14);
  EXPECT_LE((x - pseudo_inverse_solve(singular, b)).norm(), 1e-14);
}

}  // namespace
