// The ODE engine of particle scenes.
//
// State x = [r; v] with r the 3N Cartesian positions (m) and v = ṙ (m/s).
// Equations of motion with Lagrange multipliers for the active constraint
// rows (links, surfaces, resting contacts), M = diag(m) ⊗ I₃:
//   M a = F(r, v, t) + Cᵀ λ,   C a = −γ − b,
// solved through the Schur complement S = C M⁻¹ Cᵀ (complete orthogonal
// decomposition, so redundant constraints are allowed). F is the sum of the
// declared force kernels only: the kernel list is built once from the scene.

#include "particle_engine.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <numeric>
#include <sstream>
#include <unordered_map>
#include <utility>

#include <Eigen/Dense>
#include <boost/numeric/odeint/stepper/bulirsch_stoer.hpp>
#include <boost/numeric/odeint/stepper/controlled_runge_kutta.hpp>
#include <boost/numeric/odeint/stepper/generation.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta4.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_cash_karp54.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_dopri5.hpp>
#include <boost/numeric/odeint/stepper/runge_kutta_fehlberg78.hpp>

#include "lagrangian/constraints.hpp"
#include "lagrangian/detail/roots.hpp"
#include "lagrangian/detail/stiff.hpp"
#include "lagrangian/errors.hpp"

