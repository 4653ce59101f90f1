#pragma once
// Internal: the differentiation rules of ad::EomJet (eom_jet.hpp, which
// includes this file at its end): the product rule and the chain rules of
// one- and two-argument functions, part by part, skipping parts known to be
// zero. The member functions are declared, and documented, in the class.

// IWYU pragma: private, include "lagrangian/ad/eom_jet.hpp"

// (g++ cannot follow which parts a number's storage state makes valid
// through the flattened passes, and warns of parts that are never read.)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace lagrangian::ad {

template <int N, bool R>
constexpr EomJet<N, R> EomJet<N, R>::product(const EomJet& a, const EomJet& b) {
  EomJet r{Uninitialized{}};
  r.level = (a.level == 2 || b.level == 2) ? 2 : a.level + b.level;
  r.state_ = joint(a.state_, b.state_);
  r.v = a.v * b.v;
  r.d = a.v * b.d + b.v * a.d;
  const int s = r.state_;
  if (&a == &b) {  // a square: (a²)' = 2 a a', (a²)'' = 2 a a'' + 2 a' a'ᵀ
    const double a2 = 2.0 * a.v;
    each(s, [&](int i) { r.gq_[i] = a2 * a.gq_[i]; });
    if (a.level >= 1) {
      const double d2 = 2.0 * a.d;
      each(s, [&](int i) {
        r.gv_[i] = a2 * a.gv_[i];
        r.c_[i] = a2 * a.c_[i] + d2 * a.gv_[i];
      });
      r.lo_ = a.lo_;
      r.hi_ = a.hi_;
      r.dense_ = false;
      r.nterms_ = 0;
      if (a.level == 2) r.add_hessian_of(a, a2);
      r.push_square(2.0, a);
    }
    return r;
  }
  if (s >= 0 || (a.state_ == kDense && b.state_ == kDense)) {
    // Both factors stored alike (or one holds nothing): one fused pass.
    if (a.state_ == kNone) {
      each(s, [&](int i) { r.gq_[i] = a.v * b.gq_[i]; });
    } else if (b.state_ == kNone) {
      each(s, [&](int i) { r.gq_[i] = b.v * a.gq_[i]; });
    } else {
      each(s, [&](int i) { r.gq_[i] = a.v * b.gq_[i] + b.v * a.gq_[i]; });
    }
    if (a.level >= 1 && b.level >= 1) {
      each(s, [&](int i) {
        r.gv_[i] = a.v * b.gv_[i] + b.v * a.gv_[i];
        r.c_[i] = a.v * b.c_[i] + b.v * a.c_[i] + a.gv_[i] * b.d + b.gv_[i] * a.d;
      });
    } else if (a.level >= 1) {
      each(s, [&](int i) {
        r.gv_[i] = b.v * a.gv_[i];
        r.c_[i] = b.v * a.c_[i] + a.gv_[i] * b.d;
      });
    } else if (b.level >= 1) {
      each(s, [&](int i) {
        r.gv_[i] = a.v * b.gv_[i];
        r.c_[i] = a.v * b.c_[i] + b.gv_[i] * a.d;
      });
    }
  } else {
    // Mixed storage: the result is dense; each factor adds its share.
    put(r.gq_, s, b.v, a.gq_, a.state_);
    add(r.gq_, a.v, b.gq_, b.state_);
    if (a.level >= 1) {
      put(r.gv_, s, b.v, a.gv_, a.state_);
      put2(r.c_, s, b.v, a.c_, b.d, a.gv_, a.state_);
      if (b.level >= 1) {
        add(r.gv_, a.v, b.gv_, b.state_);
        add2(r.c_, a.v, b.c_, a.d, b.gv_, b.state_);
      }
    } else if (b.level >= 1) {
      put(r.gv_, s, a.v, b.gv_, b.state_);
      put2(r.c_, s, a.v, b.c_, a.d, b.gv_, b.state_);
    }
  }
  if (a.level >= 1 && b.level >= 1) {
    r.set_hull(a, b);
  } else if (a.level >= 1) {
    r.lo_ = a.lo_;
    r.hi_ = a.hi_;
  } else if (b.level >= 1) {
    r.lo_ = b.lo_;
    r.hi_ = b.hi_;
  }
  if (r.level == 2) {
    r.dense_ = false;
    r.nterms_ = 0;
    // H from the factors' own Hessians ...
    if (a.level == 2) r.add_hessian_of(a, b.v);
    if (b.level == 2) r.add_hessian_of(b, a.v);
    // ... plus the outer products of the velocity gradients.
    if (a.level >= 1 && b.level >= 1) {
      r.push_symmetric(1.0, a, b);
    }
  }
  return r;
}

template <int N, bool R>
constexpr EomJet<N, R> EomJet<N, R>::chain_rule(const EomJet& a, double f0, double f1, double f2) {
  EomJet r{Uninitialized{}};
  r.level = a.level == 0 ? 0 : 2;
  r.state_ = a.state_;
  r.v = f0;
  r.d = f1 * a.d;
  each(a.state_, [&](int i) { r.gq_[i] = f1 * a.gq_[i]; });
  if (a.level >= 1) {
    const double f2d = f2 * a.d;
    each(a.state_, [&](int i) {
      r.gv_[i] = f1 * a.gv_[i];
      r.c_[i] = f1 * a.c_[i] + f2d * a.gv_[i];
    });
    r.lo_ = a.lo_;
    r.hi_ = a.hi_;
    r.dense_ = false;
    r.nterms_ = 0;
    if (a.level == 2) r.add_hessian_of(a, f1);
    if (f2 != 0.0) r.push_square(f2, a);
  }
  return r;
}

template <int N, bool R>
EomJet<N, R> EomJet<N, R>::chain2_rule(EomJet a, EomJet b, double f0, double fa, double fb,
                                                 double faa, double fab, double fbb) {
  const int L = (a.level == 0 && b.level == 0) ? 0 : 2;
  a.convert(kDense);
  b.convert(kDense);
  a.raise(L >= 1 ? 1 : 0);
  b.raise(L >= 1 ? 1 : 0);
  EomJet r{Uninitialized{}};
  r.level = L;
  r.state_ = kDense;
  r.v = f0;
  r.d = fa * a.d + fb * b.d;
  dense_loop([&](int i) { r.gq_[i] = fa * a.gq_[i] + fb * b.gq_[i]; });
  if (L == 2) {
    dense_loop([&](int i) {
      r.gv_[i] = fa * a.gv_[i] + fb * b.gv_[i];
      r.c_[i] = fa * a.c_[i] + fb * b.c_[i] + faa * a.gv_[i] * a.d + fbb * b.gv_[i] * b.d +
                fab * (a.gv_[i] * b.d + b.gv_[i] * a.d);
    });
    r.set_hull(a, b);
    r.dense_ = false;
    r.nterms_ = 0;
    if (a.level == 2) r.add_hessian_of(a, fa);
    if (b.level == 2) r.add_hessian_of(b, fb);
    r.push_square(faa, a);
    r.push_square(fbb, b);
    r.push_symmetric(fab, a, b);
  }
  return r;
}

}  // namespace lagrangian::ad

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
