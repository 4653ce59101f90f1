#include <algorithm>
#include <cmath>
#include <cstdint>

#include <boost/math/tools/toms748_solve.hpp>

#include "lagrangian/integrate/detail/roots.hpp"

namespace lagrangian::detail {

std::pair<double, double> bracket_root(TimeFunction f, double a, double b, double fa, double fb, double relative) {
  std::uintmax_t iterations = 100;
  auto close_enough = [relative](double lo, double hi) {
    return std::abs(hi - lo) <= relative * std::max(1.0, std::min(std::abs(lo), std::abs(hi)));
  };
  return boost::math::tools::toms748_solve(f, a, b, fa, fb, close_enough, iterations);
}

}  // namespace lagrangian::detail
