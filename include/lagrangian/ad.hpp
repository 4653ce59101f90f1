#pragma once
/// \file ad.hpp
/// Forward-mode automatic differentiation used to derive the equations of
/// motion. This header and its folder ad/ (traits, jet, eom_jet, cmath,
/// eigen) are the only place the AD backend is named: the rest of the library
/// speaks of `ad::Jet` and of the helpers in them, so the backend can be
/// swapped without touching the dynamics.
///
/// `Jet<T, N, Order>` is a truncated Taylor polynomial in N directions:
///   x = v + Σ_i g_i ε_i + ½ Σ_ij h_ij ε_i ε_j      (Order = 2)
/// with the symmetric second-order part stored packed (N(N+1)/2 entries).
/// Order 1 is the ordinary dual number (value and gradient). It is a value
/// type without expression templates, so user model code may use `auto`
/// locals, `S x = 0`, `pow`, `abs`, `using std::cos` and branches freely.
/// `T` may itself be a Jet (nesting), which is how higher derivatives are
/// taken where needed.
///
/// `EomJet<N>` is the number type of the single pass that derives the
/// Euler–Lagrange equations (see dynamics.hpp); it tracks which parts of a
/// number are structurally zero so the O(N²) work happens only where needed.
///
/// Why not Eigen's AutoDiffScalar: nested AutoDiffScalar rejects `S x = 0.0`,
/// `pow` and `abs`, returns expression types that dangle when bound to `auto`,
/// and needs n(n+1) directions for a mass matrix where the symmetric
/// second-order Jet needs (n+1)(n+2)/2. The numbers are in docs/architecture.md.

#include "lagrangian/ad/cmath.hpp"    // IWYU pragma: export
#include "lagrangian/ad/eigen.hpp"    // IWYU pragma: export
#include "lagrangian/ad/eom_jet.hpp"  // IWYU pragma: export
#include "lagrangian/ad/jet.hpp"      // IWYU pragma: export
#include "lagrangian/ad/path.hpp"     // IWYU pragma: export
#include "lagrangian/ad/traits.hpp"   // IWYU pragma: export
