// Newton's law at an impact of a particle scene, with its links' and
// surfaces' rows kept, and its derivatives (particle_impact.hpp).

#include "particle_impact.hpp"

#include <algorithm>
#include <cstddef>
#include <type_traits>
#include <vector>

#include <Eigen/Core>

#include "lagrangian/ad/cmath.hpp"
#include "lagrangian/ad/eigen.hpp"
#include "lagrangian/ad/jet.hpp"
#include "lagrangian/ad/traits.hpp"
#include "lagrangian/mechanics/detail/min_norm_solver.hpp"

namespace lagrangian::scene::detail {
namespace {

using particles::at;
using particles::Contact;
using particles::Parameter;
using particles::ParticleModel;
using particles::Vector3;
using Kind = particles::Parameter::Kind;

/// The bodies the law reads and moves: the contact's and those of the
/// fixed rows (an anchor, −1, is none), in increasing order.
std::vector<int> law_bodies(const ParticleModel& model, const Contact& c) {
  std::vector<int> bodies{c.a};
  if (c.pair) bodies.push_back(c.b);
  for (int i = 0; i < model.fixed_rows(); ++i) {
    const particles::Row& row = model.rows()[static_cast<std::size_t>(i)];
    bodies.push_back(row.a);
    if (row.b >= 0) bodies.push_back(row.b);
  }
  std::sort(bodies.begin(), bodies.end());
  bodies.erase(std::unique(bodies.begin(), bodies.end()), bodies.end());
  return bodies;
}

/// The approach speed v (m/s) and the contact's impulse μ_k (N·s).
template <class J>
struct LawResult {
  J approach, impulse;
};

/// The law (particle_impact.hpp) on doubles (a plain run) or on numbers J
/// whose directions are those of the state or of the seeded parameter `p`:
/// v_plus = q̇⁺ on the coordinates of `bodies` (the others are left alone).
/// W is k × d over those coordinates, k = rows + 1, d = 3 |bodies|; μ's
/// derivatives are those of (W M⁻¹ Wᵀ) μ = b,
///   A δμ = δb − δA μ,
/// solved by the same factors as μ.
template <class J>
LawResult<J> law(const ParticleModel& model, const Contact& c, const std::vector<int>& bodies, const J* r,
                 const J* v, const J& e, const Parameter& p, J* v_plus) {
  const int rows = model.fixed_rows(), k = rows + 1, d = 3 * static_cast<int>(bodies.size());
  const auto slot = [&](int body) {
    return 3 * static_cast<int>(std::lower_bound(bodies.begin(), bodies.end(), body) - bodies.begin());
  };
  const auto coordinate = [&](int j) { return 3 * bodies[static_cast<std::size_t>(j / 3)] + j % 3; };
  std::vector<J> w(static_cast<std::size_t>(k * d), J(0.0)), inverse(static_cast<std::size_t>(d));
  for (int j = 0; j < d; ++j) {
    const int body = bodies[static_cast<std::size_t>(j / 3)];
    inverse[static_cast<std::size_t>(j)] =
        particles::inverse_mass<J>(1.0 / model.mass()[static_cast<std::size_t>(body)], body, p);
  }
  const auto put = [&](int row, int body, const Vector3<J>& gradient, double sign) {
    for (int a = 0; a < 3; ++a) w[static_cast<std::size_t>(row * d + slot(body) + a)] += sign * gradient[a];
  };
  for (int i = 0; i < rows; ++i) {
    const particles::Row& row = model.rows()[static_cast<std::size_t>(i)];
    const Vector3<J> gradient = row.grad(r, p);
    put(i, row.a, gradient, 1.0);
    if (row.b >= 0) put(i, row.b, gradient, -1.0);
  }
  const Vector3<J> normal =
      c.pair ? Vector3<J>((at(r, c.a) - at(r, c.b)).normalized()) : Vector3<J>(c.n.template cast<J>());
  put(rows, c.a, normal, 1.0);
  if (c.pair) put(rows, c.b, normal, -1.0);
  // b = −(C q̇⁻, (1 + e) v), and A = W M⁻¹ Wᵀ.
  std::vector<J> b(static_cast<std::size_t>(k)), a(static_cast<std::size_t>(k * k));
  J approach(0.0);
  for (int i = 0; i < k; ++i) {
    J rate(0.0);
    for (int j = 0; j < d; ++j) rate += w[static_cast<std::size_t>(i * d + j)] * v[coordinate(j)];
    if (i == rows) approach = rate;
    b[static_cast<std::size_t>(i)] = i == rows ? -(1.0 + e) * rate : -rate;
    for (int l = 0; l <= i; ++l) {
      J s(0.0);
      for (int j = 0; j < d; ++j)
        s += w[static_cast<std::size_t>(i * d + j)] * inverse[static_cast<std::size_t>(j)] *
             w[static_cast<std::size_t>(l * d + j)];
      a[static_cast<std::size_t>(i * k + l)] = a[static_cast<std::size_t>(l * k + i)] = s;
    }
  }
  Eigen::MatrixXd values(k, k);
  Eigen::VectorXd rhs(k), solution(k);
  for (int i = 0; i < k; ++i)
    for (int l = 0; l < k; ++l) values(i, l) = ad::value_of(a[static_cast<std::size_t>(i * k + l)]);
  lagrangian::detail::MinNormSolver solver(k);
  solver.factorize(values.data());
  std::vector<J> mu(static_cast<std::size_t>(k));
  for (int i = 0; i < k; ++i) rhs[i] = ad::value_of(b[static_cast<std::size_t>(i)]);
  solver.solve(rhs.data(), solution.data());
  const Eigen::VectorXd mu_value = solution;
  for (int i = 0; i < k; ++i) mu[static_cast<std::size_t>(i)] = J(mu_value[i]);
  if constexpr (!std::is_same_v<J, double>) {
    for (int dir = 0; dir < J::directions; ++dir) {
      const auto at_dir = static_cast<std::size_t>(dir);
      for (int i = 0; i < k; ++i) {
        rhs[i] = b[static_cast<std::size_t>(i)].g[at_dir];
        for (int l = 0; l < k; ++l) rhs[i] -= a[static_cast<std::size_t>(i * k + l)].g[at_dir] * mu_value[l];
      }
      solver.solve(rhs.data(), solution.data());
      for (int i = 0; i < k; ++i) mu[static_cast<std::size_t>(i)].g[at_dir] = solution[i];
    }
  }
  for (int j = 0; j < d; ++j) {
    J change(0.0);
    for (int i = 0; i < k; ++i) change += w[static_cast<std::size_t>(i * d + j)] * mu[static_cast<std::size_t>(i)];
    v_plus[coordinate(j)] = v[coordinate(j)] + inverse[static_cast<std::size_t>(j)] * change;
  }
  return {approach, mu[static_cast<std::size_t>(rows)]};
}

}  // namespace

double impact_map(const ParticleModel& model, const Contact& c, const double* q, const double* qd, double e,
                  double* qd_plus, double* jacobian) {
  using JetWide = ad::Jet<double, 4, 1>;
  const int n = model.dim();
  const std::vector<int> bodies = law_bodies(model, c);
  const int d = 3 * static_cast<int>(bodies.size());
  std::vector<JetWide> r(static_cast<std::size_t>(n)), v(static_cast<std::size_t>(n)),
      plus(static_cast<std::size_t>(n));
  std::copy(qd, qd + n, qd_plus);
  std::fill(jacobian, jacobian + static_cast<std::ptrdiff_t>(n) * (2 * n), 0.0);
  for (int i = 0; i < n; ++i) jacobian[(n + i) * n + i] = 1.0;
  const auto coordinate = [&](int j) { return 3 * bodies[static_cast<std::size_t>(j / 3)] + j % 3; };
  double approach = 0;
  // Directions: the positions, then the velocities, of the law's coordinates.
  for (int first = 0; first < 2 * d; first += JetWide::directions) {
    for (int i = 0; i < n; ++i) {
      r[static_cast<std::size_t>(i)] = JetWide(q[i]);
      v[static_cast<std::size_t>(i)] = JetWide(qd[i]);
    }
    const int width = std::min(JetWide::directions, 2 * d - first);
    for (int s = 0; s < width; ++s) {
      const int dir = first + s;
      (dir < d ? r : v)[static_cast<std::size_t>(coordinate(dir % d))].g[static_cast<std::size_t>(s)] = 1.0;
    }
    approach = law(model, c, bodies, r.data(), v.data(), JetWide(e), Parameter{}, plus.data()).approach.v;
    for (int s = 0; s < width; ++s) {
      const int dir = first + s, column = (dir < d ? 0 : n) + coordinate(dir % d);
      for (int j = 0; j < d; ++j) {
        const int row = coordinate(j);
        jacobian[column * n + row] = plus[static_cast<std::size_t>(row)].g[static_cast<std::size_t>(s)];
      }
    }
  }
  for (int j = 0; j < d; ++j) qd_plus[coordinate(j)] = plus[static_cast<std::size_t>(coordinate(j))].v;
  return approach;
}

double impulse(const ParticleModel& model, const Contact& c, double e, double* x) {
  const int n = model.dim();
  double* v = x + n;
  return law(model, c, law_bodies(model, c), x, v, e, Parameter{}, v).impulse;
}

double impact_along_parameter(const ParticleModel& model, const Contact& c, const Parameter& p, const double* q,
                              const double* qd, bool plastic, double* dqd_plus) {
  using D = ad::Jet<double, 1, 1>;
  const int n = model.dim();
  const bool own_e = c.pair ? p.is(Kind::sphere_restitution)
                     : c.plane >= 0 ? p.is(Kind::plane_restitution, c.plane)
                                    : p.is(Kind::box_restitution);
  const D e = plastic ? D(0.0) : particles::seeded<D>(c.e, own_e);
  const std::vector<int> bodies = law_bodies(model, c);
  std::vector<D> r(q, q + n), v(qd, qd + n), plus(v);
  law(model, c, bodies, r.data(), v.data(), e, p, plus.data());
  for (int i = 0; i < n; ++i) dqd_plus[i] = plus[static_cast<std::size_t>(i)].g[0];
  double dphi = 0;
  if (p.kind == Kind::radius && (p.index == c.a || (c.pair && p.index == c.b))) dphi = -1.0;
  if (!c.pair) {
    // The wall's point: its plane's, or the box's lower corner for a wall
    // whose normal points along +axis and its upper corner for one along −axis.
    const double side = c.n.sum();
    if ((c.plane >= 0 && p.kind == Kind::plane_point && p.index == c.plane) ||
        (c.plane < 0 && ((p.kind == Kind::box_min && side > 0) || (p.kind == Kind::box_max && side < 0))))
      dphi -= c.n[p.component];
  }
  return dphi;
}

}  // namespace lagrangian::scene::detail
