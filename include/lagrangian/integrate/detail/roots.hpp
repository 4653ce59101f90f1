#pragma once
// Root location for events, compiled once in src/integrate/events.cpp: the event code
// of every model calls it through a function pointer instead of
// instantiating Boost.Math's TOMS 748 for each of its lambdas.

#include <utility>

namespace lagrangian::detail {

/// A non-owning reference to a callable with the given signature, passed
/// across the compiled-once boundary as a context pointer and a function
/// pointer (no allocation, no template on the callable's type).
template <class Signature>
struct FunctionRef;

template <class R, class... Args>
struct FunctionRef<R(Args...)> {
  const void* context;
  R (*eval)(const void* context, Args... args);
  R operator()(Args... args) const { return eval(context, args...); }
};

/// A FunctionRef to f, which must outlive it.
template <class Signature, class F>
FunctionRef<Signature> function_ref(const F& f) {
  return {&f, [](const void* c, auto... args) { return (*static_cast<const F*>(c))(args...); }};
}

/// A scalar function of time.
using TimeFunction = FunctionRef<double(double)>;

template <class F>
TimeFunction time_function(const F& f) {
  return function_ref<double(double)>(f);
}

/// The state at time t inside a step: f(t, x_out).
using Interpolator = FunctionRef<void(double, double*)>;

template <class F>
Interpolator interpolator(const F& f) {
  return function_ref<void(double, double*)>(f);
}

/// Boost.Math TOMS 748 on [a, b] with f(a) = fa and f(b) = fb of opposite
/// signs (or one zero): the final bracket, narrowed until its width is at
/// most `relative` · max(1, min(|lo|, |hi|)) (at most 100 iterations).
std::pair<double, double> bracket_root(TimeFunction f, double a, double b, double fa, double fb, double relative);

}  // namespace lagrangian::detail
