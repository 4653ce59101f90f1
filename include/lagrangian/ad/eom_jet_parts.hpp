#pragma once
// Internal: how ad::EomJet (eom_jet.hpp, which includes this file at its
// end) keeps and combines its parts: re-storing the first-order parts, the
// velocity support, the lazily summed Hessian block H = ∂²x/∂q̇∂q̇ (dense
// rows on the support plus pending rank-one terms, flushed into the rows
// when the slots run out), and the sums, scalings and copies built on them.
// The member functions are declared, and documented, in the class.

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
constexpr EomJet<N, R>::EomJet(EomJet&& o) noexcept : level(o.level), v(o.v), d(o.d) {
  if constexpr (kPooled) {
    second_ = std::move(o.second_);
    copy_first(o);
  } else {
    copy_parts(o);
  }
}

template <int N, bool R>
constexpr EomJet<N, R>& EomJet<N, R>::operator=(EomJet&& o) noexcept {
  level = o.level;
  v = o.v;
  d = o.d;
  if constexpr (kPooled) {
    second_ = std::move(o.second_);
    copy_first(o);
  } else {
    copy_parts(o);
  }
  return *this;
}

template <int N, bool R>
constexpr void EomJet<N, R>::zero_rows(std::array<double, N * N>& H, int lo, int hi) {
  if constexpr (kPooled) {
    for (int i = lo; i < hi; ++i)
      for (int j = lo; j <= i; ++j) H[i * N + j] = 0.0;
  } else {
    for (int i = lo * N; i < hi * N; ++i) H[i] = 0.0;
  }
}

template <int N, bool R>
constexpr void EomJet<N, R>::widen(int lo, int hi) {
  if (lo == lo_ && hi == hi_) return;
  if (level == 2 && dense_) {
    if (lo_ == hi_) {
      zero_rows(H(), lo, hi);
    } else if constexpr (kPooled) {
      // The triangle on [lo, hi) less the one on [lo_, hi_): new rows,
      // and the old rows' columns [lo, lo_).
      auto& h = H();
      for (int i = lo; i < hi; ++i) {
        double* row = h.data() + i * N;
        const int jhi = (i >= lo_ && i < hi_) ? lo_ : i + 1;
        for (int j = lo; j < jhi; ++j) row[j] = 0.0;
      }
    } else {
      zero_rows(H(), lo, lo_);
      zero_rows(H(), hi_, hi);
    }
  }
  lo_ = lo;
  hi_ = hi;
}

template <int N, bool R>
void EomJet<N, R>::flush() {
  ensure_dense();
  if constexpr (lazy_terms > 0) {
    std::array<const double*, 2 * lazy_terms> x{}, y{};
    std::array<double, 2 * lazy_terms> f{};
    std::array<int, 2 * lazy_terms> xlo{}, xhi{}, ylo{}, yhi{};
    int np = 0;
    const Term* ts = terms();
    for (int k = 0; k < nterms_; ++k) {
      const Term& t = ts[k];
      x[np] = t.u.data();
      y[np] = t.sq ? t.u.data() : t.w.data();
      xlo[np] = t.ulo;
      xhi[np] = t.uhi;
      ylo[np] = t.wlo;
      yhi[np] = t.whi;
      f[np++] = t.f;
      if (!t.sq) {
        x[np] = t.w.data();
        y[np] = t.u.data();
        xlo[np] = t.wlo;
        xhi[np] = t.whi;
        ylo[np] = t.ulo;
        yhi[np] = t.uhi;
        f[np++] = t.f;
      }
    }
    if constexpr (kPooled) {
      // Large n: each piece touches only its rows and columns (its
      // vectors are zero outside their supports) and, H being symmetric,
      // only the lower triangle, in loops of run-time length over
      // contiguous entries.
      // Pieces with the same supports (the x and y components of one
      // velocity, squared) are summed in pairs, each row loaded once per pair.
      auto& h = H();
      std::array<bool, 2 * lazy_terms> done{};
      for (int p = 0; p < np; ++p) {
        if (done[p]) continue;
        int q = p + 1;
        while (q < np && (done[q] || xlo[q] != xlo[p] || xhi[q] != xhi[p] || ylo[q] != ylo[p] || yhi[q] != yhi[p]))
          ++q;
        for (int i = xlo[p]; i < xhi[p]; ++i) {
          const int end = yhi[p] < i + 1 ? yhi[p] : i + 1;  // the lower triangle
          if (q < np) {
            axpy2(h.data() + i * N, f[p] * x[p][i], y[p], f[q] * x[q][i], y[q], ylo[p], end);
          } else {
            axpy(h.data() + i * N, f[p] * x[p][i], y[p], ylo[p], end);
          }
        }
        if (q < np) done[q] = true;
      }
      nterms_ = 0;
      return;
    }
    for (int i = lo_; i < hi_; ++i) {
      double* row = H().data() + i * N;
      double acc[N];  // local: provably apart from the pieces' vectors
      for (int j = 0; j < N; ++j) acc[j] = row[j];  // (N ≤ kInlineHessianMax: fixed width)
      for (int p = 0; p < np; ++p) {
        const double c = f[p] * x[p][i];
        const double* yp = y[p];
        for (int j = 0; j < N; ++j) acc[j] += c * yp[j];
      }
      for (int j = 0; j < N; ++j) row[j] = acc[j];
    }
    nterms_ = 0;
  }
}

