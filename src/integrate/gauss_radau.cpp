// The constants of the 15th-order Gauss–Radau stepper (integrate/detail/gauss_radau.hpp):
// its nodes, computed from Legendre's polynomials, and the tables derived
// from them.

#include "lagrangian/integrate/detail/gauss_radau.hpp"

namespace lagrangian::detail {
namespace {

constexpr int K = GaussRadauConstants::K;

/// P₇(u) + P₈(u) by Legendre's recurrence (k + 1) P_{k+1} = (2k + 1) u P_k − k P_{k−1}.
long double radau_polynomial(long double u) {
  long double p0 = 1, p1 = u;
  for (int k = 1; k < 8; ++k) {
    const long double p2 = ((2 * k + 1) * u * p1 - k * p0) / (k + 1);
    p0 = p1;
    p1 = p2;
  }
  return p0 + p1;  // P₇ + P₈
}

/// The roots of P₇ + P₈ in (−1, 1], bracketed on a grid and bisected to
/// long double precision, mapped to h = (u + 1)/2; h₀ = 0 (u = −1).
std::array<double, K + 1> compute_nodes() {
  std::array<double, K + 1> h{};
  int found = 0;
  constexpr int kGrid = 4096;
  const long double du = 2.0L / kGrid;
  long double a = -1 + du / 8, fa = radau_polynomial(a);  // past the root at u = −1
  for (int i = 1; i <= kGrid && found < K; ++i) {
    const long double b = -1 + du * i, fb = radau_polynomial(b);
    if ((fa < 0) != (fb < 0)) {
      long double lo = a, hi = b, flo = fa;
      for (int it = 0; it < 200; ++it) {
        const long double mid = (lo + hi) / 2;
        if (mid == lo || mid == hi) break;
        const long double fm = radau_polynomial(mid);
        if ((fm < 0) == (flo < 0)) {
          lo = mid;
          flo = fm;
        } else {
          hi = mid;
        }
      }
      h[static_cast<std::size_t>(++found)] = static_cast<double>(((lo + hi) / 2 + 1) / 2);
    }
    a = b;
    fa = fb;
  }
  return h;
}

GaussRadauConstants make_constants() {
  GaussRadauConstants g;
  g.h = compute_nodes();
  const auto& h = g.h;
  std::array<std::array<long double, K + 2>, K + 1> poly{};  // poly[k][m]: s^m in N_k
  poly[1][1] = 1;
  for (std::size_t k = 2; k <= K; ++k)
    for (std::size_t m = 1; m <= k; ++m)  // N_k = N_{k−1} · (s − h_{k−1})
      poly[k][m] = poly[k - 1][m - 1] - static_cast<long double>(h[k - 1]) * poly[k - 1][m];
  for (std::size_t k = 1; k <= K; ++k) {
    for (std::size_t m = 1; m <= k; ++m) g.c[k][m] = static_cast<double>(poly[k][m]);
    g.inv_h[k] = 1.0 / h[k];
    for (std::size_t j = 1; j < k; ++j) g.inv_gap[k][j] = 1.0 / (h[k] - h[j]);
  }
  for (int k = 0; k < K; ++k)
    for (int j = 0; j <= k; ++j) {
      double r = 1;  // C(k + 1, j + 1)
      for (int i = 1; i <= j + 1; ++i) r = r * (k + 1 - (j + 1) + i) / i;
      g.binomial[static_cast<std::size_t>(k)][static_cast<std::size_t>(j)] = r;
    }
  return g;
}

}  // namespace

const GaussRadauConstants& gauss_radau_constants() {
  static const GaussRadauConstants g = make_constants();
  return g;
}

}  // namespace lagrangian::detail
