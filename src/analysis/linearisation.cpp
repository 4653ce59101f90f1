// The dynamic-size linear algebra of the analyses (linearisation.hpp),
// compiled once rather than in every translation unit that includes it.
#include "lagrangian/linearisation.hpp"

#include <Eigen/QR>
#include <Eigen/SVD>

#include "lagrangian/constraints.hpp"

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

Eigen::VectorXd least_squares_multipliers(const Eigen::MatrixXd& G, const Eigen::VectorXd& grad) {
  if (G.rows() == 0) return Eigen::VectorXd();
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(G.transpose());
  return cod.solve(grad);
}

}  // namespace lagrangian::detail