template <int N, bool R>
constexpr void EomJet<N, R>::full_gv(typename EomJet<N, R>::Vector& out, const EomJet& a) {
  if constexpr (kPooled) {  // (read only on the support [a.lo_, a.hi_))
    if (a.state_ == kDense) {
      for (int i = a.lo_; i < a.hi_; ++i) out[i] = a.gv_[i];
    } else if (a.state_ >= 0) {
      for (int i = a.lo_; i < a.hi_; ++i) out[i] = 0.0;
      out[a.state_] = a.gv_[a.state_];
    }
  } else if (a.state_ == kDense) {
    out = a.gv_;
  } else {
    out.fill(0.0);
    if (a.state_ >= 0) out[a.state_] = a.gv_[a.state_];
  }
}

template <int N, bool R>
constexpr void EomJet<N, R>::ensure_dense() {
  if (!dense_) {
    zero_rows(H(), lo_, hi_);
    dense_ = true;
  }
}

template <int N, bool R>
constexpr void EomJet<N, R>::push_square(double f, const EomJet& a) {
  if constexpr (lazy_terms == 0) {
    ensure_dense();
    auto& h = H();
    for (int i = a.lo_; i < a.hi_; ++i) {
      const double fi = f * a.gv_[i];
      for (int j = 0; j < N; ++j) h[i * N + j] += fi * a.gv_[j];
    }
  } else {
    Term& t = new_term();
    t.f = f;
    t.sq = true;
    t.ulo = t.wlo = a.lo_;
    t.uhi = t.whi = a.hi_;
    full_gv(t.u, a);
  }
}

template <int N, bool R>
constexpr void EomJet<N, R>::push_symmetric(double f, const EomJet& a, const EomJet& b) {
  if constexpr (lazy_terms == 0) {
    ensure_dense();
    auto& h = H();
    for (int i = lo_; i < hi_; ++i) {
      const double fa = f * a.gv_[i], fb = f * b.gv_[i];
      for (int j = 0; j < N; ++j) h[i * N + j] += fa * b.gv_[j] + fb * a.gv_[j];
    }
  } else {
    Term& t = new_term();
    t.f = f;
    t.sq = false;
    t.ulo = a.lo_;
    t.uhi = a.hi_;
    t.wlo = b.lo_;
    t.whi = b.hi_;
    full_gv(t.u, a);
    full_gv(t.w, b);
  }
}

template <int N, bool R>
constexpr void EomJet<N, R>::add_hessian_of(const EomJet& a, double f) {
  if (a.dense_) {
    auto& h = H();
    const auto& ha = a.H();
    const bool copy = !dense_ && a.lo_ == lo_ && a.hi_ == hi_;
    if (!copy && !dense_) zero_rows(h, lo_, hi_);
    dense_ = true;
    if constexpr (kPooled) {
      for (int i = a.lo_; i < a.hi_; ++i) {
        if (copy) {
          scale_range(h.data() + i * N, f, ha.data() + i * N, a.lo_, i + 1);
        } else {
          axpy(h.data() + i * N, f, ha.data() + i * N, a.lo_, i + 1);
        }
      }
    } else if (copy) {
      for (int i = lo_ * N; i < hi_ * N; ++i) h[i] = f * ha[i];
    } else {
      for (int i = a.lo_ * N; i < a.hi_ * N; ++i) h[i] += f * ha[i];
    }
  }
  if constexpr (lazy_terms > 0)
    for (int k = 0; k < a.nterms_; ++k) {
      Term& t = new_term();
      t = a.terms()[k];
      t.f *= f;
    }
}

template <int N, bool R>
constexpr void EomJet<N, R>::convert(int s) {
  if (s == state_) return;
  auto move = [&](Vector& x) {
    if (state_ >= 0) {  // single → dense
      const double keep = x[state_];
      set_zero(x, kDense);
      x[state_] = keep;
    } else {  // nothing → s
      set_zero(x, s);
    }
  };
  move(gq_);
  if (level >= 1) {
    move(gv_);
    move(c_);
  }
  state_ = s;
}

