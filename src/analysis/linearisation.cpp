// The dynamic-size linear algebra of the analyses (linearisation.hpp),
// compiled once rather than in every translation unit that includes it.
#include "lagrangian/analysis/linearisation.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/mechanics/detail/min_norm_solver.hpp"

namespace lagrangian::detail {

Eigen::MatrixXd tangent_basis(const Eigen::MatrixXd& G, int n) {
  if (G.rows() == 0) return Eigen::MatrixXd::Identity(n, n);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(G, Eigen::ComputeFullV);
  const auto& s = svd.singularValues();
  int rank = 0;
  for (int i = 0; i < s.size(); ++i)
    if (s[i] > rank_tolerance * s[0] && s[0] > 0) ++rank;
  return svd.matrixV().rightCols(n - rank);
}

Eigen::VectorXd min_norm_solve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  MinNormSolver solver(static_cast<int>(A.rows()), static_cast<int>(A.cols()));
  solver.factorize(A.data());
  Eigen::VectorXd x(A.cols());
  solver.solve(b.data(), x.data());
  return x;
}

Eigen::VectorXd least_squares_multipliers(const Eigen::MatrixXd& G, const Eigen::VectorXd& grad) {
  if (G.rows() == 0) return Eigen::VectorXd();
  return min_norm_solve(G.transpose(), grad);
}

bool symmetric_eigenvalues(const Eigen::MatrixXd& S, Eigen::VectorXd& eigenvalues) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S, Eigen::EigenvaluesOnly);
  if (es.info() != Eigen::Success) return false;
  eigenvalues = es.eigenvalues();
  return true;
}

}  // namespace lagrangian::detail
