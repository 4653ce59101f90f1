#pragma once
// ad::Jet<T, N, Order>: the truncated Taylor polynomial in N directions,
// first or second order (see ad.hpp).

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <ostream>
#include <type_traits>
#include <utility>

#include <Eigen/Core>

#include "lagrangian/ad/traits.hpp"

namespace lagrangian::ad {

/// Truncated Taylor polynomial in N directions, first or second order.
template <class T, int N, int Order>
class Jet {
  static_assert(N >= 1, "ad::Jet needs at least one direction");
  static_assert(Order == 1 || Order == 2, "ad::Jet supports Order 1 (gradient) or 2 (gradient and Hessian)");

 public:
  static constexpr int directions = N;
  static constexpr int order = Order;
  static constexpr int hessian_size = Order == 2 ? N * (N + 1) / 2 : 0;
  using value_type = T;

  T v{};                          ///< value
  std::array<T, N> g{};           ///< ∂x/∂ε_i
  std::array<T, hessian_size> h{};  ///< ∂²x/∂ε_i∂ε_j, packed, i <= j

  constexpr Jet() = default;
  /// A constant (all derivatives zero). Implicit, so `S x = 0` and `x * 2` work.
  template <class A>
    requires(std::is_arithmetic_v<A> || std::is_same_v<A, T>)
  constexpr Jet(const A& value) : v(static_cast<T>(value)) {}

  /// The independent variable number `i` at `value` (seed ∂x/∂ε_i = 1).
  static constexpr Jet variable(const T& value, int i) {
    Jet r(value);
    r.g[i] = T(1);
    return r;
  }

  /// h_ij accessor (symmetric).
  constexpr const T& hess(int i, int j) const {
    return i <= j ? h[detail::packed(i, j, N)] : h[detail::packed(j, i, N)];
  }
  constexpr T& hess(int i, int j) { return i <= j ? h[detail::packed(i, j, N)] : h[detail::packed(j, i, N)]; }

  // -- compound assignment -------------------------------------------------
  constexpr Jet& operator+=(const Jet& b) {
    v += b.v;
    for (int i = 0; i < N; ++i) g[i] += b.g[i];
    for (int k = 0; k < hessian_size; ++k) h[k] += b.h[k];
    return *this;
  }
  constexpr Jet& operator-=(const Jet& b) {
    v -= b.v;
    for (int i = 0; i < N; ++i) g[i] -= b.g[i];
    for (int k = 0; k < hessian_size; ++k) h[k] -= b.h[k];
    return *this;
  }
  constexpr Jet& operator*=(const Jet& b) { return *this = *this * b; }
  constexpr Jet& operator/=(const Jet& b) { return *this = *this / b; }
  constexpr Jet& operator+=(const T& s) {
    v += s;
    return *this;
  }
  constexpr Jet& operator-=(const T& s) {
    v -= s;
    return *this;
  }
  constexpr Jet& operator*=(const T& s) {
    v *= s;
    for (int i = 0; i < N; ++i) g[i] *= s;
    for (int k = 0; k < hessian_size; ++k) h[k] *= s;
    return *this;
  }
  constexpr Jet& operator/=(const T& s) { return *this *= T(1) / s; }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  constexpr Jet& operator+=(A s) { return *this += T(s); }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  constexpr Jet& operator-=(A s) { return *this -= T(s); }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  constexpr Jet& operator*=(A s) { return *this *= T(s); }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  constexpr Jet& operator/=(A s) { return *this /= T(s); }

