#pragma once
// Shared pieces of the stability suite: energy error per time window and a
// line printed for docs/stability.md.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "lagrangian/lagrangian.hpp"

namespace stability {

/// Largest |h − h0| / scale in each window [k w, (k+1) w) of time: an
/// observer for simulate().
template <int N>
struct WindowedEnergy {
  double window;   ///< window length (s)
  double h0 = 0, scale = 1;
  bool first = true;
  std::vector<double> max_error;
  void operator()(const lagrangian::Sample<N>& s) {
    if (first) {
      h0 = s.energy;
      scale = std::max(std::abs(h0), 1e-300);
      first = false;
    }
    const auto k = static_cast<std::size_t>(s.t / window);
    if (max_error.size() <= k) max_error.resize(k + 1, 0.0);
    max_error[k] = std::max(max_error[k], std::abs(s.energy - h0) / scale);
  }
  /// Largest error over windows [from, to).
  double max_over(std::size_t from, std::size_t to) const {
    double m = 0;
    for (std::size_t k = from; k < std::min(to, max_error.size()); ++k) m = std::max(m, max_error[k]);
    return m;
  }
};

/// 1, or `short_factor` when LAGRANGIAN_STABILITY_SHORT is set: the
/// sanitizer stage runs the long cases over a fraction of their length (same
/// code paths; a fifth unless a case says otherwise).
inline double length_factor(double short_factor = 0.2) {
  return std::getenv("LAGRANGIAN_STABILITY_SHORT") ? short_factor : 1.0;
}

/// One line of the figures table: case, method, figure, bound.
inline void record(const std::string& what, const std::string& method, double figure, double bound) {
  std::printf("STABILITY | %s | %s | %.3g | %.3g |\n", what.c_str(), method.c_str(), figure, bound);
}
inline void record(const std::string& what, lagrangian::Method method, double figure, double bound) {
  record(what, std::string(lagrangian::to_string(method)), figure, bound);
}

}  // namespace stability
