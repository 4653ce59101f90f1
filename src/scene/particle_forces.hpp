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

// -- the scene's parameters in a pass of its tangent flow -----------------------

/// One number a particle scene declares, named by its scene key
/// (scene_parameters(), particle_tangent.cpp): what it is, the entry it
/// belongs to (a body, a spring, a drag entry, a link, a surface, a
/// contact plane) and its component (x, y, z of a vector). A pass of the
/// tangent flow on numbers with one direction (ad::Jet<double, 1, 1>)
/// seeds it: the parameter then carries δp = 1 along that direction, so
/// the pass gives ∂a/∂p beside (∂a/∂x) δx. Kind::none seeds nothing.
struct Parameter {
  enum class Kind {
    none,
    gravity,            // gravity.g[c] (m/s²)
    newton_G,           // newtonian_gravity.G (m³ kg⁻¹ s⁻²)
    mass,               // bodies[i].mass (kg)
    radius,             // bodies[i].radius (m)
    stiffness,          // springs[i].stiffness (N/m)
    rest_length,        // springs[i].rest_length (m)
    linear_drag,        // linear_drag[i].coefficient (kg/s)
    quadratic_drag,     // quadratic_drag[i].coefficient (kg/m)
    link_length,        // links[i].length (m)
    surface_point,      // surfaces[i].point[c] (m)
    surface_radius,     // surfaces[i].radius (m)
    sphere_restitution, // contacts.spheres.restitution
    plane_restitution,  // contacts.planes[i].restitution
    plane_point,        // contacts.planes[i].point[c] (m)
    box_restitution,    // contacts.box.restitution
    box_min,            // contacts.box.min[c] (m)
    box_max,            // contacts.box.max[c] (m)
  };
  Kind kind = Kind::none;
  int index = 0;
  int component = 0;
  bool is(Kind k, int i = 0, int c = 0) const { return kind == k && index == i && component == c; }
};

/// `value` as a number of type S, carrying δ = 1 along its one direction
/// when it is the seeded parameter (`seeded`); a double stays a double.
template <class S>
S seeded(double value, bool seeded) {
  if constexpr (std::is_same_v<S, double>) {
    return value;
  } else {
    S x(value);
    if (seeded) x.g[0] = 1.0;
    return x;
  }
}

