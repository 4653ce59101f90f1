#include "lagrangian/mechanics/detail/singular_values.hpp"

#include <algorithm>

#include <Eigen/Core>
#include <Eigen/SVD>

namespace lagrangian::detail {

struct SingularValues::Impl {
  Eigen::MatrixXd a;  // the matrix, copied in: JacobiSVD takes its own type
  Eigen::JacobiSVD<Eigen::MatrixXd> svd;
  Impl(int rows, int cols) : a(rows, cols), svd(rows, cols) {}
};

SingularValues::SingularValues(int rows, int cols) : impl_(new Impl(rows, cols)) {}
SingularValues::~SingularValues() = default;
SingularValues::SingularValues(const SingularValues& other) : impl_(new Impl(*other.impl_)) {}
SingularValues& SingularValues::operator=(const SingularValues& other) {
  if (this != &other) *impl_ = *other.impl_;
  return *this;
}

const double* SingularValues::compute(const double* a) {
  Impl& s = *impl_;
  s.a = Eigen::Map<const Eigen::MatrixXd>(a, s.a.rows(), s.a.cols());
  s.svd.compute(s.a);
  return s.svd.singularValues().data();
}

int SingularValues::size() const { return static_cast<int>(std::min(impl_->a.rows(), impl_->a.cols())); }

}  // namespace lagrangian::detail
