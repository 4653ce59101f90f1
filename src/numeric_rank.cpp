#include <vector>

#include <Eigen/SVD>

#include "lagrangian/constraints.hpp"

namespace lagrangian::detail {

int numeric_rank_of(const Eigen::MatrixXd& a, std::vector<double>* values) {
  if (a.rows() == 0) return 0;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a);
  const auto& s = svd.singularValues();
  if (values) values->assign(s.data(), s.data() + s.size());
  if (s.size() == 0 || !(s[0] > 0)) return 0;
  int r = 0;
  for (int i = 0; i < s.size(); ++i)
    if (s[i] > rank_tolerance * s[0]) ++r;
  return r;
}

}  // namespace lagrangian::detail
