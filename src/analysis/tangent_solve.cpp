// The linear algebra of the tangent pass (analysis/detail/tangent_solve.hpp),
// compiled once for each size the tangent flow takes.

#include <sstream>

#include "lagrangian/analysis/detail/tangent_solve.hpp"

namespace lagrangian::detail {

template <int n>
void TangentCholesky<n>::factor(const Mat<double, n>& mass, const Vec<double, n>& q, const Vec<double, n>& qd,
                                double t) {
  if (!llt_.compute(mass, singular_mass_tolerance)) {
    std::ostringstream os;
    os.precision(17);
    os << "tangent flow: the mass matrix M = d2L/dqd2 is singular or not positive definite at "
       << describe_state(q, qd, t);
    throw DynamicsError(os.str());
  }
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
