#pragma once
// Root location for events, compiled once in src/events.cpp: the event code
// of every model calls it through a function pointer instead of
// instantiating Boost.Math's TOMS 748 for each of its lambdas.

#include <utility>

namespace lagrangian::detail {

/// A scalar function of time: eval(context, t).
struct TimeFunction {
  const void* context;
  double (*eval)(const void* context, double t);
  double operator()(double t) const { return eval(context, t); }
};

template <class F>
TimeFunction time_function(const F& f) {
  return {&f, [](const void* c, double t) { return (*static_cast<const F*>(c))(t); }};
}

/// The state at time t inside a step: eval(context, t, x_out).
struct Interpolator {
  const void* context;
  void (*eval)(const void* context, double t, double* out);
  void operator()(double t, double* out) const { eval(context, t, out); }
};

template <class F>
Interpolator interpolator(const F& f) {
  return {&f, [](const void* c, double t, double* out) { (*static_cast<const F*>(c))(t, out); }};
}

/// Boost.Math TOMS 748 on [a, b] with f(a) = fa and f(b) = fb of opposite
/// signs (or one zero): the final bracket, narrowed until its width is at
/// most `relative` · max(1, min(|lo|, |hi|)) (at most 100 iterations).
std::pair<double, double> bracket_root(TimeFunction f, double a, double b, double fa, double fb, double relative);

}  // namespace lagrangian::detail