namespace lagrangian::scene::detail {
namespace {

using X = std::vector<double>;
using Eigen::Vector3d;

Vector3d at(const double* p, int i) { return {p[3 * i], p[3 * i + 1], p[3 * i + 2]}; }
void add(double* p, int i, const Vector3d& f) {
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
  void add(const double*, const double*, double* a) {
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
  void add(const double* r, const double*, double* a) {
    ++evaluations;
    const int n = static_cast<int>(mass.size());
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const Vector3d d = at(r, i) - at(r, j);
        const double d2 = d.squaredNorm();
        const Vector3d f = (-G / (d2 * std::sqrt(d2))) * d;  // per unit mass of each
        add3(a, i, mass[static_cast<std::size_t>(j)] * f);
        add3(a, j, -mass[static_cast<std::size_t>(i)] * f);
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
  static void add3(double* a, int i, const Vector3d& f) { lagrangian::scene::detail::add(a, i, f); }
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
  void add(const double* r, const double*, double* acc) {
    ++evaluations;
    for (const auto& s : springs) {
      const Vector3d d = at(r, s.a) - (s.b >= 0 ? at(r, s.b) : s.anchor);
      Vector3d f;
      if (s.L0 == 0.0) {
        f = -s.k * d;
      } else {
        const double l = d.norm();
        f = (-s.k * (l - s.L0) / l) * d;  // l = 0 gives NaN, caught as a non-finite state
      }
      lagrangian::scene::detail::add(acc, s.a, s.inv_ma * f);
      if (s.b >= 0) lagrangian::scene::detail::add(acc, s.b, -s.inv_mb * f);
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
  void add(const double*, const double* v, double* a) {
    ++evaluations;
    for (std::size_t k = 0; k < body.size(); ++k) lagrangian::scene::detail::add(a, body[k], -rate[k] * at(v, body[k]));
  }
  bool dissipative() const override { return true; }
};

/// F = −c |v| v (D = ⅓ c |v|³).
struct QuadraticDragKernel final : Kernel {
  QuadraticDragKernel(std::vector<int> b, std::vector<double> c)
      : Kernel("quadratic_drag"), body(std::move(b)), rate(std::move(c)) {}
  std::vector<int> body;
  std::vector<double> rate;  // c/m (1/m) per entry
  void add(const double*, const double* v, double* a) {
    ++evaluations;
    for (std::size_t k = 0; k < body.size(); ++k) {
      const Vector3d u = at(v, body[k]);
      lagrangian::scene::detail::add(a, body[k], -rate[k] * u.norm() * u);
    }
  }
  bool dissipative() const override { return true; }
};

// -- constraint rows -----------------------------------------------------------

/// One position-level constraint row g(r) = 0 with its gradient and γ, the
/// part of g̈ that does not contain the accelerations (g̈ = ∇g·a + γ).
struct Row {
  enum class Kind { link, plane, sphere, rest_plane, rest_spheres };
  Kind kind = Kind::link;
  int a = -1, b = -1;  // bodies; b = -1 for a fixed end
  Vector3d p = Vector3d::Zero(), n = Vector3d::Zero();
  double length = 0;  // link L, sphere ρ, contact R or R_a + R_b
  std::string name;

  Vector3d d(const double* r) const { return at(r, a) - (b >= 0 ? at(r, b) : p); }
  double value(const double* r) const {
    switch (kind) {
      case Kind::link: return 0.5 * (d(r).squaredNorm() - length * length);
      case Kind::plane: return n.dot(at(r, a) - p);
      case Kind::sphere: return 0.5 * ((at(r, a) - p).squaredNorm() - length * length);
      case Kind::rest_plane: return n.dot(at(r, a) - p) - length;
      case Kind::rest_spheres: return d(r).norm() - length;
    }
    return 0;
  }
  /// Gradient with respect to body a (body b gets its negative).
  Vector3d grad(const double* r) const {
    switch (kind) {
      case Kind::link: return d(r);
      case Kind::plane:
      case Kind::rest_plane: return n;
      case Kind::sphere: return at(r, a) - p;
      case Kind::rest_spheres: return d(r).normalized();
    }
    return Vector3d::Zero();
  }
  double gamma(const double* r, const double* v) const {
    const Vector3d dv = at(v, a) - (b >= 0 ? at(v, b) : Vector3d::Zero());
    switch (kind) {
      case Kind::link:
      case Kind::sphere: return dv.squaredNorm();
      case Kind::plane:
      case Kind::rest_plane: return 0.0;
      case Kind::rest_spheres: {
        const Vector3d dd = d(r);
        const double l = dd.norm();
        const double radial = dd.dot(dv) / l;
        return (dv.squaredNorm() - radial * radial) / l;
      }
    }
    return 0;
  }
};

/// C = ∂g/∂r of the rows (rows × dim): each row's gradient on body a and its
/// negative on body b.
void jacobian(const std::vector<Row>& rows, const double* r, int dim, Eigen::MatrixXd& C) {
  C.setZero(static_cast<Eigen::Index>(rows.size()), dim);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto row = static_cast<Eigen::Index>(k);
    const Vector3d g = rows[k].grad(r);
    C.block<1, 3>(row, 3 * rows[k].a) += g.transpose();
    if (rows[k].b >= 0) C.block<1, 3>(row, 3 * rows[k].b) -= g.transpose();
  }
}

// -- contacts ------------------------------------------------------------------

struct Contact {
  bool pair = false;  // sphere–sphere; else sphere–plane
  int a = -1, b = -1;
  Vector3d p = Vector3d::Zero(), n = Vector3d::Zero();
  double R = 0;  // R_a (+ R_b)
  double e = 1;
  std::string name;
  double max_approach = 0;
  double last_impact = -std::numeric_limits<double>::infinity();
  bool resting = false;

  double gap(const double* r) const {
    return pair ? (at(r, a) - at(r, b)).norm() - R : n.dot(at(r, a) - p) - R;
  }
  Vector3d normal(const double* r) const { return pair ? (at(r, a) - at(r, b)).normalized() : n; }
  double rate(const double* r, const double* v) const {
    const Vector3d dv = at(v, a) - (pair ? at(v, b) : Vector3d::Zero());
    return normal(r).dot(dv);
  }
};

// -- quintic Hermite interpolation of positions within a step ------------------

struct StepPath {
  double t0 = 0, h = 0;
  const double *r0 = nullptr, *v0 = nullptr, *a0 = nullptr, *r1 = nullptr, *v1 = nullptr, *a1 = nullptr;
  /// Position of coordinate c at time t and its rate.
  void eval(int c, double t, double& pos, double& vel) const {
    const double s = (t - t0) / h, s2 = s * s, s3 = s2 * s, s4 = s3 * s, s5 = s4 * s;
    const double H0 = 1 - 10 * s3 + 15 * s4 - 6 * s5, H1 = s - 6 * s3 + 8 * s4 - 3 * s5,
                 H2 = 0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5, H3 = 10 * s3 - 15 * s4 + 6 * s5,
                 H4 = -4 * s3 + 7 * s4 - 3 * s5, H5 = 0.5 * s3 - s4 + 0.5 * s5;
    const double D0 = -30 * s2 + 60 * s3 - 30 * s4, D1 = 1 - 18 * s2 + 32 * s3 - 15 * s4,
                 D2 = s - 4.5 * s2 + 6 * s3 - 2.5 * s4, D3 = -D0, D4 = -12 * s2 + 28 * s3 - 15 * s4,
                 D5 = 1.5 * s2 - 4 * s3 + 2.5 * s4;
    pos = H0 * r0[c] + H1 * h * v0[c] + H2 * h * h * a0[c] + H3 * r1[c] + H4 * h * v1[c] + H5 * h * h * a1[c];
    vel = (D0 * r0[c] + D1 * h * v0[c] + D2 * h * h * a0[c] + D3 * r1[c] + D4 * h * v1[c] + D5 * h * h * a1[c]) / h;
  }
  void body(int i, double t, Vector3d& r, Vector3d& v) const {
    for (int k = 0; k < 3; ++k) eval(3 * i + k, t, r[k], v[k]);
  }
};

double gap_on_path(const Contact& c, const StepPath& path, double t, double* rate = nullptr) {
  Vector3d ra, va, rb, vb;
  path.body(c.a, t, ra, va);
  if (c.pair) {
    path.body(c.b, t, rb, vb);
    const Vector3d d = ra - rb;
    const double l = d.norm();
    if (rate) *rate = d.dot(va - vb) / l;
    return l - c.R;
  }
  if (rate) *rate = c.n.dot(va);
  return c.n.dot(ra - c.p) - c.R;
}

// -- the system ----------------------------------------------------------------

class System {
 public:
  explicit System(const Scene& scene) {
    n_ = static_cast<int>(scene.bodies.size());
    dim_ = 3 * n_;
    std::unordered_map<std::string, int> index;
    for (int i = 0; i < n_; ++i) {
      const Body& b = scene.bodies[static_cast<std::size_t>(i)];
      index[b.name] = i;
      names_.push_back(b.name);
      mass_.push_back(b.mass);
      radius_.push_back(b.radius);
    }
    inv_mass3_.resize(dim_);
    for (int i = 0; i < n_; ++i) inv_mass3_.segment<3>(3 * i).setConstant(1.0 / mass_[static_cast<std::size_t>(i)]);
    auto body = [&](const std::string& name) { return name.empty() ? -1 : index.at(name); };
    auto members = [&](const std::vector<std::string>& list) {
      std::vector<int> out;
      if (list.empty()) {
        out.resize(static_cast<std::size_t>(n_));
        std::iota(out.begin(), out.end(), 0);
      } else {
        for (const auto& s : list) out.push_back(index.at(s));
      }
      return out;
    };

    // Only the declared effects become kernels.
    auto inv = [&](int i) { return i < 0 ? 0.0 : 1.0 / mass_[static_cast<std::size_t>(i)]; };
    if (scene.gravity) {
      kernels_.push_back(std::make_unique<GravityKernel>(mass_, scene.gravity->g));
      gravity_ = static_cast<GravityKernel*>(kernels_.back().get());
    }
    if (scene.newtonian_gravity) {
      kernels_.push_back(std::make_unique<NewtonKernel>(mass_, scene.newtonian_gravity->G));
      newton_ = static_cast<NewtonKernel*>(kernels_.back().get());
    }
    if (!scene.springs.empty()) {
      std::vector<SpringData> s;
      for (const auto& sp : scene.springs) {
        const int a = body(sp.a), b = body(sp.b);
        s.push_back({a, b, sp.anchor, sp.stiffness, sp.rest_length, inv(a), inv(b)});
      }
      kernels_.push_back(std::make_unique<SpringKernel>(std::move(s)));
      springs_ = static_cast<SpringKernel*>(kernels_.back().get());
    }
    if (!scene.linear_drag.empty()) {
      std::vector<int> b;
      std::vector<double> c;
      for (const auto& d : scene.linear_drag)
        for (int i : members(d.bodies)) b.push_back(i), c.push_back(d.coefficient * inv(i));
      kernels_.push_back(std::make_unique<LinearDragKernel>(std::move(b), std::move(c)));
      linear_drag_ = static_cast<LinearDragKernel*>(kernels_.back().get());
    }
    if (!scene.quadratic_drag.empty()) {
      std::vector<int> b;
      std::vector<double> c;
      for (const auto& d : scene.quadratic_drag)
        for (int i : members(d.bodies)) b.push_back(i), c.push_back(d.coefficient * inv(i));
      kernels_.push_back(std::make_unique<QuadraticDragKernel>(std::move(b), std::move(c)));
      quadratic_drag_ = static_cast<QuadraticDragKernel*>(kernels_.back().get());
    }

    for (std::size_t k = 0; k < scene.links.size(); ++k) {
      const Link& l = scene.links[k];
      Row row;
    row.kind = Row::Kind::link;
      row.a = body(l.a);
      row.b = body(l.b);
      row.p = l.anchor;
      const Vector3d d0 = scene.bodies[static_cast<std::size_t>(row.a)].position -
                          (row.b >= 0 ? scene.bodies[static_cast<std::size_t>(row.b)].position : l.anchor);
      row.length = std::isnan(l.length) ? d0.norm() : l.length;
      row.name = l.name.empty() ? "link" + std::to_string(k) : l.name;
      rows_.push_back(row);
      has_links_ = true;
    }
    for (std::size_t k = 0; k < scene.surfaces.size(); ++k) {
      const Surface& s = scene.surfaces[k];
      Row row;
    row.kind = s.kind == Surface::Kind::plane ? Row::Kind::plane : Row::Kind::sphere;
      row.a = body(s.body);
      row.p = s.point;
      row.n = s.normal.normalized();
      row.length = s.radius;
      row.name = s.name.empty() ? "surface" + std::to_string(k) : s.name;
      rows_.push_back(row);
      has_surfaces_ = true;
    }
    fixed_rows_ = static_cast<int>(rows_.size());

    if (scene.sphere_contacts) {
      pair_members_ = members(scene.sphere_contacts->bodies);
      pair_e_ = scene.sphere_contacts->restitution;
      has_pairs_ = true;
    }
    for (std::size_t k = 0; k < scene.planes.size(); ++k) {
      const PlaneContact& pc = scene.planes[k];
      const std::string pname = pc.name.empty() ? "plane" + std::to_string(k) : pc.name;
      for (int i : members(pc.bodies)) {
        Contact c;
        c.a = i;
        c.p = pc.point;
        c.n = pc.normal.normalized();
        c.R = radius_[static_cast<std::size_t>(i)];
        c.e = pc.restitution;
        c.name = names_[static_cast<std::size_t>(i)] + "-" + pname;
        wall_contacts_.push_back(c);
      }
      has_planes_ = true;
    }
    if (scene.box) {
      const char* axis[3] = {"x", "y", "z"};
      for (int i = 0; i < n_; ++i)
        for (int k = 0; k < 3; ++k)
          for (int side = 0; side < 2; ++side) {
            Contact c;
            c.a = i;
            c.n = Vector3d::Zero();
            c.n[k] = side == 0 ? 1.0 : -1.0;
            c.p = side == 0 ? scene.box->min : scene.box->max;
            c.R = radius_[static_cast<std::size_t>(i)];
            c.e = scene.box->restitution;
            c.name = names_[static_cast<std::size_t>(i)] + "-wall:" + axis[k] + (side == 0 ? "_min" : "_max");
            wall_contacts_.push_back(c);
          }
      has_box_ = true;
    }
    has_contacts_ = has_pairs_ || !wall_contacts_.empty();
    constrained_ = fixed_rows_ > 0 || has_contacts_;  // contacts may come to rest
    resize_rows();
    select_rhs();
  }

  int bodies() const { return n_; }
  int dim() const { return dim_; }
  const std::vector<std::string>& names() const { return names_; }
  const std::vector<double>& mass() const { return mass_; }
  bool has_contacts() const { return has_contacts_; }
  bool dissipative() const {
    return std::any_of(kernels_.begin(), kernels_.end(), [](const auto& k) { return k->dissipative(); });
  }
  const std::vector<Row>& rows() const { return rows_; }
  int fixed_rows() const { return fixed_rows_; }
  std::uint64_t rhs_evaluations = 0;
  double omega = 0;  // Baumgarte rate (1/s); 0: none
  std::uint64_t constraint_solves = 0, contact_sweeps = 0;

  /// ẋ = [v; a], through the right-hand side composed for this scene.
  void rhs(const double* x, double* dx, double t) { rhs_fn_(*this, x, dx, t); }

  /// The right-hand side for one set of declared kinds (bits: uniform
  /// gravity, Newtonian gravity, springs, linear drag, quadratic drag) and
  /// with or without constraint rows. Undeclared kinds are not in the code.
  template <unsigned Kinds, bool Constrained>
  static void rhs_for(System& s, const double* x, double* dx, double) {
    ++s.rhs_evaluations;
    const int dim = s.dim_;
    const double* r = x;
    const double* v = x + dim;
    double* a = dx + dim;
    if constexpr ((Kinds & 1u) != 0) {
      s.gravity_->start(v, dx, a, dim);  // ṙ = v and a = g in one pass
    } else {
      for (int i = 0; i < dim; ++i) {
        dx[i] = v[i];
        a[i] = 0.0;
      }
    }
    if constexpr ((Kinds & 2u) != 0) s.newton_->add(r, v, a);
    if constexpr ((Kinds & 4u) != 0) s.springs_->add(r, v, a);
    if constexpr ((Kinds & 8u) != 0) s.linear_drag_->add(r, v, a);
    if constexpr ((Kinds & 16u) != 0) s.quadratic_drag_->add(r, v, a);
    if constexpr (Constrained) s.constrain(r, v, a);
  }

  using RhsFn = void (*)(System&, const double*, double*, double);
  template <unsigned... K>
  static constexpr std::array<RhsFn, 64> rhs_table(std::integer_sequence<unsigned, K...>) {
    return {rhs_for<(K >> 1), (K & 1u) != 0>...};
  }
  /// Chooses the right-hand side once, from what the scene declares.
  void select_rhs() {
    unsigned kinds = 0;
    if (gravity_) kinds |= 1u;
    if (newton_) kinds |= 2u;
    if (springs_) kinds |= 4u;
    if (linear_drag_) kinds |= 8u;
    if (quadratic_drag_) kinds |= 16u;
    static constexpr auto table = rhs_table(std::make_integer_sequence<unsigned, 64>{});
    rhs_fn_ = table[(kinds << 1) | (constrained_ ? 1u : 0u)];
  }


  double kinetic(const double* x) const {
    double T = 0;
    for (int i = 0; i < n_; ++i) T += 0.5 * mass_[static_cast<std::size_t>(i)] * at(x + dim_, i).squaredNorm();
    return T;
  }
  double potential(const double* x) const {
    double V = 0;
    for (const auto& k : kernels_) V += k->potential(x);
    return V;
  }

  std::map<std::string, std::uint64_t> counts() const {
    std::map<std::string, std::uint64_t> out;
    for (const auto& k : kernels_) out[k->kind] = k->evaluations;
    if (has_links_) out["links"] = constraint_solves;
    if (has_surfaces_) out["surfaces"] = constraint_solves;
    if (has_pairs_) out["sphere_contacts"] = contact_sweeps;
    if (has_planes_) out["plane_contacts"] = contact_sweeps;
    if (has_box_) out["box_contacts"] = contact_sweeps;
    return out;
  }

  // -- constraints ----------------------------------------------------------

  void resize_rows() {
    const int m = static_cast<int>(rows_.size());
    C_.setZero(m, dim_);
    MinvCt_.setZero(dim_, m);
    S_.setZero(m, m);
    rhs_m_.setZero(m);
    lambda_.setZero(m);
  }

  void assemble(const double* r) {
    jacobian(rows_, r, dim_, C_);
    MinvCt_ = inv_mass3_.asDiagonal() * C_.transpose();
    S_.noalias() = C_ * MinvCt_;
    cod_.compute(S_);
  }

  /// a ← a + M⁻¹Cᵀλ with S λ = −(C a + γ + b), a the unconstrained accelerations.
  void constrain(const double* r, const double* v, double* a) {
    if (rows_.empty()) return;  // contacts only, none resting now
    ++constraint_solves;
    assemble(r);
    Eigen::Map<const Eigen::VectorXd> vv(v, dim_);
    for (int k = 0; k < static_cast<int>(rows_.size()); ++k) {
      const Row& row = rows_[static_cast<std::size_t>(k)];
      double b = row.gamma(r, v);
      if (omega > 0) b += 2 * omega * C_.row(k).dot(vv) + omega * omega * row.value(r);
      rhs_m_[k] = -b;
    }
    Eigen::Map<Eigen::VectorXd> acc(a, dim_);
    rhs_m_.noalias() -= C_ * acc;
    lambda_ = cod_.solve(rhs_m_);
    acc.noalias() += MinvCt_ * lambda_;
  }

  double position_residual(const double* r) const {
    double g = 0;
    for (const Row& row : rows_) g = std::max(g, std::abs(row.value(r)));
    return g;
  }
  double velocity_residual(const double* x) {
    if (rows_.empty()) return 0;
    jacobian(rows_, x, dim_, C_);  // C only: no factorisation for a residual
    Eigen::Map<const Eigen::VectorXd> vv(x + dim_, dim_);
    return (C_ * vv).lpNorm<Eigen::Infinity>();
  }

  /// Projects r onto g = 0 (M-weighted Gauss–Newton) and v onto C v = 0.
  /// Returns the iterations, or −1 when nothing needed doing.
  int project(double* x, double tolerance) {
    if (rows_.empty()) return -1;
    Eigen::Map<Eigen::VectorXd> r(x, dim_), v(x + dim_, dim_);
    const double scale = 1.0 + r.lpNorm<Eigen::Infinity>();
    int it = 0;
    bool moved = false;
    for (; it < 20; ++it) {
      for (int k = 0; k < static_cast<int>(rows_.size()); ++k) rhs_m_[k] = rows_[static_cast<std::size_t>(k)].value(x);
      if (rhs_m_.lpNorm<Eigen::Infinity>() <= tolerance * scale) break;
      assemble(x);
      r -= MinvCt_ * cod_.solve(rhs_m_);
      moved = true;
    }
    assemble(x);
    rhs_m_.noalias() = C_ * v;
    if (rhs_m_.lpNorm<Eigen::Infinity>() > tolerance * (1.0 + v.lpNorm<Eigen::Infinity>())) {
      v -= MinvCt_ * cod_.solve(rhs_m_);
      moved = true;
    }
    return moved ? it : -1;
  }

  // -- contacts -------------------------------------------------------------

  /// Contacts that may close in a step: every wall contact, and sphere pairs
  /// whose x-extents over the step overlap (sweep and prune on x).
  void candidates(const StepPath& path, std::vector<Contact*>& out) {
    ++contact_sweeps;
    out.clear();
    for (auto& c : wall_contacts_)
      if (!c.resting) out.push_back(&c);
    if (!has_pairs_) return;
    const double h = path.h;
    spans_.clear();
    for (int i : pair_members_) {
      const int c = 3 * i;
      const double bulge = 0.125 * h * h * std::max(std::abs(path.a0[c]), std::abs(path.a1[c])) + 1e-12;
      const double R = radius_[static_cast<std::size_t>(i)];
      spans_.push_back({std::min(path.r0[c], path.r1[c]) - R - bulge, std::max(path.r0[c], path.r1[c]) + R + bulge, i});
    }
    std::sort(spans_.begin(), spans_.end(), [](const Span& a, const Span& b) { return a.lo < b.lo; });
    for (std::size_t p = 0; p < spans_.size(); ++p)
      for (std::size_t q = p + 1; q < spans_.size() && spans_[q].lo <= spans_[p].hi; ++q) {
        Contact& c = pair_contact(spans_[p].body, spans_[q].body);
        if (!c.resting) out.push_back(&c);
      }
  }

  Contact& pair_contact(int i, int j) {
    if (i > j) std::swap(i, j);
    const std::uint64_t key = static_cast<std::uint64_t>(i) * static_cast<std::uint64_t>(n_) + static_cast<std::uint64_t>(j);
    auto it = pairs_.find(key);
    if (it != pairs_.end()) return it->second;
    Contact c;
    c.pair = true;
    c.a = i;
    c.b = j;
    c.R = radius_[static_cast<std::size_t>(i)] + radius_[static_cast<std::size_t>(j)];
    c.e = pair_e_;
    c.name = names_[static_cast<std::size_t>(i)] + "-" + names_[static_cast<std::size_t>(j)];
    return pairs_.emplace(key, c).first->second;
  }

  /// All contacts within `tol` of closing at state x (for simultaneous impacts).
  void near_contacts(const double* x, double tol, std::vector<Contact*>& out) {
    out.clear();
    for (auto& c : wall_contacts_)
      if (!c.resting && c.gap(x) <= tol) out.push_back(&c);
    if (!has_pairs_) return;
    for (std::size_t p = 0; p < pair_members_.size(); ++p)
      for (std::size_t q = p + 1; q < pair_members_.size(); ++q) {
        const int i = pair_members_[p], j = pair_members_[q];
        const double dist = (at(x, i) - at(x, j)).norm();
        if (dist - radius_[static_cast<std::size_t>(i)] - radius_[static_cast<std::size_t>(j)] <= tol) {
          Contact& c = pair_contact(i, j);
          if (!c.resting) out.push_back(&c);
        }
      }
  }

  /// Newton's law of restitution for one contact, with the active constraint
  /// rows kept at C Δv = −C v:  M Δv = Jᵀ μ,  J = [C; ∇φ],
  /// J Δv = [−C v; −(1 + e) φ̇]. Returns the impulse along ∇φ (N·s).
  /// Resting contacts are not rows here: they take part as contacts of their
  /// own (released when the impulse makes them approach, see resolve_at).
  double impulse(double* x, const Contact& c, double e) {
    const int m = fixed_rows_;
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(m + 1, dim_);
    if (m > 0) {
      assemble(x);
      J.topRows(m) = C_.topRows(m);
    }
    const Vector3d nrm = c.normal(x);
    J.block<1, 3>(m, 3 * c.a) = nrm.transpose();
    if (c.pair) J.block<1, 3>(m, 3 * c.b) = -nrm.transpose();
    Eigen::Map<Eigen::VectorXd> v(x + dim_, dim_);
    Eigen::VectorXd b(m + 1);
    if (m > 0) b.head(m) = -(C_.topRows(m) * v);
    b[m] = -(1.0 + e) * c.rate(x, x + dim_);
    const Eigen::MatrixXd MinvJt = inv_mass3_.asDiagonal() * J.transpose();
    const Eigen::MatrixXd S = J * MinvJt;
    const Eigen::VectorXd mu = S.completeOrthogonalDecomposition().solve(b);
    v += MinvJt * mu;
    return mu[m];
  }

  /// d²φ/dt² of a contact at x under the current forces and constraints.
  /// True when the forces press the contact shut: d²φ/dt² < 0 beyond
  /// round-off (1e-9 of the largest acceleration, at least 1e-12 m/s²).
  bool pressed(const double* x, const Contact& c) {
    std::vector<double> dx(static_cast<std::size_t>(2 * dim_));
    rhs(x, dx.data(), 0.0);
    const double* v = x + dim_;
    const double* a = dx.data() + dim_;
    double scale = 0;
    for (int k = 0; k < dim_; ++k) scale = std::max(scale, std::abs(a[k]));
    const double tol = 1e-9 * scale + 1e-12;
    if (!c.pair) return c.n.dot(at(a, c.a)) < -tol;
    const Vector3d d = at(x, c.a) - at(x, c.b);
    const Vector3d dv = at(v, c.a) - at(v, c.b);
    const Vector3d da = at(a, c.a) - at(a, c.b);
    const double l = d.norm();
    const double radial = d.dot(dv) / l;
    return d.dot(da) / l + (dv.squaredNorm() - radial * radial) / l < -tol;
  }

  /// Resting contacts that an impulse has set approaching: they leave the
  /// constraint rows and become contacts to resolve.
  void wake_approaching(const double* x, double touch, std::vector<Contact*>& near) {
    bool changed = false;
    for (int k = static_cast<int>(rows_.size()) - 1; k >= fixed_rows_; --k) {
      const std::size_t idx = static_cast<std::size_t>(k - fixed_rows_);
      Contact* c = rest_contacts_[idx];
      if (c->rate(x, x + dim_) < -touch) {
        c->resting = false;
        rest_contacts_.erase(rest_contacts_.begin() + static_cast<std::ptrdiff_t>(idx));
        rows_.erase(rows_.begin() + k);
        if (std::find(near.begin(), near.end(), c) == near.end()) near.push_back(c);
        changed = true;
      }
    }
    if (changed) resize_rows();
  }

  void make_resting(Contact& c) {
    c.resting = true;
    Row row;
    row.kind = c.pair ? Row::Kind::rest_spheres : Row::Kind::rest_plane;
    row.a = c.a;
    row.b = c.pair ? c.b : -1;
    row.p = c.p;
    row.n = c.n;
    row.length = c.R;
    row.name = c.name;
    rest_contacts_.push_back(&c);
    rows_.push_back(row);
    resize_rows();
  }

  /// Releases resting contacts whose multiplier pulls; returns their names.
  std::vector<std::string> release_pulling(const double* x) {
    std::vector<std::string> out;
    if (rest_contacts_.empty()) return out;
    std::vector<double> dx(static_cast<std::size_t>(2 * dim_));
    rhs(x, dx.data(), 0.0);
    for (int k = static_cast<int>(rows_.size()) - 1; k >= fixed_rows_; --k) {
      if (lambda_[k] < 0) {
        const std::size_t idx = static_cast<std::size_t>(k - fixed_rows_);
        rest_contacts_[idx]->resting = false;
        out.push_back(rows_[static_cast<std::size_t>(k)].name);
        rest_contacts_.erase(rest_contacts_.begin() + static_cast<std::ptrdiff_t>(idx));
        rows_.erase(rows_.begin() + k);
      }
    }
    if (!out.empty()) resize_rows();
    return out;
  }

 private:
  struct Span {
    double lo, hi;
    int body;
  };
  int n_ = 0, dim_ = 0;
  std::vector<std::string> names_;
  std::vector<double> mass_, radius_;
  Eigen::VectorXd inv_mass3_;
  std::vector<std::unique_ptr<Kernel>> kernels_;
  std::vector<Row> rows_;
  int fixed_rows_ = 0;
  bool constrained_ = false, has_links_ = false, has_surfaces_ = false;
  bool has_pairs_ = false, has_planes_ = false, has_box_ = false, has_contacts_ = false;
  std::vector<int> pair_members_;
  double pair_e_ = 1;
  std::vector<Contact> wall_contacts_;
  std::unordered_map<std::uint64_t, Contact> pairs_;
  std::vector<Contact*> rest_contacts_;
  std::vector<Span> spans_;
  Eigen::VectorXd rhs_m_, lambda_;
  GravityKernel* gravity_ = nullptr;
  NewtonKernel* newton_ = nullptr;
  SpringKernel* springs_ = nullptr;
  LinearDragKernel* linear_drag_ = nullptr;
  QuadraticDragKernel* quadratic_drag_ = nullptr;
  RhsFn rhs_fn_ = nullptr;
  Eigen::MatrixXd C_, MinvCt_, S_;
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod_;
};

// -- steppers ------------------------------------------------------------------

struct Rhs {
  System* sys;
  void operator()(const X& x, X& dx, double t) const { sys->rhs(x.data(), dx.data(), t); }
};

struct Stepper {
  virtual ~Stepper() = default;
  /// One attempt from (x, t) with step dt; on success x, t advance and dt is
  /// the next suggested step.
  virtual bool try_step(X& x, double& t, double& dt) = 0;
  virtual void reset() {}
};

template <class Controlled>
struct OdeintStepper final : Stepper {
  OdeintStepper(Rhs r, Controlled c) : rhs(r), stepper(std::move(c)) {}
  Rhs rhs;
  Controlled stepper;
  bool try_step(X& x, double& t, double& dt) override {
    return stepper.try_step(rhs, x, t, dt) == boost::numeric::odeint::success;
  }
  void reset() override {
    if constexpr (requires { stepper.reset(); }) stepper.reset();
  }
};

struct Rk4Stepper final : Stepper {
  explicit Rk4Stepper(Rhs r) : rhs(r) {}
  Rhs rhs;
  boost::numeric::odeint::runge_kutta4<X> stepper;
  bool try_step(X& x, double& t, double& dt) override {
    stepper.do_step(rhs, x, t, dt);
    t += dt;
    return true;
  }
};

struct StiffStepper final : Stepper {
  StiffStepper(System* s, int m, double atol, double rtol) : sys(s), xa(static_cast<std::size_t>(m)),
        fa(static_cast<std::size_t>(m)), fb(static_cast<std::size_t>(m)), impl(m, atol, rtol) {}
  System* sys;
  X xa, fa, fb;
  lagrangian::detail::Rosenbrock4Stepper impl;
  bool try_step(X& x, double& t, double& dt) override {
    lagrangian::detail::StiffSystem stiff{
        this,
        [](void* c, const double* xin, double* dxdt, double tt) { static_cast<StiffStepper*>(c)->sys->rhs(xin, dxdt, tt); },
        [](void* c, const double* xin, double* J, double* dfdt, double tt) {
          auto& k = *static_cast<StiffStepper*>(c);
          const int m = static_cast<int>(k.xa.size());
          const double cbrt_eps = std::cbrt(std::numeric_limits<double>::epsilon());
          std::copy(xin, xin + m, k.xa.begin());
          for (int j = 0; j < m; ++j) {
            const double h = cbrt_eps * std::max(std::abs(k.xa[static_cast<std::size_t>(j)]), 1.0);
            const double xj = k.xa[static_cast<std::size_t>(j)];
            k.xa[static_cast<std::size_t>(j)] = xj + h;
            k.sys->rhs(k.xa.data(), k.fa.data(), tt);
            k.xa[static_cast<std::size_t>(j)] = xj - h;
            k.sys->rhs(k.xa.data(), k.fb.data(), tt);
            k.xa[static_cast<std::size_t>(j)] = xj;
            for (int i = 0; i < m; ++i)
              J[i * m + j] = (k.fa[static_cast<std::size_t>(i)] - k.fb[static_cast<std::size_t>(i)]) / (2 * h);
          }
          for (int i = 0; i < m; ++i) dfdt[i] = 0.0;  // particle scenes are autonomous
        }};
    return impl.try_step(stiff, x.data(), t, dt);
  }
};

std::unique_ptr<Stepper> make_stepper(const std::string& method, System& sys, const RunSpec& run) {
  namespace odeint = boost::numeric::odeint;
  const Rhs rhs{&sys};
  if (method == "rk4") return std::make_unique<Rk4Stepper>(rhs);
  if (method == "dopri5") {
    using C = odeint::controlled_runge_kutta<odeint::runge_kutta_dopri5<X>>;
    return std::make_unique<OdeintStepper<C>>(rhs, C{typename C::error_checker_type(run.atol, run.rtol)});
  }
  if (method == "cash_karp54") {
    using C = odeint::controlled_runge_kutta<odeint::runge_kutta_cash_karp54<X>>;
    return std::make_unique<OdeintStepper<C>>(rhs, C{typename C::error_checker_type(run.atol, run.rtol)});
  }
  if (method == "fehlberg78") {
    using C = odeint::controlled_runge_kutta<odeint::runge_kutta_fehlberg78<X>>;
    return std::make_unique<OdeintStepper<C>>(rhs, C{typename C::error_checker_type(run.atol, run.rtol)});
  }
  if (method == "bulirsch_stoer") {
    using C = odeint::bulirsch_stoer<X>;
    return std::make_unique<OdeintStepper<C>>(rhs, C(run.atol, run.rtol));
  }
  if (method == "rosenbrock4") return std::make_unique<StiffStepper>(&sys, 2 * sys.dim(), run.atol, run.rtol);
  if (method == "variational" || method == "symplectic_rkn_sb3a_mclachlan" || method == "velocity_verlet")
    throw OptionError("run.method: '" + method +
                      "' runs built-in models (model = ...) only; a scene of bodies runs with rk4, dopri5, "
                      "cash_karp54, fehlberg78, bulirsch_stoer or rosenbrock4");
  throw OptionError("run.method: unknown stepper '" + method + "' for a particle scene");
}

bool reached(double t, double t_end) {
  return t_end - t <= 4.0 * std::numeric_limits<double>::epsilon() * std::max(std::abs(t), std::abs(t_end));
}

std::string describe(const System& sys, const X& x, double t) {
  std::ostringstream os;
  os.precision(17);
  os << "t = " << t << " s;";
  for (int i = 0; i < sys.bodies(); ++i) {
    os << " " << sys.names()[static_cast<std::size_t>(i)] << ": r = (" << x[3 * i] << ", " << x[3 * i + 1] << ", "
       << x[3 * i + 2] << ") v = (" << x[sys.dim() + 3 * i] << ", " << x[sys.dim() + 3 * i + 1] << ", "
       << x[sys.dim() + 3 * i + 2] << ")";
    if (i >= 3 && sys.bodies() > 5) {
      os << " …";
      break;
    }
  }
  return os.str();
}

// -- the run ------------------------------------------------------------------

class Runner {
 public:
  Runner(const Scene& scene, const ParticleSample& sample, const SampleTick& tick)
      : scene_(scene), run_(scene.run), sys_(scene), sample_(sample), tick_(tick) {}

  ParticleRun go() {
    const auto wall_start = std::chrono::steady_clock::now();
    const int dim = sys_.dim();
    fixed_step_ = run_.method == "rk4";
    RunReport& rep = out_.report;
    rep.model = scene_.name;
    for (const auto& nm : sys_.names())
      for (const char* ax : {".x", ".y", ".z"}) rep.coordinates.push_back(nm + ax);
    rep.method = run_.method;
    rep.adaptive = !fixed_step_;
    rep.rtol = run_.rtol;
    rep.atol = run_.atol;
    rep.dt = run_.dt;
    rep.t0 = run_.t0;
    rep.t_end = run_.t_end;
    if (run_.stabilization == Stabilization::baumgarte) sys_.omega = run_.baumgarte_omega;

    x_.assign(static_cast<std::size_t>(2 * dim), 0.0);
    for (int i = 0; i < sys_.bodies(); ++i)
      for (int k = 0; k < 3; ++k) {
        x_[static_cast<std::size_t>(3 * i + k)] = scene_.bodies[static_cast<std::size_t>(i)].position[k];
        x_[static_cast<std::size_t>(dim + 3 * i + k)] = scene_.bodies[static_cast<std::size_t>(i)].velocity[k];
      }
    f0_.assign(x_.size(), 0.0);
    f1_.assign(x_.size(), 0.0);
    xprev_ = x_;

    rep.conservative = !sys_.dissipative();
    rep.has_total_energy = true;
    const double T0 = sys_.kinetic(x_.data()), V0 = sys_.potential(x_.data());
    E0_ = T0 + V0;
    rep.energy_scale = std::max(std::abs(E0_), std::abs(T0) + std::abs(V0));
    if (rep.energy_scale == 0) rep.energy_scale = 1;
    rep.energy_initial = rep.total_energy_initial = E0_;
    rep.has_particles = true;
    momentum(x_.data(), P0_, L0_);
    for (int k = 0; k < 3; ++k) {
      rep.linear_momentum_initial[static_cast<std::size_t>(k)] = P0_[k];
      rep.angular_momentum_initial[static_cast<std::size_t>(k)] = L0_[k];
    }
    rep.constrained = sys_.fixed_rows() > 0;
    if (rep.constrained) {
      for (const Row& r : sys_.rows()) rep.constraints.names.push_back(r.name);
      rep.constraints.stabilization = to_string(run_.stabilization);
      rep.constraints.baumgarte_omega = sys_.omega;
      rep.constraints.initial_rank = rep.constraints.min_rank = rank(x_.data());
    }

    stepper_ = make_stepper(run_.method, sys_, run_);
    double t = run_.t0;
    if (sys_.has_contacts()) resolve_at(t, nullptr);  // contacts already closing at t0
    observe(t);
    next_output_ = run_.output_interval > 0 ? run_.t0 + run_.output_interval : std::numeric_limits<double>::infinity();
    std::uint64_t k_grid = 0;
    double dt = run_.dt;
    while (!reached(t, run_.t_end)) {
      if (rep.steps >= run_.max_steps)
        throw SimulationError("run stopped: max_steps (" + std::to_string(run_.max_steps) + ") reached at t = " +
                                  std::to_string(t) + " s",
                              t);
      const double limit = std::min(run_.t_end, next_output_);
      double dt_try;
      bool clamped;
      const double grid = run_.t0 + static_cast<double>(k_grid + 1) * run_.dt;
      if (fixed_step_) {
        dt_try = std::min(grid, limit) - t;
        clamped = true;
      } else {
        clamped = t + dt > limit;
        dt_try = clamped ? limit - t : dt;
      }
      const double t_old = t;
      if (sys_.has_contacts()) {
        xprev_ = x_;
        if (f_cached_) {
          std::swap(f0_, f1_);  // the previous step's end, unchanged since
        } else {
          sys_.rhs(xprev_.data(), f0_.data(), t_old);
        }
        f_cached_ = false;
      }
      if (!stepper_->try_step(x_, t, dt_try)) {
        ++rep.rejected_steps;
        if (!(dt_try > 1e-14 * std::max(1.0, std::abs(t))))
          throw SimulationError("run stopped: step size underflow at " + describe(sys_, x_, t), t);
        dt = dt_try;
        continue;
      }
      if (clamped) t = fixed_step_ ? t_old + dt_try : limit;
      ++rep.steps;
      check_finite(t);
      bool moved = false;
      if (sys_.has_contacts()) {
        moved = handle_contacts(t_old, t);
        if (moved) stepper_->reset();
      }
      if (fixed_step_ && t >= grid - 1e-15 * std::max(1.0, std::abs(grid))) ++k_grid;
      if (!sys_.rows().empty() && run_.stabilization == Stabilization::projection) {
        const auto ps = std::chrono::steady_clock::now();
        const int it = sys_.project(x_.data(), 1e-12);
        if (it >= 0) {
          moved = true;
          ++rep.constraints.projections;
          rep.constraints.projection_iterations += static_cast<std::uint64_t>(it);
          stepper_->reset();
        }
        rep.constraints.stabilization_time_s +=
            std::chrono::duration<double>(std::chrono::steady_clock::now() - ps).count();
      }
      if (sys_.has_contacts()) {
        const auto released = sys_.release_pulling(x_.data());
        for (const auto& name : released) log_event(t, EventKind::release, name, 0, 0, 0);
        f_cached_ = !moved && released.empty();
      }
      if (rep.constrained) track_constraints(t);
      if (reached(t, next_output_) || run_.output_interval == 0 || reached(t, run_.t_end)) {
        observe(t);
        while (next_output_ <= t + 1e-12 * std::max(1.0, std::abs(t))) next_output_ += run_.output_interval;
      }
      if (tick_) tick_(t);
      if (!fixed_step_) dt = clamped ? std::max(dt, dt_try) : dt_try;
      if (fixed_step_) dt = run_.dt;
    }
    if (rep.samples == 0 || last_sample_t_ != t) observe(t);
    rep.t_final = t;
    const double Tf = sys_.kinetic(x_.data()), Vf = sys_.potential(x_.data());
    rep.energy_final = Tf + Vf;
    rep.energy_drift_final = rep.total_energy_drift_final = std::abs(Tf + Vf - E0_ - shift_) / rep.energy_scale;
    if (rep.constrained) {
      rep.constraints.final_position_residual = sys_.position_residual(x_.data());
      rep.constraints.final_velocity_residual = sys_.velocity_residual(x_.data());
    }
    rep.rhs_evaluations = sys_.rhs_evaluations;
    out_.q_final.assign(x_.begin(), x_.begin() + dim);
    out_.qd_final.assign(x_.begin() + dim, x_.end());
    out_.effect_evaluations = sys_.counts();
    rep.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    return std::move(out_);
  }

 private:
  void momentum(const double* x, Vector3d& P, Vector3d& L) const {
    P.setZero();
    L.setZero();
    for (int i = 0; i < sys_.bodies(); ++i) {
      const Vector3d p = sys_.mass()[static_cast<std::size_t>(i)] * at(x + sys_.dim(), i);
      P += p;
      L += at(x, i).cross(p);
    }
  }

  int rank(const double* x) {
    Eigen::MatrixXd C;
    jacobian(sys_.rows(), x, sys_.dim(), C);
    return lagrangian::detail::numeric_rank(C);
  }

  void check_finite(double t) {
    for (double v : x_)
      if (!std::isfinite(v)) throw SimulationError("run stopped: non-finite state at " + describe(sys_, x_, t), t);
  }

  void track_constraints(double t) {
    auto& c = out_.report.constraints;
    c.max_position_residual = std::max(c.max_position_residual, sys_.position_residual(x_.data()));
    c.max_velocity_residual = std::max(c.max_velocity_residual, sys_.velocity_residual(x_.data()));
    (void)t;
  }

  void observe(double t) {
    RunReport& rep = out_.report;
    const double E = sys_.kinetic(x_.data()) + sys_.potential(x_.data());
    const double drift = std::abs(E - E0_ - shift_) / rep.energy_scale;
    rep.energy_drift_max = std::max(rep.energy_drift_max, drift);
    rep.total_energy_drift_max = rep.energy_drift_max;
    Vector3d P, L;
    momentum(x_.data(), P, L);
    rep.linear_momentum_drift_final = (P - P0_).norm();
    rep.angular_momentum_drift_final = (L - L0_).norm();
    rep.linear_momentum_drift_max = std::max(rep.linear_momentum_drift_max, rep.linear_momentum_drift_final);
    rep.angular_momentum_drift_max = std::max(rep.angular_momentum_drift_max, rep.angular_momentum_drift_final);
    if (rep.constrained && !sys_.rows().empty()) rep.constraints.min_rank = std::min(rep.constraints.min_rank, rank(x_.data()));
    ++rep.samples;
    last_sample_t_ = t;
    if (sample_) sample_(t, x_.data(), x_.data() + sys_.dim(), sys_.dim(), E);
  }

  void log_event(double t, EventKind kind, const std::string& name, double J, double u_in, double u_out,
                 double T_before = 0, double T_after = 0) {
    EventRecord e;
    e.t = t;
    e.kind = kind;
    e.name = name;
    e.impulse = J;
    e.approach_speed = u_in;
    e.separation_speed = u_out;
    e.kinetic_energy_before = T_before;
    e.kinetic_energy_after = T_after;
    out_.report.events.push_back(std::move(e));
    if (kind == EventKind::impact) ++out_.report.impacts;
  }

  /// Finds the first contact closing in [t0, t1] on the step's interpolant,
  /// moves the state back to that time and resolves the impacts there.
  bool handle_contacts(double t0, double& t1) {
    sys_.rhs(x_.data(), f1_.data(), t1);
    const int dim = sys_.dim();
    StepPath path{t0, t1 - t0, xprev_.data(), xprev_.data() + dim, f0_.data() + dim,
                  x_.data(),  x_.data() + dim,  f1_.data() + dim};
    if (!(path.h > 0)) return false;
    sys_.candidates(path, cand_);
    double t_hit = std::numeric_limits<double>::infinity();
    Contact* first = nullptr;
    for (Contact* c : cand_) {
      double rate0 = 0, rate1 = 0;
      const double g0 = gap_on_path(*c, path, t0, &rate0);
      const double g1 = gap_on_path(*c, path, t1, &rate1);
      double lo = t0, hi = t1, glo = g0, ghi = g1;
      // The extremum of the gap inside the step, where its rate vanishes.
      auto extremum = [&]() {
        auto rate = [&](double t) {
          double r = 0;
          gap_on_path(*c, path, t, &r);
          return r;
        };
        const auto fr = lagrangian::detail::time_function(rate);
        const auto br = lagrangian::detail::bracket_root(fr, t0, t1, rate0, rate1, 1e-13);
        return 0.5 * (br.first + br.second);
      };
      if (g1 < 0 && g0 > 0) {
        // a crossing
      } else if (g1 < 0 && rate0 > 0 && rate1 < 0) {
        // leaving a touch (e.g. just after an impact), rising, then falling through
        const double tm = extremum();
        const double gm = gap_on_path(*c, path, tm);
        if (gm <= 0) continue;
        lo = tm;
        glo = gm;
      } else if (g0 > 0 && g1 > 0 && rate0 < 0 && rate1 > 0) {
        // a dip below zero and back inside the step
        const double tm = extremum();
        const double gm = gap_on_path(*c, path, tm);
        if (gm >= 0) continue;
        hi = tm;
        ghi = gm;
      } else {
        continue;
      }
      if (lo >= t_hit) continue;
      auto gap = [&](double t) { return gap_on_path(*c, path, t); };
      const auto fg = lagrangian::detail::time_function(gap);
      const auto br = lagrangian::detail::bracket_root(fg, lo, hi, glo, ghi, 1e-13);
      const double tc = br.first;  // the contact is still open at the bracket's left end
      if (tc < t_hit) {
        t_hit = tc;
        first = c;
      }
    }
    if (!first) return false;
    // Redo the step up to the contact time.
    x_ = xprev_;
    stepper_->reset();
    double t = t0;
    double h = t_hit - t0;
    while (t < t_hit && h > 0) {
      double dt_try = t_hit - t;
      if (stepper_->try_step(x_, t, dt_try)) {
        t = t_hit;
      } else {
        ++out_.report.rejected_steps;
        h = dt_try;
        // A shortened re-step: take smaller pieces.
        while (t < t_hit) {
          double d = std::min(h, t_hit - t);
          const double t_before = t;
          if (stepper_->try_step(x_, t, d)) {
            if (t_hit - t < 1e-15 * std::max(1.0, std::abs(t))) t = t_hit;
            h = d;
          } else {
            ++out_.report.rejected_steps;
            if (!(d > 1e-14 * std::max(1.0, std::abs(t))))
              throw SimulationError("run stopped: step size underflow while moving to a contact at " +
                                        describe(sys_, x_, t),
                                    t);
            h = d;
            t = t_before;
          }
        }
      }
    }
    t1 = t_hit;
    resolve_at(t1, first);
    return true;  // the next step starts at the contact time
  }

  /// Resolves every contact that is closed and approaching at t, fastest
  /// first, until none approaches (sequential pairwise impacts).
  void resolve_at(double t, Contact* located) {
    const int dim = sys_.dim();
    const double tol = 1e-9 * (1.0 + std::abs(*std::max_element(x_.begin(), x_.begin() + dim, [](double a, double b) {
                         return std::abs(a) < std::abs(b);
                       })));
    std::vector<Contact*> near;
    sys_.near_contacts(x_.data(), tol, near);
    if (located && std::find(near.begin(), near.end(), located) == near.end()) near.push_back(located);
    const double touch = 1e-9;
    for (int it = 0;; ++it) {
      if (it > 1000 * static_cast<int>(near.size() + 1))
        throw SimulationError("run stopped: simultaneous impacts at t = " + std::to_string(t) +
                                  " s did not settle after " + std::to_string(it) + " pairwise impacts",
                              t);
      Contact* fastest = nullptr;
      double u_max = touch;
      for (Contact* c : near) {
        if (c->resting) continue;
        const double u = -c->rate(x_.data(), x_.data() + dim);
        if (u > u_max) {
          u_max = u;
          fastest = c;
        }
      }
      if (!fastest) break;
      Contact& c = *fastest;
      const double T_before = sys_.kinetic(x_.data());
      const bool accumulating = u_max <= 1e-6 * c.max_approach ||
                                t - c.last_impact <= 1e-10 * std::max(1.0, std::abs(t));
      const double e = accumulating ? 0.0 : c.e;
      const double J = sys_.impulse(x_.data(), c, e);
      const double T_after = sys_.kinetic(x_.data());
      shift_ += T_after - T_before;
      out_.report.impact_energy_loss += T_before - T_after;
      c.max_approach = std::max(c.max_approach, u_max);
      c.last_impact = t;
      const double u_out = c.rate(x_.data(), x_.data() + dim);
      log_event(t, accumulating ? EventKind::rest : EventKind::impact, c.name, J, u_max, u_out, T_before, T_after);
      if (accumulating && sys_.pressed(x_.data(), c)) sys_.make_resting(c);
      sys_.wake_approaching(x_.data(), touch, near);
    }
    // Slow touches pressed shut become resting contacts too.
    for (Contact* c : near) {
      if (c->resting) continue;
      const double u = -c->rate(x_.data(), x_.data() + dim);
      if (std::abs(u) <= touch && c->gap(x_.data()) <= tol && sys_.pressed(x_.data(), *c)) {
        sys_.make_resting(*c);
        log_event(t, EventKind::rest, c->name, 0, std::max(u, 0.0), 0, sys_.kinetic(x_.data()),
                  sys_.kinetic(x_.data()));
      }
    }
  }

  const Scene& scene_;
  const RunSpec& run_;
  System sys_;
  const ParticleSample& sample_;
  const SampleTick& tick_;
  ParticleRun out_;
  std::unique_ptr<Stepper> stepper_;
  X x_, xprev_, f0_, f1_;
  std::vector<Contact*> cand_;
  double E0_ = 0, shift_ = 0;
  bool fixed_step_ = false;  // rk4: steps on the grid t0 + k dt
  bool f_cached_ = false;  // f1_ holds the derivative at the current state
  Vector3d P0_ = Vector3d::Zero(), L0_ = Vector3d::Zero();
  double next_output_ = 0, last_sample_t_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace

struct ComposedRhs::Impl {
  explicit Impl(const Scene& s) : system(s) {}
  System system;
};
ComposedRhs::ComposedRhs(const Scene& scene) : impl_(std::make_unique<Impl>(scene)) {}
ComposedRhs::~ComposedRhs() = default;
int ComposedRhs::size() const { return 2 * impl_->system.dim(); }
void ComposedRhs::operator()(const double* x, double* dx, double t) { impl_->system.rhs(x, dx, t); }
std::uint64_t ComposedRhs::evaluations() const { return impl_->system.rhs_evaluations; }

ParticleRun run_particles(const Scene& scene, const ParticleSample& sample, const SampleTick& tick) {
  Runner runner(scene, sample, tick);
  return runner.go();
}

bool event_driven_eligible(const Scene& scene) {
  // The conditions Scene::validate() demands of engine = "event_driven".
  if (scene.model || !scene.box || !scene.sphere_contacts || !scene.sphere_contacts->bodies.empty()) return false;
  for (const auto& kind : scene.declared())
    if (kind != "sphere_contacts" && kind != "plane_contacts" && kind != "box_contacts") return false;
  return std::all_of(scene.bodies.begin(), scene.bodies.end(), [](const Body& b) { return b.radius > 0; });
}

std::string inspect_particles(const Scene& scene) {
  System sys(scene);
  std::ostringstream os;
  os.precision(6);
  const int n = sys.bodies();
  os << "scene        " << scene.name << "\n";
  if (!scene.description.empty()) os << "description  " << scene.description << "\n";
  os << "engine       " << (scene.run.engine == "auto" ? (event_driven_eligible(scene) ? "event_driven" : "ode")
                                                          : scene.run.engine)
     << "\n";
  os << "bodies       " << n << " (" << 3 * n << " Cartesian coordinates)\n";
  const int shown = std::min(n, 20);
  for (int i = 0; i < shown; ++i) {
    const Body& b = scene.bodies[static_cast<std::size_t>(i)];
    os << "  " << b.name << ": m = " << b.mass << " kg";
    if (b.radius > 0) os << ", R = " << b.radius << " m";
    os << ", r = (" << b.position.transpose() << ") m, v = (" << b.velocity.transpose() << ") m/s"
       << ", p = m v = (" << (b.mass * b.velocity).transpose() << ") kg·m/s\n";
  }
  if (n > shown) os << "  … " << n - shown << " more\n";

  // Degrees of freedom from the rank of the constraint Jacobian at t0.
  const auto& rows = sys.rows();
  std::vector<double> x(static_cast<std::size_t>(6 * n), 0.0);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      x[static_cast<std::size_t>(3 * i + k)] = scene.bodies[static_cast<std::size_t>(i)].position[k];
      x[static_cast<std::size_t>(3 * n + 3 * i + k)] = scene.bodies[static_cast<std::size_t>(i)].velocity[k];
    }
  Eigen::MatrixXd C;
  jacobian(rows, x.data(), 3 * n, C);
  const int rank = lagrangian::detail::numeric_rank(C);
  os << "constraints  " << rows.size() << " holonomic";
  if (!rows.empty()) {
    os << " (";
    for (std::size_t k = 0; k < rows.size(); ++k) os << (k ? ", " : "") << rows[k].name;
    os << ")";
  }
  os << "\n";
  os << "rank         " << rank << " (redundant constraints: " << static_cast<int>(rows.size()) - rank << ")\n";
  os << "DOF          " << 3 * n - rank << " = " << 3 * n << " coordinates − rank " << rank << "\n";

  Vector3d P = Vector3d::Zero(), L = Vector3d::Zero();
  for (int i = 0; i < n; ++i) {
    const Body& b = scene.bodies[static_cast<std::size_t>(i)];
    P += b.mass * b.velocity;
    L += b.position.cross(b.mass * b.velocity);
  }
  os << "momentum     P = (" << P.transpose() << ") kg·m/s, L about the origin = (" << L.transpose() << ") kg·m²/s\n";
  const double T = sys.kinetic(x.data()), V = sys.potential(x.data());
  os << "energy       T = " << T << " J, V = " << V << " J, E = T + V = " << T + V << " J\n";

  // Conserved quantities: what no declared effect can change.
  std::vector<std::string> conserved;
  const bool walls = !scene.planes.empty() || scene.box.has_value();
  const bool anchored = std::any_of(scene.links.begin(), scene.links.end(), [](const Link& l) { return l.b.empty(); }) ||
                        !scene.surfaces.empty() ||
                        std::any_of(scene.springs.begin(), scene.springs.end(), [](const Spring& s) { return s.b.empty(); });
  const bool drag = !scene.linear_drag.empty() || !scene.quadratic_drag.empty();
  const bool lossy_contacts = (scene.sphere_contacts && scene.sphere_contacts->restitution < 1) ||
                              std::any_of(scene.planes.begin(), scene.planes.end(),
                                          [](const PlaneContact& p) { return p.restitution < 1; }) ||
                              (scene.box && scene.box->restitution < 1);
  if (!drag) conserved.push_back(lossy_contacts ? "E = T + V between impacts (impacts with e < 1 remove energy)"
                                                : "E = T + V (no dissipative effect declared)");
  if (!walls && !anchored && !drag) {
    if (!scene.gravity) {
      conserved.push_back("linear momentum P (no external force)");
      conserved.push_back("angular momentum L (internal forces are central)");
    } else {
      conserved.push_back("the components of P perpendicular to g (gravity is the only external force)");
      conserved.push_back("the component of L along g about any point");
    }
  }
  os << "conserved    " << (conserved.empty() ? std::string("none detected") : conserved.front()) << "\n";
  for (std::size_t k = 1; k < conserved.size(); ++k) os << "             " << conserved[k] << "\n";

  const auto declared = scene.declared();
  os << "active       ";
  if (declared.empty()) os << "none (free flight)";
  for (std::size_t k = 0; k < declared.size(); ++k) os << (k ? ", " : "") << declared[k];
  os << "\n";
  return os.str();
}

}  // namespace lagrangian::scene::detail