template <int N, bool R>
constexpr void EomJet<N, R>::set_hull(const EomJet& a, const EomJet& b) {
  if (a.lo_ == a.hi_) {
    lo_ = b.lo_;
    hi_ = b.hi_;
  } else if (b.lo_ == b.hi_) {
    lo_ = a.lo_;
    hi_ = a.hi_;
  } else {
    lo_ = a.lo_ < b.lo_ ? a.lo_ : b.lo_;
    hi_ = a.hi_ > b.hi_ ? a.hi_ : b.hi_;
  }
}

template <int N, bool R>
constexpr EomJet<N, R> EomJet<N, R>::scaled(const EomJet& a, double f, double s) {
  EomJet r{Uninitialized{}};
  r.level = a.level;
  r.state_ = a.state_;
  r.v = f * a.v + s;
  r.d = f * a.d;
  each(a.state_, [&](int i) { r.gq_[i] = f * a.gq_[i]; });
  if (a.level >= 1) {
    each(a.state_, [&](int i) {
      r.gv_[i] = f * a.gv_[i];
      r.c_[i] = f * a.c_[i];
    });
    r.lo_ = a.lo_;
    r.hi_ = a.hi_;
  }
  if (a.level == 2) {
    r.dense_ = false;
    r.nterms_ = 0;
    r.add_hessian_of(a, f);
  }
  return r;
}

template <int N, bool R>
constexpr EomJet<N, R> EomJet<N, R>::combined(const EomJet& a, const EomJet& b, double sign) {
  if (a.level != b.level || a.state_ != b.state_) {
    EomJet r = a;
    r.accumulate(b, sign);
    return r;
  }
  // Alike storage and level: every part in one pass.
  EomJet r{Uninitialized{}};
  r.level = a.level;
  r.state_ = a.state_;
  r.v = a.v + sign * b.v;
  r.d = a.d + sign * b.d;
  each(r.state_, [&](int i) { r.gq_[i] = a.gq_[i] + sign * b.gq_[i]; });
  if (a.level >= 1) {
    each(r.state_, [&](int i) {
      r.gv_[i] = a.gv_[i] + sign * b.gv_[i];
      r.c_[i] = a.c_[i] + sign * b.c_[i];
    });
    r.set_hull(a, b);
  }
  if (a.level == 2) {
    r.dense_ = false;
    r.nterms_ = 0;
    r.add_hessian_of(a, 1.0);
    r.add_hessian_of(b, sign);
  }
  return r;
}

template <int N, bool R>
constexpr EomJet<N, R>& EomJet<N, R>::accumulate(const EomJet& b, double sign) {
  if (&b == this) return *this *= 1.0 + sign;  // x += x, x -= x
  convert(joint(state_, b.state_));
  raise(b.level);
  v += sign * b.v;
  d += sign * b.d;
  add(gq_, sign, b.gq_, b.state_);
  if (b.level >= 1) {
    add(gv_, sign, b.gv_, b.state_);
    add(c_, sign, b.c_, b.state_);
    if (b.lo_ != b.hi_) {
      if (lo_ == hi_) {
        widen(b.lo_, b.hi_);
      } else {
        widen(b.lo_ < lo_ ? b.lo_ : lo_, b.hi_ > hi_ ? b.hi_ : hi_);
      }
    }
  }
  if (b.level == 2) add_hessian_of(b, sign);
  return *this;
}

template <int N, bool R>
constexpr void EomJet<N, R>::copy_parts(const EomJet& o) {
  copy_first(o);
  if (o.level == 2 && (o.dense_ || o.nterms_ > 0)) {
    Term* ts = terms();
    const Term* os = o.terms();
    for (int k = 0; k < nterms_; ++k) ts[k] = os[k];
    if (dense_) {
      auto& h = H();
      const auto& oh = o.H();
      if constexpr (kPooled) {
        for (int i = lo_; i < hi_; ++i) copy_range(h.data() + i * N, oh.data() + i * N, lo_, i + 1);
      } else {
        for (int i = lo_ * N; i < hi_ * N; ++i) h[i] = oh[i];
      }
    }
  }
}

template <int N, bool R>
constexpr void EomJet<N, R>::copy_first(const EomJet& o) {
  state_ = o.state_;
  if (state_ == kDense) {
    copy_vector(gq_, o.gq_);
    if (o.level >= 1) {
      copy_vector(gv_, o.gv_);
      copy_vector(c_, o.c_);
    }
  } else if (state_ >= 0) {
    gq_[state_] = o.gq_[state_];
    if (o.level >= 1) {
      gv_[state_] = o.gv_[state_];
      c_[state_] = o.c_[state_];
    }
  }
  if (o.level >= 1) {
    lo_ = o.lo_;
    hi_ = o.hi_;
  }
  if (o.level == 2) {
    dense_ = o.dense_;
    nterms_ = o.nterms_;
  }
}

}  // namespace lagrangian::ad

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
