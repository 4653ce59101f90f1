#pragma once
// <cmath> for the AD number types: each function gives f, f′, f″ at the
// value and lets the number type apply the chain rule (see ad.hpp).

#include <cmath>
#include <type_traits>

#include "lagrangian/ad/eom_jet.hpp"
#include "lagrangian/ad/jet.hpp"
#include "lagrangian/ad/traits.hpp"

namespace lagrangian::ad {

// -- <cmath> for AD numbers -------------------------------------------------------
// Each function gives f, f', f'' at the value and lets the number type apply
// the chain rule (`chain`, `chain2`); `using std::sin;` lets the value type be
// double or another Jet.

#define LAGRANGIAN_AD_UNARY(name, f0, f1, f2)      \
  template <ADNumber J>                            \
  constexpr J name(const J& a) {                   \
    using T = typename J::value_type;              \
    using std::sin;                                \
    using std::cos;                                \
    using std::exp;                                \
    using std::log;                                \
    using std::sqrt;                               \
    using std::cosh;                               \
    using std::sinh;                               \
    using std::tan;                                \
    using std::tanh;                               \
    using std::atan;                               \
    using std::asin;                               \
    using std::acos;                               \
    using std::cbrt;                               \
    using std::log1p;                              \
    using std::expm1;                              \
    using std::asinh;                              \
    using std::acosh;                              \
    using std::atanh;                              \
    const T& x = a.v;                              \
    (void)x;                                       \
    return chain(a, f0, f1, f2);                   \
  }

LAGRANGIAN_AD_UNARY(expm1, expm1(x), exp(x), exp(x))
LAGRANGIAN_AD_UNARY(log, log(x), T(1) / x, T(-1) / (x * x))
LAGRANGIAN_AD_UNARY(log1p, log1p(x), T(1) / (T(1) + x), T(-1) / ((T(1) + x) * (T(1) + x)))
LAGRANGIAN_AD_UNARY(log10, log(x) / T(std::log(10.0)), T(1) / (x * T(std::log(10.0))),
                    T(-1) / (x * x * T(std::log(10.0))))
LAGRANGIAN_AD_UNARY(log2, log(x) / T(std::log(2.0)), T(1) / (x * T(std::log(2.0))),
                    T(-1) / (x * x * T(std::log(2.0))))
LAGRANGIAN_AD_UNARY(cbrt, cbrt(x), T(1) / (T(3) * cbrt(x) * cbrt(x)), T(-2) / (T(9) * x * cbrt(x) * cbrt(x)))
LAGRANGIAN_AD_UNARY(asin, asin(x), T(1) / sqrt(T(1) - x * x), x / ((T(1) - x * x) * sqrt(T(1) - x * x)))
LAGRANGIAN_AD_UNARY(acos, acos(x), T(-1) / sqrt(T(1) - x * x), -x / ((T(1) - x * x) * sqrt(T(1) - x * x)))
LAGRANGIAN_AD_UNARY(atan, atan(x), T(1) / (T(1) + x * x), T(-2) * x / ((T(1) + x * x) * (T(1) + x * x)))
LAGRANGIAN_AD_UNARY(sinh, sinh(x), cosh(x), sinh(x))
LAGRANGIAN_AD_UNARY(cosh, cosh(x), sinh(x), cosh(x))
LAGRANGIAN_AD_UNARY(asinh, asinh(x), T(1) / sqrt(x * x + T(1)), -x / ((x * x + T(1)) * sqrt(x * x + T(1))))
LAGRANGIAN_AD_UNARY(acosh, acosh(x), T(1) / sqrt(x * x - T(1)), -x / ((x * x - T(1)) * sqrt(x * x - T(1))))
LAGRANGIAN_AD_UNARY(atanh, atanh(x), T(1) / (T(1) - x * x), T(2) * x / ((T(1) - x * x) * (T(1) - x * x)))
#undef LAGRANGIAN_AD_UNARY

template <class J>
inline constexpr bool memoize_trig_v = false;
template <int N, bool R>
inline constexpr bool memoize_trig_v<EomJet<N, R>> = EomJet<N, R>::memoize_trig;

namespace detail {
/// sin x and cos x, evaluated once (g++ fuses the two calls into sincos).
/// With `memo` (the Euler–Lagrange pass of systems with more than four
/// coordinates) the last results are kept per thread, 64 slots addressed by
/// a hash of the argument's exact value: model code takes sin and cos of
/// the same angle, in T and again in V, and a hit returns the very same
/// numbers a call would, so results are unchanged bit for bit. (With 8
/// slots a 10-link chain's angles collided and half the lookups missed.)
template <class T>
inline void sin_cos(const T& x, T& s, T& c, bool memo) {
  using std::cos;
  using std::sin;
  if constexpr (std::is_same_v<T, double>) {
    if (memo) {
      constexpr unsigned slots = 64;
      struct Memo {
        double x[slots], s[slots], c[slots];
      };
      static thread_local constinit Memo m = [] {
        Memo r{};
        for (double& k : r.x) k = std::numeric_limits<double>::quiet_NaN();  // matches nothing
        return r;
      }();
      std::uint64_t bits = 0;
      std::memcpy(&bits, &x, sizeof bits);
      const unsigned slot = static_cast<unsigned>((bits ^ (bits >> 23) ^ (bits >> 45)) & (slots - 1));
      if (m.x[slot] == x) {
        s = m.s[slot];
        c = m.c[slot];
        return;
      }
#if defined(__GLIBC__)
      ::sincos(x, &s, &c);  // (g++ does not fuse the two calls here)
#else
      s = sin(x);
      c = cos(x);
#endif
      m.x[slot] = x;
      m.s[slot] = s;
      m.c[slot] = c;
      return;
    }
  }
  s = sin(x);
  c = cos(x);
}
}  // namespace detail

template <ADNumber J>
constexpr J sin(const J& a) {
  typename J::value_type s, c;
  detail::sin_cos(a.v, s, c, memoize_trig_v<J>);
  return chain(a, s, c, -s);
}
template <ADNumber J>
constexpr J cos(const J& a) {
  typename J::value_type s, c;
  detail::sin_cos(a.v, s, c, memoize_trig_v<J>);
  return chain(a, c, -s, -c);
}
template <ADNumber J>
constexpr J exp(const J& a) {
  using std::exp;
  const typename J::value_type e = exp(a.v);
  return chain(a, e, e, e);
}
template <ADNumber J>
constexpr J sqrt(const J& a) {
  using std::sqrt;
  using T = typename J::value_type;
  const T r = sqrt(a.v);
  return chain(a, r, T(0.5) / r, T(-0.25) / (a.v * r));
}
template <ADNumber J>
constexpr J tan(const J& a) {
  using std::tan;
  using T = typename J::value_type;
  const T r = tan(a.v);
  const T sec2 = T(1) + r * r;
  return chain(a, r, sec2, T(2) * r * sec2);
}
template <ADNumber J>
constexpr J tanh(const J& a) {
  using std::tanh;
  using T = typename J::value_type;
  const T r = tanh(a.v);
  const T sech2 = T(1) - r * r;
  return chain(a, r, sech2, T(-2) * r * sech2);
}

/// |a|; the derivative at a = 0 is taken from the right (sign +1).
template <ADNumber J>
constexpr J abs(const J& a) {
  return a.v < typename J::value_type(0) ? -a : a;
}
template <ADNumber J>
constexpr J fabs(const J& a) {
  return abs(a);
}

/// a^p for a constant exponent p: f' = p a^(p-1), f'' = p(p-1) a^(p-2).
/// Integer exponents are exact at a = 0 (x² has derivative 0 there).
template <ADNumber J, class P>
  requires std::is_arithmetic_v<P>
constexpr J pow(const J& a, P p) {
  using std::pow;
  using T = typename J::value_type;
  const T& x = a.v;
  if constexpr (std::is_integral_v<P>) {
    if (p == 0) return J(T(1));
    if (p == 1) return a;
    if (p == 2) return a * a;
    const double pd = static_cast<double>(p);
    const T xm2 = pow(x, static_cast<int>(p - 2));
    return chain(a, xm2 * x * x, T(pd) * xm2 * x, T(pd * (pd - 1.0)) * xm2);
  } else {
    const double pd = static_cast<double>(p);
    return chain(a, pow(x, T(pd)), T(pd) * pow(x, T(pd - 1.0)), T(pd * (pd - 1.0)) * pow(x, T(pd - 2.0)));
  }
}
/// c^b for a constant base: exp(b ln c).
template <ADNumber J, class C>
  requires std::is_arithmetic_v<C>
constexpr J pow(C c, const J& b) {
  using std::log;
  return exp(b * typename J::value_type(log(static_cast<double>(c))));
}
/// a^b, both varying: exp(b ln a); needs a > 0.
template <ADNumber J>
constexpr J pow(const J& a, const J& b) {
  return exp(b * log(a));
}
template <class T, int N, int O>
  requires is_jet_v<T>
constexpr Jet<T, N, O> pow(const Jet<T, N, O>& a, const T& p) {
  return exp(Jet<T, N, O>(p) * log(a));
}

/// atan2(y, x), the angle of the point (x, y).
template <ADNumber J>
constexpr J atan2(const J& y, const J& x) {
  using std::atan2;
  using T = typename J::value_type;
  const T r2 = x.v * x.v + y.v * y.v;
  const T r4 = r2 * r2;
  return chain2(y, x, atan2(y.v, x.v), x.v / r2, -y.v / r2, T(-2) * x.v * y.v / r4, (y.v * y.v - x.v * x.v) / r4,
                T(2) * x.v * y.v / r4);
}
template <ADNumber J, class A>
  requires std::is_arithmetic_v<A>
constexpr J atan2(const J& y, A x) {
  return atan2(y, J(x));
}
template <ADNumber J, class A>
  requires std::is_arithmetic_v<A>
constexpr J atan2(A y, const J& x) {
  return atan2(J(y), x);
}

/// sqrt(a² + b²) without intermediate overflow in the value.
template <ADNumber J>
constexpr J hypot(const J& a, const J& b) {
  using std::hypot;
  using T = typename J::value_type;
  const T r = hypot(a.v, b.v);
  const T r3 = r * r * r;
  return chain2(a, b, r, a.v / r, b.v / r, b.v * b.v / r3, -a.v * b.v / r3, a.v * a.v / r3);
}

template <ADNumber J>
constexpr J max(const J& a, const J& b) {
  return a.v < b.v ? b : a;
}
template <ADNumber J>
constexpr J min(const J& a, const J& b) {
  return b.v < a.v ? b : a;
}
template <ADNumber J>
constexpr J fmax(const J& a, const J& b) {
  return max(a, b);
}
template <ADNumber J>
constexpr J fmin(const J& a, const J& b) {
  return min(a, b);
}

template <ADNumber J>
bool isfinite(const J& a) {
  using std::isfinite;
  return isfinite(a.v);
}
template <ADNumber J>
bool isnan(const J& a) {
  using std::isnan;
  return isnan(a.v);
}

}  // namespace lagrangian::ad
