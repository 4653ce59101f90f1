#pragma once
// Internal: second derivatives of a function of a run-time number of
// variables, for the analyses of run-time sized models (linearisation.hpp,
// discrete.hpp).

#include <algorithm>

#include <Eigen/Core>

#include "lagrangian/ad/jet.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian::detail {

/// The value, gradient and Hessian of y = f(x) over `nv` variables at x, for
/// a run-time nv: passes of ad::Jet<double, 2B, 2> over pairs of blocks of
/// B variables, pass (a, b) seeding blocks a and b (the Hessian block a × b;
/// pass (a, a) also the gradient of block a). f takes a Vec<J, Dynamic>.
template <class F>
void second_derivatives_by_blocks(int nv, const Eigen::VectorXd& x, F&& f, double& value, Eigen::VectorXd& gradient,
                                  Eigen::MatrixXd& hessian) {
  constexpr int B = 4;
  using J = ad::Jet<double, 2 * B, 2>;
  const int blocks = (nv + B - 1) / B;
  gradient.resize(nv);
  hessian.resize(nv, nv);
  value = 0;
  Vec<J, Dynamic> xj(nv);
  for (int a = 0; a < blocks; ++a) {
    for (int b = a; b < blocks; ++b) {
      for (int k = 0; k < nv; ++k) xj[k] = J(x[k]);
      auto seed = [&](int block, int offset) {
        for (int k = block * B; k < std::min(nv, (block + 1) * B); ++k)
          xj[k] = J::variable(x[k], offset + k - block * B);
      };
      seed(a, 0);
      if (b != a) seed(b, B);
      const J y = f(xj);
      value = y.v;
      for (int i = a * B; i < std::min(nv, (a + 1) * B); ++i) {
        const int li = i - a * B;
        if (b == a) gradient[i] = y.g[li];
        const int offset = b == a ? 0 : B;
        for (int j = b * B; j < std::min(nv, (b + 1) * B); ++j)
          hessian(i, j) = hessian(j, i) = y.hess(li, offset + j - b * B);
      }
    }
  }
}

}  // namespace lagrangian::detail
