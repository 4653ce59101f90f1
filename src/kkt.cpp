#include "lagrangian/detail/kkt.hpp"

#include <Eigen/Core>
#include <Eigen/QR>

namespace lagrangian::detail {

struct KktSolver::Impl {
  Eigen::MatrixXd k;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
  Eigen::VectorXd f, z;
  explicit Impl(int s) : k(s, s), cod(s, s), f(s), z(s) {}
};

KktSolver::KktSolver(int size) : impl_(new Impl(size)) {}
KktSolver::~KktSolver() = default;

int KktSolver::factorize(const double* k) {
  impl_->k = Eigen::Map<const Eigen::MatrixXd>(k, impl_->k.rows(), impl_->k.cols());
  impl_->cod.compute(impl_->k);
  return static_cast<int>(impl_->cod.rank());
}

void KktSolver::solve(const double* f, double* z) const {
  impl_->f = Eigen::Map<const Eigen::VectorXd>(f, impl_->f.size());
  impl_->z = impl_->cod.solve(impl_->f);
  Eigen::Map<Eigen::VectorXd>(z, impl_->z.size()) = impl_->z;
}

}  // namespace lagrangian::detail
