#pragma once
// The type-erased observer of a run.

#include "lagrangian/integrate/observers.hpp"

namespace lagrangian::detail {

template <class O>
concept observer_with_begin = requires(O& o, const Columns& c) { o.begin(c); };
template <class O>
concept observer_with_finish = requires(O& o) { o.finish(); };

/// A non-owning, type-erased observer: the run loops are compiled once per
/// model, not once per (model, observer) pair. One indirect call per sample.
template <int N>
struct ObserverRef {
  void* object = nullptr;
  void (*sample)(void*, const Sample<N>&) = nullptr;
  void (*begin)(void*, const Columns&) = nullptr;

  template <class O>
  static ObserverRef of(O& o) {
    ObserverRef r;
    r.object = &o;
    r.sample = [](void* p, const Sample<N>& s) { (*static_cast<O*>(p))(s); };
    if constexpr (observer_with_begin<O>) r.begin = [](void* p, const Columns& c) { static_cast<O*>(p)->begin(c); };
    return r;
  }
  void operator()(const Sample<N>& s) const { sample(object, s); }
};

}  // namespace lagrangian::detail