/// 1/m of body `body` (1/kg; 0 for an anchor, body −1) from its stored
/// `inverse`, carrying ∂(1/m)/∂m when its mass is seeded.
template <class S>
S inverse_mass(double inverse, int body, const Parameter& p) {
  if constexpr (!std::is_same_v<S, double>) {
    if (body >= 0 && p.is(Parameter::Kind::mass, body)) return 1.0 / seeded<S>(1.0 / inverse, true);
  }
  return S(inverse);
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
  void add(const S*, const S*, S* a, const Parameter& p = {}) {
    ++evaluations;
    const int n = static_cast<int>(mass.size());
    const S g0 = seeded<S>(g[0], p.is(Parameter::Kind::gravity, 0, 0)),
            g1 = seeded<S>(g[1], p.is(Parameter::Kind::gravity, 0, 1)),
            g2 = seeded<S>(g[2], p.is(Parameter::Kind::gravity, 0, 2));
    for (int i = 0; i < n; ++i) {
      a[3 * i] += g0;
      a[3 * i + 1] += g1;
      a[3 * i + 2] += g2;
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
  void add(const S* r, const S*, S* a, const Parameter& p = {}) {
    using std::sqrt;
    ++evaluations;
    const int n = static_cast<int>(mass.size());
    const S g = seeded<S>(G, p.is(Parameter::Kind::newton_G));
    const auto m = [&](int i) {
      return seeded<S>(mass[static_cast<std::size_t>(i)], p.is(Parameter::Kind::mass, i));
    };
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const Vector3<S> d = at(r, i) - at(r, j);
        const S d2 = d.squaredNorm();
        const Vector3<S> f = (-g / (d2 * sqrt(d2))) * d;  // per unit mass of each
        add3(a, i, Vector3<S>(m(j) * f));
        add3(a, j, Vector3<S>(-m(i) * f));
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
  void add(const S* r, const S*, S* acc, const Parameter& p = {}) {
    ++evaluations;
    for (const SpringData& s : springs) {
      const int entry = static_cast<int>(&s - springs.data());
      const Vector3<S> d = at(r, s.a) - (s.b >= 0 ? at(r, s.b) : Vector3<S>(s.anchor.cast<S>()));
      const S k = seeded<S>(s.k, p.is(Parameter::Kind::stiffness, entry));
      const bool seeded_length = !std::is_same_v<S, double> && p.is(Parameter::Kind::rest_length, entry);
      Vector3<S> f;
      if (s.L0 == 0.0 && !seeded_length) {
        f = -k * d;
      } else {
        const S l = d.norm();
        f = (-k * (l - seeded<S>(s.L0, seeded_length)) / l) * d;  // l = 0 gives NaN, caught as a non-finite state
      }
      lagrangian::scene::detail::particles::add(acc, s.a, Vector3<S>(inverse_mass<S>(s.inv_ma, s.a, p) * f));
      if (s.b >= 0)
        lagrangian::scene::detail::particles::add(acc, s.b, Vector3<S>(-inverse_mass<S>(s.inv_mb, s.b, p) * f));
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

/// The bodies a drag acts on, one entry per body and [[…_drag]] table:
/// the rate c/m and, for a pass with a seeded parameter, c and m.
struct DragEntries {
  std::vector<int> body;
  std::vector<int> table;           // the entry's [[…_drag]] table
  std::vector<double> coefficient;  // c of that table
  std::vector<double> mass;         // m of the body (kg)
  std::vector<double> rate;         // c/m
  void push(int b, int t, double c, double m) {
    body.push_back(b);
    table.push_back(t);
    coefficient.push_back(c);
    mass.push_back(m);
    rate.push_back(c * (1.0 / m));
  }
  /// c/m of entry k, with its derivative when the coefficient of the
  /// entry's table (a parameter of kind `kind`) or the body's mass is seeded.
  template <class S>
  S rate_of(std::size_t k, Parameter::Kind kind, const Parameter& p) const {
    if constexpr (!std::is_same_v<S, double>) {
      const bool c = p.is(kind, table[k]), m = p.is(Parameter::Kind::mass, body[k]);
      if (c || m) return seeded<S>(coefficient[k], c) / seeded<S>(mass[k], m);
    }
    return S(rate[k]);
  }
};

/// F = −b v (Rayleigh D = ½ b |v|²).
struct LinearDragKernel final : Kernel {
  explicit LinearDragKernel(DragEntries e) : Kernel("linear_drag"), entries(std::move(e)) {}
  DragEntries entries;
  template <class S>
  void add(const S*, const S* v, S* a, const Parameter& p = {}) {
    ++evaluations;
    for (std::size_t k = 0; k < entries.body.size(); ++k) {
      const int i = entries.body[k];
      lagrangian::scene::detail::particles::add(
          a, i, Vector3<S>(-entries.rate_of<S>(k, Parameter::Kind::linear_drag, p) * at(v, i)));
    }
  }
  bool dissipative() const override { return true; }
};

/// F = −c |v| v (D = ⅓ c |v|³).
struct QuadraticDragKernel final : Kernel {
  explicit QuadraticDragKernel(DragEntries e) : Kernel("quadratic_drag"), entries(std::move(e)) {}
  DragEntries entries;
  template <class S>
  void add(const S*, const S* v, S* a, const Parameter& p = {}) {
    ++evaluations;
    for (std::size_t k = 0; k < entries.body.size(); ++k) {
      const int i = entries.body[k];
      const Vector3<S> u = at(v, i);
      if constexpr (!std::is_same_v<S, double>) {
        // |u| u has the derivative 0 at u = 0, where |u|'s is undefined:
        // on AD numbers a body at rest adds nothing.
        if (u.squaredNorm() == 0.0) continue;
      }
      lagrangian::scene::detail::particles::add(
          a, i, Vector3<S>(-entries.rate_of<S>(k, Parameter::Kind::quadratic_drag, p) * u.norm() * u));
    }
  }
  bool dissipative() const override { return true; }
};

}  // namespace lagrangian::scene::detail::particles
