#pragma once
// Internal to the particle scenes' engine: the force kernels. Each declared
// effect kind is one kernel; a body's state is 3 Cartesian coordinates
// (m) in x = [r; v]. A kernel's accelerations are a template on the number
// type: doubles in a run, AD numbers (ad::Jet) for its tangent flow
// (particle_tangent.cpp).

#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Dense>

namespace lagrangian::scene::detail::particles {

using Eigen::Vector3d;
template <class S>
using Vector3 = Eigen::Matrix<S, 3, 1>;

template <class S>
Vector3<S> at(const S* p, int i) {
  return {p[3 * i], p[3 * i + 1], p[3 * i + 2]};
}
template <class S>
void add(S* p, int i, const Vector3<S>& f) {
  p[3 * i] += f[0];
  p[3 * i + 1] += f[1];
  p[3 * i + 2] += f[2];
}

// -- force kernels -------------------------------------------------------------
//
// Each declared effect kind is one kernel. A kernel adds its accelerations
// a = F/m (m/s²) to the right-hand side; its evaluations are counted. The
// kernels are concrete types called directly (no virtual call) from a
// right-hand side instantiated for the set of declared kinds (see
// System::select_rhs); the virtual functions below serve reports only.

struct Kernel {
  explicit Kernel(const char* k) : kind(k) {}
  virtual ~Kernel() = default;
  const char* kind;
  std::uint64_t evaluations = 0;
  /// Its potential energy (J); 0 for dissipative kernels.
  virtual double potential(const double*) const { return 0.0; }
  virtual bool dissipative() const { return false; }
};

/// F_i = m_i g, so a_i = g; V = −Σ m_i g·r_i.
struct GravityKernel final : Kernel {
  GravityKernel(const std::vector<double>& m, Vector3d g_) : Kernel("uniform_gravity"), mass(m), g(g_) {}
  std::vector<double> mass;
  Vector3d g;
  template <class S>
  void add(const S*, const S*, S* a) {
    ++evaluations;
    const int n = static_cast<int>(mass.size());
    for (int i = 0; i < n; ++i) {
      a[3 * i] += g[0];
      a[3 * i + 1] += g[1];
      a[3 * i + 2] += g[2];
    }
  }
  /// The first kernel of a right-hand side: writes ṙ = v and a = g.
  void start(const double* v, double* dr, double* a, int dim) {
    ++evaluations;
    const double g0 = g[0], g1 = g[1], g2 = g[2];
    for (int i = 0; i < dim; i += 3) {
      dr[i] = v[i];
      dr[i + 1] = v[i + 1];
      dr[i + 2] = v[i + 2];
      a[i] = g0;
      a[i + 1] = g1;
      a[i + 2] = g2;
    }
  }
  double potential(const double* r) const override {
    double V = 0;
    for (std::size_t i = 0; i < mass.size(); ++i) V -= mass[i] * g.dot(at(r, static_cast<int>(i)));
    return V;
  }
};

/// F_i = −G m_i m_j (r_i − r_j)/|r_i − r_j|³ for every pair; V = −G m_i m_j/|r_i − r_j|.
struct NewtonKernel final : Kernel {
  NewtonKernel(const std::vector<double>& m, double G_) : Kernel("newtonian_gravity"), mass(m), G(G_) {}
  std::vector<double> mass;
  double G;
  template <class S>
  void add(const S* r, const S*, S* a) {
    using std::sqrt;
    ++evaluations;
    const int n = static_cast<int>(mass.size());
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const Vector3<S> d = at(r, i) - at(r, j);
        const S d2 = d.squaredNorm();
        const Vector3<S> f = (-G / (d2 * sqrt(d2))) * d;  // per unit mass of each
        add3(a, i, Vector3<S>(mass[static_cast<std::size_t>(j)] * f));
        add3(a, j, Vector3<S>(-mass[static_cast<std::size_t>(i)] * f));
      }
  }
  double potential(const double* r) const override {
    double V = 0;
    const int n = static_cast<int>(mass.size());
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j)
        V -= G * mass[static_cast<std::size_t>(i)] * mass[static_cast<std::size_t>(j)] / (at(r, i) - at(r, j)).norm();
    return V;
  }
  template <class S>
  static void add3(S* a, int i, const Vector3<S>& f) {
    lagrangian::scene::detail::particles::add(a, i, f);
  }
};

