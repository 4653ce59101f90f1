#pragma once
// Internal to the particle scenes' engine: the position-level constraint
// rows g(r) = 0 (links, surfaces) and the contacts of a scene of bodies, on
// the state x = [r; v] of 3N Cartesian positions (m) and velocities (m/s).

#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

#include <Eigen/Dense>

#include "lagrangian/integrate/detail/contact_rules.hpp"
#include "particle_forces.hpp"

namespace lagrangian::scene::detail::particles {

// -- constraint rows -----------------------------------------------------------

/// One position-level constraint row g(r) = 0 with its gradient and γ, the
/// part of g̈ that does not contain the accelerations (g̈ = ∇g·a + γ).
struct Row {
  enum class Kind { link, plane, sphere, rest_plane, rest_spheres };
  Kind kind = Kind::link;
  int a = -1, b = -1;  // bodies; b = -1 for a fixed end
  Vector3d p = Vector3d::Zero(), n = Vector3d::Zero();
  double length = 0;  // link L, sphere ρ, contact R or R_a + R_b
  int source = -1;    // the scene's link or surface this row is (-1 for a resting contact)
  std::string name;

  // g, its gradient and γ on numbers S: doubles in a run, AD numbers
  // (ad::Jet) for the tangent flow (particle_tangent.cpp), whose pass may
  // seed one of the scene's parameters `par` (a link's length, a surface's
  // point or radius).

  /// p (m): the anchor, a plane's point or a sphere's centre.
  template <class S>
  Vector3<S> point(const Parameter& par) const {
    Vector3<S> x = p.template cast<S>();
    if constexpr (!std::is_same_v<S, double>) {
      if ((kind == Kind::plane || kind == Kind::sphere) && par.kind == Parameter::Kind::surface_point &&
          par.index == source)
        x[par.component].g[0] = 1.0;
    }
    return x;
  }
  /// L, ρ or R (m).
  template <class S>
  S size(const Parameter& par) const {
    return seeded<S>(length, (kind == Kind::link && par.is(Parameter::Kind::link_length, source)) ||
                                 (kind == Kind::sphere && par.is(Parameter::Kind::surface_radius, source)));
  }
  /// r_a − r_b (m), or r_a − p for a fixed end.
  template <class S>
  Vector3<S> d(const S* r, const Parameter& par = {}) const {
    return at(r, a) - (b >= 0 ? at(r, b) : point<S>(par));
  }
  /// Unit of the row's multiplier: N/m for the rows ½(|d|² − L²), N for gaps in m.
  const char* multiplier_unit() const { return kind == Kind::link || kind == Kind::sphere ? "N/m" : "N"; }
  /// g(r): m² for the rows ½(|d|² − L²), m for gaps.
  template <class S>
  S value(const S* r, const Parameter& par = {}) const {
    switch (kind) {
      case Kind::link: {
        const S l = size<S>(par);
        return 0.5 * (d(r, par).squaredNorm() - l * l);
      }
      case Kind::plane: return n.template cast<S>().dot(at(r, a) - point<S>(par));
      case Kind::sphere: {
        const S rho = size<S>(par);
        return 0.5 * ((at(r, a) - point<S>(par)).squaredNorm() - rho * rho);
      }
      case Kind::rest_plane: return n.template cast<S>().dot(at(r, a) - p.template cast<S>()) - length;
      case Kind::rest_spheres: return d(r).norm() - length;
    }
    return S(0.0);
  }
  /// Gradient with respect to body a (body b gets its negative).
  template <class S>
  Vector3<S> grad(const S* r, const Parameter& par = {}) const {
    switch (kind) {
      case Kind::link: return d(r, par);
      case Kind::plane:
      case Kind::rest_plane: return n.template cast<S>();
      case Kind::sphere: return at(r, a) - point<S>(par);
      case Kind::rest_spheres: return d(r).normalized();
    }
    return Vector3<S>(S(0.0), S(0.0), S(0.0));
  }
  /// γ = g̈ − ∇g·a = vᵀ ∂²g/∂r² v (m²/s² or m/s²); no parameter enters it.
  template <class S>
  S gamma(const S* r, const S* v) const {
    const Vector3<S> dv = b >= 0 ? Vector3<S>(at(v, a) - at(v, b)) : at(v, a);
    switch (kind) {
      case Kind::link:
      case Kind::sphere: return dv.squaredNorm();
      case Kind::plane:
      case Kind::rest_plane: return S(0.0);
      case Kind::rest_spheres: {
        const Vector3<S> dd = d(r);
        const S l = dd.norm();
        const S radial = dd.dot(dv) / l;
        return (dv.squaredNorm() - radial * radial) / l;
      }
    }
    return S(0.0);
  }
};

/// C = ∂g/∂r of the rows (rows × dim): each row's gradient on body a and its
/// negative on body b.
inline void jacobian(const std::vector<Row>& rows, const double* r, int dim, Eigen::MatrixXd& C) {
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
  int plane = -1;  // the scene's contact plane it is (-1 for a box wall or a pair of spheres)
  std::string name;
  int id = -1;  // its number among the scene's contacts (ParticleModel::contact)
  lagrangian::detail::ContactHistory history;  // for the Zeno rule
  bool resting = false;

  double gap(const double* r) const {
    return pair ? (at(r, a) - at(r, b)).norm() - R : n.dot(at(r, a) - p) - R;
  }
  Vector3d normal(const double* r) const { return pair ? (at(r, a) - at(r, b)).normalized() : n; }
  double rate(const double* r, const double* v) const {
    const Vector3d dv = at(v, a) - (pair ? at(v, b) : Vector3d::Zero());
    return normal(r).dot(dv);
  }
  /// φ and φ̇ from the positions and velocities of body a (and b for a pair).
  lagrangian::detail::GapRate gap_rate(const Vector3d& ra, const Vector3d& va, const Vector3d& rb,
                                       const Vector3d& vb) const {
    if (!pair) return {n.dot(ra - p) - R, n.dot(va)};
    const Vector3d d = ra - rb;
    const double l = d.norm();
    return {l - R, d.dot(va - vb) / l};
  }
};

}  // namespace lagrangian::scene::detail::particles