  // -- arithmetic (hidden friends: found by ADL, allow implicit constants) --
  // First-order results of a value type that is itself a number (the tangent
  // flow's Jet<EomJet, K, 1>) are built in place, each part from the
  // expression that computes it: no default construction and assignment, no
  // copies of large numbers. (Over plain values the loops below measure
  // faster.)
  static constexpr bool kInPlace = Order == 1 && !std::is_arithmetic_v<T>;
  friend constexpr Jet operator+(const Jet& a) { return a; }
  friend constexpr Jet operator-(const Jet& a) {
    if constexpr (kInPlace) {
      return build([&] { return -a.v; }, [&](int i) { return -a.g[i]; });
    } else {
      Jet r;
      r.v = -a.v;
      for (int i = 0; i < N; ++i) r.g[i] = -a.g[i];
      for (int k = 0; k < hessian_size; ++k) r.h[k] = -a.h[k];
      return r;
    }
  }
  friend constexpr Jet operator+(const Jet& a, const Jet& b) {
    if constexpr (kInPlace) {
      return build([&] { return a.v + b.v; }, [&](int i) { return a.g[i] + b.g[i]; });
    } else {
      Jet r = a;
      r += b;
      return r;
    }
  }
  friend constexpr Jet operator-(const Jet& a, const Jet& b) {
    if constexpr (kInPlace) {
      return build([&] { return a.v - b.v; }, [&](int i) { return a.g[i] - b.g[i]; });
    } else {
      Jet r = a;
      r -= b;
      return r;
    }
  }
  friend constexpr Jet operator+(const Jet& a, const T& s) {
    if constexpr (kInPlace) {
      return build([&] { return a.v + s; }, [&](int i) { return a.g[i]; });
    } else {
      Jet r = a;
      r += s;
      return r;
    }
  }
  friend constexpr Jet operator+(const T& s, const Jet& a) { return a + s; }
  friend constexpr Jet operator-(const Jet& a, const T& s) {
    if constexpr (kInPlace) {
      return build([&] { return a.v - s; }, [&](int i) { return a.g[i]; });
    } else {
      Jet r = a;
      r -= s;
      return r;
    }
  }
  friend constexpr Jet operator-(const T& s, const Jet& a) {
    Jet r = -a;
    r.v += s;
    return r;
  }
  friend constexpr Jet operator*(const Jet& a, const T& s) {
    if constexpr (kInPlace) {
      return build([&] { return a.v * s; }, [&](int i) { return a.g[i] * s; });
    } else {
      Jet r = a;
      r *= s;
      return r;
    }
  }
  friend constexpr Jet operator*(const T& s, const Jet& a) { return a * s; }
  friend constexpr Jet operator/(const Jet& a, const T& s) { return a * (T(1) / s); }
  friend constexpr Jet operator/(const T& s, const Jet& a) { return s * reciprocal(a); }

  // Arithmetic with plain numbers when T is not itself that number type
  // (nested numbers): the plain number meets each part as it is, which T may
  // take faster than a T made of it (an EomJet scales its parts).
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  friend constexpr Jet operator*(const Jet& a, A s) {
    if constexpr (kInPlace) {
      return build([&] { return a.v * s; }, [&](int i) { return a.g[i] * s; });
    } else {
      return a * T(s);
    }
  }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  friend constexpr Jet operator*(A s, const Jet& a) {
    return a * s;
  }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  friend constexpr Jet operator/(const Jet& a, A s) {
    return a * (1.0 / static_cast<double>(s));
  }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  friend constexpr Jet operator/(A s, const Jet& a) {
    return T(s) / a;
  }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  friend constexpr Jet operator+(const Jet& a, A s) {
    if constexpr (kInPlace) {
      return build([&] { return a.v + s; }, [&](int i) { return a.g[i]; });
    } else {
      return a + T(s);
    }
  }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  friend constexpr Jet operator+(A s, const Jet& a) {
    return a + s;
  }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  friend constexpr Jet operator-(const Jet& a, A s) {
    if constexpr (kInPlace) {
      return build([&] { return a.v - s; }, [&](int i) { return a.g[i]; });
    } else {
      return a - T(s);
    }
  }
  template <class A>
    requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
  friend constexpr Jet operator-(A s, const Jet& a) {
    if constexpr (kInPlace) {
      return build([&] { return s - a.v; }, [&](int i) { return -a.g[i]; });
    } else {
      return T(s) - a;
    }
  }

