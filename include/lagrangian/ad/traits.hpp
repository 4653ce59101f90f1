#pragma once
// What the AD number types share: the type traits (is_jet_v, ADNumber,
// scalar_of), value_of, and the helpers of their storage. See ad.hpp.

#include <type_traits>

namespace lagrangian::ad {

template <class T, int N, int Order = 1>
class Jet;

namespace detail {
template <class X>
struct is_jet : std::false_type {};
template <class T, int N, int O>
struct is_jet<Jet<T, N, O>> : std::true_type {};

/// Keeps a cold helper out of the flattened Euler–Lagrange pass (dynamics.hpp
/// inlines everything else into it): the pass stays small enough to compile
/// quickly, at the price of a call where the helper is rarely needed.
#if defined(__GNUC__)
#define LAGRANGIAN_COLD __attribute__((noinline))
#else
#define LAGRANGIAN_COLD
#endif

/// Index of h_ij (i <= j) in packed upper-triangular storage of an N×N matrix.
constexpr int packed(int i, int j, int n) { return i * n - (i * (i - 1)) / 2 + (j - i); }
}  // namespace detail

/// True for Jet types (at any nesting depth).
template <class X>
inline constexpr bool is_jet_v = detail::is_jet<std::remove_cvref_t<X>>::value;

template <int N, bool RunTimeWidth = false>
class EomJet;
namespace detail {
template <class X>
struct is_eom_jet : std::false_type {};
template <int N, bool R>
struct is_eom_jet<EomJet<N, R>> : std::true_type {};
}  // namespace detail

/// The AD number types of this header: Jet and EomJet. The <cmath>
/// functions below are written once for both.
template <class X>
concept ADNumber = is_jet_v<X> || detail::is_eom_jet<std::remove_cvref_t<X>>::value;

/// Underlying floating-point type of a (possibly nested) Jet, or X itself.
template <class X>
struct scalar_of {
  using type = X;
};
template <class T, int N, int O>
struct scalar_of<Jet<T, N, O>> {
  using type = typename scalar_of<T>::type;
};

/// Plain value of a number: the value part of an AD number, recursively.
template <class X>
constexpr auto value_of(const X& x) {
  if constexpr (ADNumber<X>) {
    return value_of(x.v);
  } else {
    return x;
  }
}

}  // namespace lagrangian::ad
