#include <vector>

#include "lagrangian/constraints.hpp"
#include "lagrangian/detail/singular_values.hpp"

namespace lagrangian::detail {

int numeric_rank_of(const Eigen::MatrixXd& a, std::vector<double>* values) {
  if (a.rows() == 0) return 0;
  SingularValues svd(static_cast<int>(a.rows()), static_cast<int>(a.cols()));
  const double* s = svd.compute(a.data());
  const int count = svd.size();
  if (values) values->assign(s, s + count);
  if (count == 0 || !(s[0] > 0)) return 0;
  int r = 0;
  for (int i = 0; i < count; ++i)
    if (s[i] > rank_tolerance * s[0]) ++r;
  return r;
}

}  // namespace lagrangian::detail
