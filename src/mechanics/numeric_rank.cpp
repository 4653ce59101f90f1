#include <vector>

#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/mechanics/detail/singular_values.hpp"

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

std::vector<int> rows_adding_no_rank(const Eigen::MatrixXd& a, int rows) {
  std::vector<int> out;
  int rank = 0;
  for (int i = 0; i < rows; ++i) {
    const int next = numeric_rank_of(a.topRows(i + 1), nullptr);
    if (next == rank) out.push_back(i);
    rank = next;
  }
  return out;
}

}  // namespace lagrangian::detail