struct SpringData {
  int a, b;  // b = -1: anchored
  Vector3d anchor;
  double k, L0;
  double inv_ma, inv_mb;  // 1/m of each end (0 for an anchor)
};

/// F_a = −k (l − L₀) d/l, d = r_a − r_b, l = |d|; V = ½ k (l − L₀)².
struct SpringKernel final : Kernel {
  explicit SpringKernel(std::vector<SpringData> s) : Kernel("springs"), springs(std::move(s)) {}
  std::vector<SpringData> springs;
  template <class S>
  void add(const S* r, const S*, S* acc) {
    ++evaluations;
    for (const auto& s : springs) {
      const Vector3<S> d = at(r, s.a) - (s.b >= 0 ? at(r, s.b) : Vector3<S>(s.anchor.cast<S>()));
      Vector3<S> f;
      if (s.L0 == 0.0) {
        f = -s.k * d;
      } else {
        const S l = d.norm();
        f = (-s.k * (l - s.L0) / l) * d;  // l = 0 gives NaN, caught as a non-finite state
      }
      lagrangian::scene::detail::particles::add(acc, s.a, Vector3<S>(s.inv_ma * f));
      if (s.b >= 0) lagrangian::scene::detail::particles::add(acc, s.b, Vector3<S>(-s.inv_mb * f));
    }
  }
  double potential(const double* r) const override {
    double V = 0;
    for (const auto& s : springs) {
      const double l = (at(r, s.a) - (s.b >= 0 ? at(r, s.b) : s.anchor)).norm();
      V += 0.5 * s.k * (l - s.L0) * (l - s.L0);
    }
    return V;
  }
};

/// F = −b v (Rayleigh D = ½ b |v|²).
struct LinearDragKernel final : Kernel {
  LinearDragKernel(std::vector<int> b, std::vector<double> c) : Kernel("linear_drag"), body(std::move(b)), rate(std::move(c)) {}
  std::vector<int> body;
  std::vector<double> rate;  // b/m (1/s) per entry
  template <class S>
  void add(const S*, const S* v, S* a) {
    ++evaluations;
    for (std::size_t k = 0; k < body.size(); ++k)
      lagrangian::scene::detail::particles::add(a, body[k], Vector3<S>(-rate[k] * at(v, body[k])));
  }
  bool dissipative() const override { return true; }
};

/// F = −c |v| v (D = ⅓ c |v|³).
struct QuadraticDragKernel final : Kernel {
  QuadraticDragKernel(std::vector<int> b, std::vector<double> c)
      : Kernel("quadratic_drag"), body(std::move(b)), rate(std::move(c)) {}
  std::vector<int> body;
  std::vector<double> rate;  // c/m (1/m) per entry
  template <class S>
  void add(const S*, const S* v, S* a) {
    ++evaluations;
    for (std::size_t k = 0; k < body.size(); ++k) {
      const Vector3<S> u = at(v, body[k]);
      if constexpr (!std::is_same_v<S, double>) {
        // |u| u has the derivative 0 at u = 0, where |u|'s is undefined:
        // on AD numbers a body at rest adds nothing.
        if (u.squaredNorm() == 0.0) continue;
      }
      lagrangian::scene::detail::particles::add(a, body[k], Vector3<S>(-rate[k] * u.norm() * u));
    }
  }
  bool dissipative() const override { return true; }
};

}  // namespace lagrangian::scene::detail::particles
