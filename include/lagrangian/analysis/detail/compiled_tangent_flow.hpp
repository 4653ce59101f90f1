#pragma once
// The tangent flow compiled once, in the library, for the built-in models.
//
// lyapunov_spectrum(), floquet_multipliers() and sensitivities() of a model
// instantiate its tangent evaluations: the state's Jacobian, one direction
// (state_jvp), and for parameter columns the same on the model's seeded
// twin (sensitivity.hpp). That is the most a model's own code costs to
// compile, and it was compiled again by every file that called one of them.
// The model headers declare the three `extern` for their concrete models
// with LAGRANGIAN_EXTERN_TANGENT_FLOW, and src/models/tangent_*.cpp
// instantiate them once with LAGRANGIAN_INSTANTIATE_TANGENT_FLOW, as
// integrate/detail/compiled_models.hpp does for simulate(). Models that are
// not listed (a user's, PendulumChain<6>, ...) are compiled where they are
// used. A library configured with LAGRANGIAN_COMPILED_TANGENT_FLOW=OFF (the
// sanitizer build, whose tests do not call them on built-in models) defines
// LAGRANGIAN_NO_COMPILED_TANGENT_FLOW for itself and its users: the
// declarations are dropped and every program compiles its own copy.
#include "lagrangian/analysis/fwd.hpp"
#include "lagrangian/model.hpp"

namespace lagrangian {

template <class M>
LyapunovResult lyapunov_spectrum(const M& model, const State<coordinate_count_v<M>>& initial,
                                 const LyapunovOptions& options);
template <class M>
FloquetResult floquet_multipliers(const M& model, const State<coordinate_count_v<M>>& initial,
                                  const FloquetOptions& options);
template <class M>
SensitivityResult sensitivities(const M& model, const State<coordinate_count_v<M>>& initial,
                                const SensitivityOptions& options);

}  // namespace lagrangian

#define LAGRANGIAN_TANGENT_FLOW_SIGNATURES(prefix, ...)                                                        \
  prefix ::lagrangian::LyapunovResult lagrangian::lyapunov_spectrum<__VA_ARGS__>(                             \
      const __VA_ARGS__&, const ::lagrangian::State<::lagrangian::coordinate_count_v<__VA_ARGS__>>&,          \
      const ::lagrangian::LyapunovOptions&);                                                                 \
  prefix ::lagrangian::FloquetResult lagrangian::floquet_multipliers<__VA_ARGS__>(                            \
      const __VA_ARGS__&, const ::lagrangian::State<::lagrangian::coordinate_count_v<__VA_ARGS__>>&,          \
      const ::lagrangian::FloquetOptions&);                                                                  \
  prefix ::lagrangian::SensitivityResult lagrangian::sensitivities<__VA_ARGS__>(                              \
      const __VA_ARGS__&, const ::lagrangian::State<::lagrangian::coordinate_count_v<__VA_ARGS__>>&,          \
      const ::lagrangian::SensitivityOptions&);

#if defined(LAGRANGIAN_NO_COMPILED_TANGENT_FLOW) && LAGRANGIAN_NO_COMPILED_TANGENT_FLOW
#define LAGRANGIAN_EXTERN_TANGENT_FLOW(...)
#else
#define LAGRANGIAN_EXTERN_TANGENT_FLOW(...) LAGRANGIAN_TANGENT_FLOW_SIGNATURES(extern template, __VA_ARGS__)
#endif
#define LAGRANGIAN_INSTANTIATE_TANGENT_FLOW(...) LAGRANGIAN_TANGENT_FLOW_SIGNATURES(template, __VA_ARGS__)