  /// Product rule to second order:
  /// (ab)_ij = a b_ij + b a_ij + a_i b_j + a_j b_i.
  friend constexpr Jet operator*(const Jet& a, const Jet& b) {
    if constexpr (kInPlace)
      return build([&] { return a.v * b.v; }, [&](int i) { return a.v * b.g[i] + b.v * a.g[i]; });
    Jet r;
    r.v = a.v * b.v;
    for (int i = 0; i < N; ++i) r.g[i] = a.v * b.g[i] + b.v * a.g[i];
    if constexpr (Order == 2) {
      int k = 0;
      for (int i = 0; i < N; ++i)
        for (int j = i; j < N; ++j, ++k)
          r.h[k] = a.v * b.h[k] + b.v * a.h[k] + a.g[i] * b.g[j] + a.g[j] * b.g[i];
    }
    return r;
  }
  friend constexpr Jet operator/(const Jet& a, const Jet& b) { return a * reciprocal(b); }

  // -- comparisons act on values (branches in user code) ---------------------
  friend constexpr bool operator==(const Jet& a, const Jet& b) { return a.v == b.v; }
  friend constexpr auto operator<=>(const Jet& a, const Jet& b) { return a.v <=> b.v; }
  friend constexpr bool operator==(const Jet& a, const T& b) { return a.v == b; }
  friend constexpr auto operator<=>(const Jet& a, const T& b) { return a.v <=> b; }

  friend std::ostream& operator<<(std::ostream& os, const Jet& a) { return os << a.v << "[jet]"; }

  /// f(a) given f(a.v), f'(a.v), f''(a.v): the chain rule to second order,
  /// f(a)_ij = f' a_ij + f'' a_i a_j.
  friend constexpr Jet chain(const Jet& a, const T& f0, const T& f1, const T& f2) {
    if constexpr (kInPlace) return build([&] { return f0; }, [&](int i) { return f1 * a.g[i]; });
    Jet r;
    r.v = f0;
    for (int i = 0; i < N; ++i) r.g[i] = f1 * a.g[i];
    if constexpr (Order == 2) {
      int k = 0;
      for (int i = 0; i < N; ++i)
        for (int j = i; j < N; ++j, ++k) r.h[k] = f1 * a.h[k] + f2 * a.g[i] * a.g[j];
    }
    return r;
  }

  /// f(a, b) given the value, the partials f_a, f_b and second partials.
  friend constexpr Jet chain2(const Jet& a, const Jet& b, const T& f0, const T& fa, const T& fb, const T& faa,
                              const T& fab, const T& fbb) {
    if constexpr (kInPlace)
      return build([&] { return f0; }, [&](int i) { return fa * a.g[i] + fb * b.g[i]; });
    Jet r;
    r.v = f0;
    for (int i = 0; i < N; ++i) r.g[i] = fa * a.g[i] + fb * b.g[i];
    if constexpr (Order == 2) {
      int k = 0;
      for (int i = 0; i < N; ++i)
        for (int j = i; j < N; ++j, ++k)
          r.h[k] = fa * a.h[k] + fb * b.h[k] + faa * a.g[i] * a.g[j] + fbb * b.g[i] * b.g[j] +
                   fab * (a.g[i] * b.g[j] + a.g[j] * b.g[i]);
    }
    return r;
  }

  friend constexpr Jet reciprocal(const Jet& a) {
    const T r = T(1) / a.v;
    return chain(a, r, -r * r, T(2) * r * r * r);
  }

  /// The first-order Jet with value fv() and derivatives fg(0) … fg(N − 1),
  /// each part constructed in place from the expression that computes it.
  template <class FV, class FG>
  static constexpr Jet build(FV&& fv, FG&& fg) {
    static_assert(Order == 1, "ad::Jet::build makes first-order Jets");
    return Jet(Build{}, fv, fg, std::make_index_sequence<N>{});
  }

