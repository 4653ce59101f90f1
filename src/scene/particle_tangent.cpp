// The tangent flow of a particle scene (particle_engine.hpp): bodies in
// Cartesian coordinates under their declared force effects, with
// J = ∂a/∂(r, v) by automatic differentiation of the force kernels
// (particle_forces.hpp) on ad::Jet numbers, as the TangentModel that
// lyapunov_spectrum() and floquet_multipliers() run.

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "lagrangian/ad/eigen.hpp"
#include "lagrangian/ad/jet.hpp"
#include "lagrangian/analysis/floquet.hpp"
#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/errors.hpp"
#include "particle_engine.hpp"
#include "particle_model.hpp"

namespace lagrangian::scene::detail {
namespace {

using particles::ParticleModel;

/// Directions per pass of the whole Jacobian.
constexpr int kWidth = 4;
using JetWide = ad::Jet<double, kWidth, 1>;
using JetOne = ad::Jet<double, 1, 1>;

/// The most bodies whose tangent flow is taken: 6N tangent vectors of 6N
/// values each, and J (3N × 6N) in 6N/4 passes of the force kernels.
constexpr std::size_t kMaxBodies = 100;

/// OptionError (`command: particle scene '<name>': …`) for a scene whose
/// tangent flow is not derived: constraint rows, contacts, a gas (whose
/// spheres are held by contacts), more than kMaxBodies bodies. Read from the
/// scene before anything is built.
void require_force_effects_only(const Scene& scene, const char* command) {
  std::vector<std::string> has;
  const auto count = [](std::size_t k, const char* one, const char* many) {
    return std::to_string(k) + " " + (k == 1 ? one : many);
  };
  if (!scene.links.empty()) has.push_back(count(scene.links.size(), "link", "links"));
  if (!scene.surfaces.empty()) has.push_back(count(scene.surfaces.size(), "surface", "surfaces"));
  if (scene.gas) has.push_back("a gas");
  if (scene.sphere_contacts) has.push_back("sphere contacts");
  if (!scene.planes.empty()) has.push_back(count(scene.planes.size(), "contact plane", "contact planes"));
  if (scene.box) has.push_back("a box");
  std::string why;
  if (!has.empty()) {
    why = "the tangent flow of a particle scene is derived for bodies under force effects ([gravity], "
          "[newtonian_gravity], [[springs]], [[linear_drag]], [[quadratic_drag]]), without constraints or contacts; "
          "this one has ";
    for (std::size_t i = 0; i < has.size(); ++i) why += (i == 0 ? "" : ", ") + has[i];
  } else if (scene.bodies.size() > kMaxBodies) {
    why = "the tangent flow of a particle scene is taken for at most " + std::to_string(kMaxBodies) +
          " bodies; this one has " + std::to_string(scene.bodies.size());
  } else {
    return;
  }
  throw OptionError(std::string(command) + ": particle scene '" + scene.name + "': " + why);
}

/// A particle scene without constraint rows or contacts as a TangentModel:
/// q = r (3N positions, m), q̇ = v (m/s), q̈ = a(r, v) of its force kernels,
/// p = m v. The numbers of the passes are kept, sized once.
class ParticleTangent {
 public:
  /// `scene` has passed require_force_effects_only().
  explicit ParticleTangent(const Scene& scene) : model_(scene), x0_(initial_state(scene)) {
    if (model_.fixed_rows() > 0 || model_.has_contacts())
      throw std::logic_error("ParticleTangent: a scene with constraint rows or contacts");
    const auto dim = static_cast<std::size_t>(model_.dim());
    wide_.resize(3 * dim);
    one_.resize(3 * dim);
  }
  ParticleTangent(const ParticleTangent&) = delete;
  ParticleTangent& operator=(const ParticleTangent&) = delete;

  lagrangian::detail::TangentModel tangent_model() const {
    lagrangian::detail::TangentModel tm;
    tm.model = this;
    tm.n = model_.dim();
    tm.evaluate = &evaluate;
    tm.momentum = &momentum;
    tm.evaluate_direction = &evaluate_direction;
    return tm;
  }
  const double* q0() const { return x0_.data(); }
  const double* qd0() const { return x0_.data() + model_.dim(); }

