#pragma once
/// \file inlined.hpp
/// The one templated path of the driver: the explicit Runge–Kutta methods
/// (dopri5, rk4, cash_karp54, fehlberg78, bulirsch_stoer) compiled for one
/// model with its q̈ inlined into the stepper's stages.
///
/// simulate() runs every model through loops compiled once in the library,
/// which reach q̈ through one indirect call per right-hand side (system.hpp).
/// For a q̈ that costs hundreds of operations (automatic differentiation,
/// constraints) that call is noise; for a hand-coded q̈ of a few dozen it is
/// not: the compiler can neither keep the model's parameters in registers
/// across the stages nor hoist their products out of the loop, and the run
/// costs about 1.15× a hand-written Boost.Odeint program. Wrapping the
/// model,
/// \code
/// #include <lagrangian/integrate/inlined.hpp>
/// auto report = lagrangian::simulate(lagrangian::inlined(MyModel{}), initial, options);
/// \endcode
/// compiles the same loops (integrate/detail/explicit_loops.hpp: one template, the
/// library's instantiation and this one) in the user's translation unit
/// with q̈ inlined, which brings a hand-coded q̈ within 1.1× of raw Odeint.
/// It costs the translation unit a few seconds of compile time (Odeint's
/// headers and five steppers) and, for an AD model, far more (the whole
/// AD pass is flattened into each loop); docs/performance.md has both. Every
/// other method, the events, constraints and monitors run as they do
/// without the wrapper, with the same results to the last bit
/// (tests/test_driver_paths.cpp).

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/integrate/detail/explicit_loops.hpp"
#include "lagrangian/integrate/detail/model_system.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

namespace detail {

/// ẋ = [q̇; q̈(q, q̇, t)] with the model's hand-coded accelerations(), on a
/// copy of the model: the loop's own object, whose parameters no store into
/// the state can alias, so the compiler keeps them out of the stages instead
/// of reloading them at every evaluation.
template <class M, class X>
struct HandCodedRhs {
  M model;
  std::uint64_t* evaluations;
  void operator()(const X& x, X& dxdt, double t) const {
    constexpr int n = coordinate_count_v<M>;
    Vec<double, n> q, qd, qdd;
    split_state(x.data(), q, qd);
    model.accelerations(q, qd, t, qdd);
    for (int i = 0; i < n; ++i) {
      dxdt[i] = x[n + i];
      dxdt[n + i] = qdd[i];
    }
    ++*evaluations;
  }
};

}  // namespace detail

/// A model M whose explicit methods are compiled with its q̈ inlined; see
/// inlined(). It is M in every other respect.
template <class M>
struct Inlined : M {
  static_assert(coordinate_count_v<M> != Dynamic,
                "lagrangian::inlined() needs a model with a compile-time number of coordinates: the inlined loops "
                "run on std::array<double, 2n>");
  using inlined_model = M;
  explicit Inlined(M model) : M(std::move(model)) {}

  /// Runs run.options().method from x (2n values) to the run's end, with the
  /// right-hand side of `system` (the model's System) inlined. Called by the
  /// driver (System::integrate_inlined).
  template <class S>
  static void run_explicit(detail::Run& run, const S& system, const M& model, std::vector<double>& x) {
    constexpr int n = coordinate_count_v<M>;
    using X = std::array<double, 2 * n>;
    std::uint64_t* evaluations = &run.report().rhs_evaluations;
    if constexpr (has_explicit_accelerations_v<M> && !has_constraints_v<M>) {
      detail::run_explicit_array<n>(run, x, detail::HandCodedRhs<M, X>{model, evaluations});
    } else {
      detail::run_explicit_array<n>(run, x, detail::DirectRhs<S, X>{&system, evaluations});
    }
  }
};

/// The model, with its explicit methods compiled in the caller's
/// translation unit with q̈ inlined (see the file comment).
template <class M>
Inlined<M> inlined(M model) {
  return Inlined<M>(std::move(model));
}

}  // namespace lagrangian