  /// A first-order Jet of plain values as one of a richer value type T (a
  /// parameter seeded along the directions of the tangent flow meeting its
  /// numbers, analysis/sensitivity.hpp).
  template <class U>
    requires(Order == 1 && std::is_arithmetic_v<U> && detail::is_eom_jet<T>::value)
  constexpr Jet(const Jet<U, N, 1>& a) : Jet(build([&] { return T(a.v); }, [&](int i) { return T(a.g[i]); })) {}

 private:
  struct Build {};
  template <class FV, class FG, std::size_t... I>
  constexpr Jet(Build, FV& fv, FG& fg, std::index_sequence<I...>) : v(fv()), g{fg(static_cast<int>(I))...} {}
};

// -- a first-order Jet of plain values meeting one of EomJets ---------------------
// (a parameter seeded along the tangent flow's directions, a Jet<double, N, 1>,
// meets the flow's numbers Jet<EomJet, N, 1> along the same directions: the
// parameter's parts meet each part as plain numbers, which an EomJet scales,
// instead of as EomJets.)
template <class T, int N>
  requires detail::is_eom_jet<T>::value
constexpr Jet<T, N, 1> operator*(const Jet<double, N, 1>& a, const Jet<T, N, 1>& b) {
  return Jet<T, N, 1>::build([&] { return b.v * a.v; }, [&](int i) { return b.g[i] * a.v + b.v * a.g[i]; });
}
template <class T, int N>
  requires detail::is_eom_jet<T>::value
constexpr Jet<T, N, 1> operator*(const Jet<T, N, 1>& b, const Jet<double, N, 1>& a) {
  return a * b;
}
template <class T, int N>
  requires detail::is_eom_jet<T>::value
constexpr Jet<T, N, 1> operator+(const Jet<double, N, 1>& a, const Jet<T, N, 1>& b) {
  return Jet<T, N, 1>::build([&] { return b.v + a.v; }, [&](int i) { return b.g[i] + a.g[i]; });
}
template <class T, int N>
  requires detail::is_eom_jet<T>::value
constexpr Jet<T, N, 1> operator+(const Jet<T, N, 1>& b, const Jet<double, N, 1>& a) {
  return a + b;
}
template <class T, int N>
  requires detail::is_eom_jet<T>::value
constexpr Jet<T, N, 1> operator-(const Jet<T, N, 1>& b, const Jet<double, N, 1>& a) {
  return Jet<T, N, 1>::build([&] { return b.v - a.v; }, [&](int i) { return b.g[i] - a.g[i]; });
}
template <class T, int N>
  requires detail::is_eom_jet<T>::value
constexpr Jet<T, N, 1> operator-(const Jet<double, N, 1>& a, const Jet<T, N, 1>& b) {
  return Jet<T, N, 1>::build([&] { return a.v - b.v; }, [&](int i) { return a.g[i] - b.g[i]; });
}
template <class T, int N>
  requires detail::is_eom_jet<T>::value
constexpr Jet<T, N, 1> operator/(const Jet<T, N, 1>& b, const Jet<double, N, 1>& a) {
  return b * reciprocal(a);
}
template <class T, int N>
  requires detail::is_eom_jet<T>::value
constexpr Jet<T, N, 1> operator/(const Jet<double, N, 1>& a, const Jet<T, N, 1>& b) {
  return a * reciprocal(b);
}


template <class T, int N, int O, class A>
  requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
constexpr bool operator==(const Jet<T, N, O>& a, A b) {
  return a.v == T(b);
}
template <class T, int N, int O, class A>
  requires(std::is_arithmetic_v<A> && !std::is_same_v<A, T>)
constexpr auto operator<=>(const Jet<T, N, O>& a, A b) {
  return a.v <=> T(b);
}

}  // namespace lagrangian::ad
