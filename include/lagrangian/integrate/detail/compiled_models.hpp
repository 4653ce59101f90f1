#pragma once
// simulate() compiled once, in the library, for the built-in models.
//
// simulate_impl<M> (simulate.hpp) checks the input and runs the model's
// adapter, ModelSystem<M> (model_system.hpp: the model's own derivatives,
// constraints, events and monitors, and for a model that opts in to the
// structure-preserving methods its variational integrator), through the
// driver, whose stepper loops are compiled once in the library
// (src/integrate/); instantiating it for a model type costs what that
// model's own code costs to compile (3-5 s for a small model,
// docs/performance.md). The model headers (models/lagrangian/models/)
// declare it `extern` for their concrete models with
// LAGRANGIAN_EXTERN_SIMULATE, and src/models/*.cpp instantiate it once with
// LAGRANGIAN_INSTANTIATE_SIMULATE, so a program that simulates a built-in
// model links the library's copy instead of compiling its own. Models that
// are not listed (a user's, PendulumChain<6>, ...) are compiled where they
// are used. With LAGRANGIAN_TRAP_FE_INVALID the declarations are dropped:
// every program then compiles its own copy, with the trap. eom_sample()
// (eom_sample.hpp: q̈, p, M and h at a state, for the catalog's agreement
// test) is declared and compiled beside simulate_impl, whose evaluation
// functions it calls.
//
// LAGRANGIAN_BUILT_IN_MODEL also opts each listed model in to the
// structure-preserving methods (structure_preserving_v, model.hpp): their
// code is compiled once here, so scenes and the CLI keep the run-time choice
// of method for every built-in model at no cost to a user's build.
#include <vector>

#include "lagrangian/model.hpp"
#include "lagrangian/integrate/report.hpp"

namespace lagrangian::detail {

template <int N>
struct ObserverRef;

/// The equations of motion of a model at one state (eom_sample.hpp):
/// q̈ (with its bilateral constraints, contacts open), p = ∂L/∂q̇,
/// M = ∂²L/∂q̇² row by row, and h = p·q̇ − L.
struct EomSample {
  std::vector<double> qdd, p, mass;
  double h = 0;
};

/// The EomSample of `model` at (q, q̇, t), n values each (eom_sample.hpp).
template <class M>
EomSample eom_sample(const M& model, const double* q, const double* qd, double t);

template <class M>
RunReport simulate_impl(const M& model, const State<coordinate_count_v<M>>& initial, const SimulationOptions& options,
                        ObserverRef<coordinate_count_v<M>> observer);

}  // namespace lagrangian::detail

#define LAGRANGIAN_SIMULATE_SIGNATURE(...)                                                                   \
  ::lagrangian::RunReport lagrangian::detail::simulate_impl<__VA_ARGS__>(                                  \
      const __VA_ARGS__&, const ::lagrangian::State<::lagrangian::coordinate_count_v<__VA_ARGS__>>&, const ::lagrangian::SimulationOptions&, \
      ::lagrangian::detail::ObserverRef<::lagrangian::coordinate_count_v<__VA_ARGS__>>)

#define LAGRANGIAN_EOM_SAMPLE_SIGNATURE(...) \
  ::lagrangian::detail::EomSample lagrangian::detail::eom_sample<__VA_ARGS__>(const __VA_ARGS__&, const double*, const double*, double)

#if defined(LAGRANGIAN_TRAP_FE_INVALID) && LAGRANGIAN_TRAP_FE_INVALID
#define LAGRANGIAN_EXTERN_SIMULATE(...)
#else
// (eom_sample() with it: both are compiled in the same library file.)
#define LAGRANGIAN_EXTERN_SIMULATE(...)                          \
  extern template LAGRANGIAN_SIMULATE_SIGNATURE(__VA_ARGS__); \
  extern template LAGRANGIAN_EOM_SAMPLE_SIGNATURE(__VA_ARGS__);
#endif
#define LAGRANGIAN_OPT_IN_STRUCTURE_PRESERVING(...) \
  template <>                                       \
  inline constexpr bool lagrangian::structure_preserving_v<__VA_ARGS__> = true;
#define LAGRANGIAN_BUILT_IN_MODEL(...)                  \
  LAGRANGIAN_OPT_IN_STRUCTURE_PRESERVING(__VA_ARGS__) \
  LAGRANGIAN_EXTERN_SIMULATE(__VA_ARGS__)
#define LAGRANGIAN_INSTANTIATE_SIMULATE(...) template LAGRANGIAN_SIMULATE_SIGNATURE(__VA_ARGS__);