 private:
  /// q̈ and ∂q̈/∂(q, q̇) (n × 2n, column-major) in passes of kWidth
  /// directions; without a drag the velocity columns are 0 and not passed.
  static void evaluate(const void* self, const double* q, const double* qd, double, double* qdd, double* jacobian) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    const int n = s.model_.dim();
    const int directions = s.model_.velocity_dependent() ? 2 * n : n;
    if (directions == n) std::fill(jacobian + n * n, jacobian + 2 * n * n, 0.0);  // n ≤ 300: no overflow
    JetWide *r = s.wide_.data(), *v = r + n, *a = v + n;
    for (int first = 0; first < directions; first += kWidth) {
      for (int i = 0; i < n; ++i) {
        r[i] = JetWide(q[i]);
        v[i] = JetWide(qd[i]);
      }
      const int width = std::min(kWidth, directions - first);
      for (int k = 0; k < width; ++k) {
        const int d = first + k;
        (d < n ? r[d] : v[d - n]).g[static_cast<std::size_t>(k)] = 1.0;
      }
      s.model_.force_accelerations(r, v, a);
      for (int k = 0; k < width; ++k)
        for (int i = 0; i < n; ++i) jacobian[(first + k) * n + i] = a[i].g[static_cast<std::size_t>(k)];
      if (first == 0)
        for (int i = 0; i < n; ++i) qdd[i] = a[i].v;
    }
  }
  /// q̈ and (∂q̈/∂(q, q̇)) w along one direction w (2n values).
  static void evaluate_direction(const void* self, const double* q, const double* qd, double, const double* w,
                                 double* qdd, double* jw) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    const int n = s.model_.dim();
    JetOne *r = s.one_.data(), *v = r + n, *a = v + n;
    for (int i = 0; i < n; ++i) {
      r[i] = JetOne(q[i]);
      r[i].g[0] = w[i];
      v[i] = JetOne(qd[i]);
      v[i].g[0] = w[n + i];
    }
    s.model_.force_accelerations(r, v, a);
    for (int i = 0; i < n; ++i) {
      qdd[i] = a[i].v;
      jw[i] = a[i].g[0];
    }
  }
  /// ∂p/∂(q, q̇) = [0 | diag(m ⊗ 1₃)] (n × 2n, column-major), p = m v.
  /// With `dl_dq`, ∂L/∂q = −∂V/∂q = m a(r, v), the force kernels' forces
  /// (drag included: a scene with drag conserves no energy).
  static void momentum(const void* self, const double* q, const double* qd, double, double* out, double* dl_dq) {
    const auto& s = *static_cast<const ParticleTangent*>(self);
    const int n = s.model_.dim();
    std::fill(out, out + 2 * n * n, 0.0);
    for (int i = 0; i < n; ++i) out[(n + i) * n + i] = s.model_.mass()[static_cast<std::size_t>(i / 3)];
    if (dl_dq == nullptr) return;
    JetOne *r = s.one_.data(), *v = r + n, *a = v + n;
    for (int i = 0; i < n; ++i) {
      r[i] = JetOne(q[i]);
      v[i] = JetOne(qd[i]);
    }
    s.model_.force_accelerations(r, v, a);
    for (int i = 0; i < n; ++i) dl_dq[i] = s.model_.mass()[static_cast<std::size_t>(i / 3)] * a[i].v;
  }

  mutable ParticleModel model_;  // its kernels count their evaluations
  mutable std::vector<JetWide> wide_;
  mutable std::vector<JetOne> one_;
  std::vector<double> x0_;
};

}  // namespace

LyapunovResult particle_lyapunov(const Scene& scene, const LyapunovOptions& options) {
  require_force_effects_only(scene, "lyapunov");
  const ParticleTangent tangent(scene);
  return lagrangian::detail::lyapunov_spectrum(tangent.tangent_model(), tangent.q0(), tangent.qd0(), options);
}

FloquetResult particle_floquet(const Scene& scene, const FloquetOptions& options) {
  require_force_effects_only(scene, "floquet");
  const ParticleTangent tangent(scene);
  return lagrangian::detail::floquet_multipliers(tangent.tangent_model(), tangent.q0(), tangent.qd0(), options);
}

Eigen::MatrixXd particle_acceleration_jacobian(const Scene& scene, const std::vector<double>& x,
                                               Eigen::VectorXd* a) {
  require_force_effects_only(scene, "particle_acceleration_jacobian");
  const ParticleTangent tangent(scene);
  const lagrangian::detail::TangentModel tm = tangent.tangent_model();
  const int n = tm.n;
  if (static_cast<int>(x.size()) != 2 * n)
    throw OptionError("particle_acceleration_jacobian: x has " + std::to_string(x.size()) + " values; the scene's " +
                      "state has " + std::to_string(2 * n));
  Eigen::MatrixXd j(n, 2 * n);
  Eigen::VectorXd qdd(n);
  tm.evaluate(tm.model, x.data(), x.data() + n, 0.0, qdd.data(), j.data());
  if (a != nullptr) *a = qdd;
  return j;
}

}  // namespace lagrangian::scene::detail
