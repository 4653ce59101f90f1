#pragma once
// Internal: what the Euler–Lagrange and tangent passes inline.
//
// LAGRANGIAN_FLATTEN inlines every operation of a model's T and V into the
// pass that evaluates them: the same arithmetic, one function, several times
// faster for small models and several times longer to compile. Defining
// LAGRANGIAN_NO_FLATTEN keeps the operations as calls (the same results to
// the last bit); the test programs and the sanitizer build do, the library,
// the command and the benchmarks do not (docs/architecture.md, "Build").

#if defined(__GNUC__)
#if defined(LAGRANGIAN_NO_FLATTEN)
#define LAGRANGIAN_FLATTEN
#else
#define LAGRANGIAN_FLATTEN __attribute__((flatten))
#endif
#define LAGRANGIAN_ALWAYS_INLINE __attribute__((always_inline)) inline
#define LAGRANGIAN_NOINLINE __attribute__((noinline))
#else
#define LAGRANGIAN_FLATTEN
#define LAGRANGIAN_ALWAYS_INLINE inline
#define LAGRANGIAN_NOINLINE
#endif
