// The linear algebra of the tangent pass (analysis/detail/tangent_solve.hpp),
// compiled once for each size the tangent flow takes.

#include <algorithm>
#include <cmath>
#include <sstream>

#include "lagrangian/analysis/detail/tangent_solve.hpp"

namespace lagrangian::detail {

template <int n>
void TangentCholesky<n>::factor(const Mat<double, n>& mass, const Vec<double, n>& q, const Vec<double, n>& qd,
                                double t) {
  // L_jj² = M_jj − Σ_{k<j} L_jk², L_ij = (M_ij − Σ_{k<j} L_ik L_jk) / L_jj for i > j.
  bool positive = true;
  double smallest = 0, largest = 0;
  for (int j = 0; j < n && positive; ++j) {
    double s = mass(j, j);
    for (int k = 0; k < j; ++k) s -= l_(j, k) * l_(j, k);
    if (!(s > 0) || !std::isfinite(s)) {
      positive = false;
      break;
    }
    const double d = std::sqrt(s);
    l_(j, j) = d;
    inverse_[j] = 1 / d;
    smallest = j == 0 ? d : std::min(smallest, d);
    largest = std::max(largest, d);
    for (int i = j + 1; i < n; ++i) {
      double x = mass(i, j);
      for (int k = 0; k < j; ++k) x -= l_(i, k) * l_(j, k);
      l_(i, j) = x * inverse_[j];
    }
  }
  if (positive) positive = smallest * smallest >= singular_mass_tolerance * largest * largest;
  if (!positive) {
    std::ostringstream os;
    os.precision(17);
    os << "tangent flow: the mass matrix M = d2L/dqd2 is singular or not positive definite at "
       << describe_state(q, qd, t);
    throw DynamicsError(os.str());
  }
}

template <int n>
void TangentCholesky<n>::solve(const double* b, double* x, int columns) const {
  // L y = b, then Lᵀ x = y, W columns at a time: x is written only in the
  // second sweep, so it may be b. l_ holds L's rows, inverse_ 1 / L_ii.
  const auto sweep = [&]<int W>(const double* bw, double* xw) {
    double y[n][W];
    for (int i = 0; i < n; ++i) {
      double s[W];
      for (int w = 0; w < W; ++w) s[w] = bw[w * n + i];
      for (int k = 0; k < i; ++k)
        for (int w = 0; w < W; ++w) s[w] -= l_(i, k) * y[k][w];
      for (int w = 0; w < W; ++w) y[i][w] = s[w] * inverse_[i];
    }
    for (int i = n - 1; i >= 0; --i) {
      for (int w = 0; w < W; ++w) {
        y[i][w] *= inverse_[i];
        xw[w * n + i] = y[i][w];
      }
      for (int k = 0; k < i; ++k)
        for (int w = 0; w < W; ++w) y[k][w] -= l_(i, k) * y[i][w];
    }
  };
  int c = 0;
  for (; c + 4 <= columns; c += 4) sweep.template operator()<4>(b + c * n, x + c * n);
  for (; c < columns; ++c) sweep.template operator()<1>(b + c * n, x + c * n);
}

template <int n>
void solve_tangent_columns(const Mat<double, n>& mass, const double* r, int k, MassDerivatives<n> dmass,
                           const Vec<double, n>& q, const Vec<double, n>& qd, double t, Vec<double, n>& qdd,
                           double* jv) {
  TangentCholesky<n> llt;
  llt.factor(mass, q, qd, t);
  llt.solve(r, qdd.data());
  Eigen::Map<Eigen::Matrix<double, n, Eigen::Dynamic>> rhs(jv, n, k);
  for (int c = 0; c < k; ++c) rhs.col(c) = Eigen::Map<const Vec<double, n>>(r + (c + 1) * n) - dmass(c) * qdd;
  llt.solve(jv, jv, k);
}

// The sizes of kMaxTangentFlowCoordinates (analysis/tangent_flow.hpp).
#define LAGRANGIAN_TANGENT_SOLVE(n)                                                                           \
  template class TangentCholesky<n>;                                                                           \
  template void solve_tangent_columns<n>(const Mat<double, n>&, const double*, int, MassDerivatives<n>,         \
                                         const Vec<double, n>&, const Vec<double, n>&, double, Vec<double, n>&, \
                                         double*);
LAGRANGIAN_TANGENT_SOLVE(1)
LAGRANGIAN_TANGENT_SOLVE(2)
LAGRANGIAN_TANGENT_SOLVE(3)
LAGRANGIAN_TANGENT_SOLVE(4)
LAGRANGIAN_TANGENT_SOLVE(5)
LAGRANGIAN_TANGENT_SOLVE(6)
#undef LAGRANGIAN_TANGENT_SOLVE

}  // namespace lagrangian::detail
