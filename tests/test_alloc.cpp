// No heap allocation per right-hand-side call for fixed-size models, and
// none per step in a run: allocations are counted by a replaced global
// operator new and, outside AddressSanitizer (which intercepts the C
// allocator itself), by wrapping malloc, calloc and realloc, which Eigen's
// dynamic-size temporaries use directly.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "lagrangian/lagrangian.hpp"
#include "lagrangian/text/fixed_size.hpp"
#include "lagrangian/text/text_model.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/impacts.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "runtime_chain.hpp"

// GCC cannot see that these new/delete pairs both use malloc/free.
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"

#if defined(__SANITIZE_ADDRESS__)
#define LAGRANGIAN_COUNT_MALLOC 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LAGRANGIAN_COUNT_MALLOC 0
#endif
#endif
#ifndef LAGRANGIAN_COUNT_MALLOC
#define LAGRANGIAN_COUNT_MALLOC 1
#endif

namespace {
std::atomic<long> g_allocations{0};
}

#if LAGRANGIAN_COUNT_MALLOC
// glibc's own entry points, which these wrappers forward to.
extern "C" void* __libc_malloc(std::size_t);
extern "C" void* __libc_calloc(std::size_t, std::size_t);
extern "C" void* __libc_realloc(void*, std::size_t);
extern "C" void* malloc(std::size_t n) noexcept {
  ++g_allocations;
  return __libc_malloc(n);
}
extern "C" void* calloc(std::size_t count, std::size_t size) noexcept {
  ++g_allocations;
  return __libc_calloc(count, size);
}
extern "C" void* realloc(void* p, std::size_t n) noexcept {
  ++g_allocations;
  return __libc_realloc(p, n);
}
#endif

// operator new counts itself only when malloc is not counted (it calls malloc).
void* operator new(std::size_t n) {
  if (!LAGRANGIAN_COUNT_MALLOC) ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t n) {
  if (!LAGRANGIAN_COUNT_MALLOC) ++g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

namespace {

using namespace lagrangian;
using namespace lagrangian::models;

template <class M>
long allocations_in_accelerations(const M& model) {
  constexpr int n = coordinate_count_v<M>;
  Workspace<n> ws;
  Vec<double, n> q = Vec<double, n>::Constant(0.3);
  Vec<double, n> qd = Vec<double, n>::Constant(-0.2);
  const long before = g_allocations.load();
  double sink = 0;
  for (int i = 0; i < 1000; ++i) {
    q[0] += 1e-4;
    sink += accelerations(model, ws, q, qd, 0.0)[0];
  }
  EXPECT_TRUE(std::isfinite(sink));
  return g_allocations.load() - before;
}

TEST(NoAllocation, AccelerationsDoNotAllocate) {
  EXPECT_EQ(allocations_in_accelerations(DoublePendulum()), 0);
  EXPECT_EQ(allocations_in_accelerations(PendulumChain<10>()), 0);
  EXPECT_EQ(allocations_in_accelerations(DrivenPendulum()), 0);
}

// Chains of 20 and 40 coordinates keep their Hessians in blocks from a
// per-thread pool, and run-time sized models their numbers in per-thread
// vectors: both are taken on a thread's first evaluation, and never again
// (70 run-time coordinates take the block passes, with the same numbers).
template <class M>
long allocations_after_the_first_call(const M& model, int n) {
  Workspace<coordinate_count_v<M>> ws(n);
  Vec<double, coordinate_count_v<M>> q = Vec<double, coordinate_count_v<M>>::Constant(n, 0.3);
  Vec<double, coordinate_count_v<M>> qd = Vec<double, coordinate_count_v<M>>::Constant(n, -0.2);
  double sink = accelerations(model, ws, q, qd, 0.0)[0];
  const long before = g_allocations.load();
  for (int i = 0; i < 200; ++i) {
    q[0] += 1e-4;
    qd[n - 1] -= 1e-4;
    sink += accelerations(model, ws, q, qd, 0.0)[0];
  }
  EXPECT_TRUE(std::isfinite(sink));
  return g_allocations.load() - before;
}

TEST(NoAllocation, LargeAndRunTimeSizedAccelerationsDoNotAllocate) {
  EXPECT_EQ(allocations_after_the_first_call(PendulumChain<20>(), 20), 0);
  EXPECT_EQ(allocations_after_the_first_call(PendulumChain<40>(), 40), 0);
  for (const int n : {3, 10, 40, 70}) {
    const test_models::RuntimeChain chain{n};
    EXPECT_EQ(allocations_after_the_first_call(chain, n), 0) << "n = " << n;
  }
  // Damping: ∂D/∂q̇ from first-order numbers, in per-thread vectors too.
  test_models::DampedRuntimeChain damped{{10}};
  damped.c = 0.3;
  EXPECT_EQ(allocations_after_the_first_call(damped, 10), 0);
}

// A model stated as text evaluates its expressions in per-thread slots,
// taken on a thread's first evaluation; its forces in a per-thread vector.
TEST(NoAllocation, TextModelAccelerationsDoNotAllocate) {
  text::Definition d;
  d.coordinates = {"a", "b"};
  d.kinetic = "0.5*(m1 + m2)*a_dot^2 + 0.5*m2*b_dot^2 + m2*a_dot*b_dot*cos(a - b)";
  d.potential = "-(m1 + m2)*g*cos(a) - m2*g*cos(b)";
  d.parameters = {{"m1", 1.0}, {"m2", 2.0}, {"g", 9.81}};
  EXPECT_EQ(allocations_after_the_first_call(text::TextModel(d), 2), 0);
  d.forces = {"-0.1*a_dot", "sin(t)"};
  d.dissipation = "0.2*b_dot^2";
  EXPECT_EQ(allocations_after_the_first_call(text::TextModel(d), 2), 0);
}

TEST(NoAllocation, ConstrainedAccelerationsDoNotAllocate) {
  const CartesianDoublePendulum model;
  Workspace<4> ws;
  ConstraintWorkspace<4, 2> cw;
  Vec<double, 4> q(0.6, -0.8, 1.4, -1.4), qd = Vec<double, 4>::Zero(), qdd;
  const long before = g_allocations.load();
  for (int i = 0; i < 100; ++i) constrained_accelerations(model, ws, cw, q, qd, 0.0, qdd);
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(qdd.allFinite());
}

/// A text model with a holonomic row (a rod of length l) and a Pfaffian
/// one (φ̇ = 0.1 ẋ), counted at run time.
text::Definition rod_and_wheel_text() {
  text::Definition d;
  d.coordinates = {"x", "y", "phi"};
  d.kinetic = "0.5*m*(x_dot^2 + y_dot^2) + 0.5*I*phi_dot^2";
  d.potential = "m*g*y";
  d.holonomic = {"sqrt(x^2 + y^2) - l"};
  d.pfaffian = {"phi_dot - 0.1*x_dot"};
  d.parameters = {{"m", 1.0}, {"I", 0.2}, {"g", 9.81}, {"l", 1.0}};
  return d;
}

// The same with a contact: its constraint rows come from per-thread
// vectors, into a workspace sized once.
TEST(NoAllocation, ConstrainedTextModelAccelerationsDoNotAllocate) {
  text::Definition d = rod_and_wheel_text();
  d.contacts = {{"floor", "y + 2*l", 0.5, "m"}};
  const text::TextModel model(d);
  Workspace<Dynamic> ws(3);
  ConstraintWorkspaceFor<text::TextModel> cw = constraint_workspace(model);
  Vec<double, Dynamic> q(3), qd(3), qdd(3);
  q << 0.6, -0.8, 0.0;
  qd << 0.8, 0.6, 0.08;
  constrained_accelerations(model, ws, cw, q, qd, 0.0, qdd, 10.0, all_active);
  const long before = g_allocations.load();
  for (int i = 0; i < 100; ++i) {
    qd[2] += 1e-4;
    constrained_accelerations(model, ws, cw, q, qd, 0.0, qdd, 10.0, all_active);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(qdd.allFinite());
  EXPECT_EQ(cw.multipliers.size(), 3);
}

// The tangent pass of a text model with run-time counted holonomic and
// Pfaffian rows (text::FixedSizeModel, the matrices of capacity
// kMaxRuntimeBilateralRows): J v along one direction and the whole J.
TEST(NoAllocation, ConstrainedTextModelTangentPassDoesNotAllocate) {
  const text::TextModel model(rod_and_wheel_text());
  const text::FixedSizeModel<3> fixed(model);
  Vec<double, 3> q(0.6, -0.8, 0.0), qd(0.8, 0.6, 0.08), qdd;
  Eigen::Matrix<double, 6, 1> v;
  v << 0.1, -0.2, 0.3, 0.05, 0.02, -0.1;
  Eigen::Matrix<double, 3, 1> jv;
  Eigen::Matrix<double, 3, 6> jacobian;
  state_jvp<1>(fixed, q, qd, 0.0, v, qdd, jv);
  state_jacobian(fixed, q, qd, 0.0, qdd, jacobian);
  const long before = g_allocations.load();
  for (int i = 0; i < 100; ++i) {
    qd[2] += 1e-4;
    state_jvp<1>(fixed, q, qd, 0.0, v, qdd, jv);
    state_jacobian(fixed, q, qd, 0.0, qdd, jacobian);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_TRUE(jacobian.allFinite());
  EXPECT_TRUE(jv.allFinite());
}

// A parameter's column while a contact rests: q̈ and its derivative along
// (δx, δp) on the seeded twin that holds the contact as the model's copy
// does (sensitivity.hpp), built on the stack at every call.
TEST(NoAllocation, ParameterDirectionThroughARestDoesNotAllocate) {
  const BallAndPlane ball(1.0, 0.1, 0.5, 9.81, {0.4, 0.0, 1.0}, 0.0);
  const lagrangian::detail::TangentModel tm = lagrangian::detail::tangent_model_of(ball, "");
  ASSERT_NE(tm.rest, nullptr);
  tm.rest(tm.model, 0, true);
  const double n[3] = {0.4 / std::sqrt(1.16), 0.0, 1.0 / std::sqrt(1.16)};
  double q[3] = {0.3, 0.1, 0.1 / n[2] - 0.3 * n[0] / n[2]}, qd[3] = {-0.5, 0.2, 0.2};
  qd[2] = -(n[0] * qd[0]) / n[2];  // along the plane
  const double v[6] = {0.1, -0.2, 0.3, 0.05, 0.02, -0.1};
  double qdd[3], jv[3];
  lagrangian::detail::evaluate_parameter_direction<BallAndPlane>(tm.model, q, qd, 0.0, v, 3, qdd, jv);
  const long before = g_allocations.load();
  for (int i = 0; i < 100; ++i) {
    q[0] += 1e-4;
    lagrangian::detail::evaluate_parameter_direction<BallAndPlane>(tm.model, q, qd, 0.0, v, 3, qdd, jv);
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  // The held motion's: no acceleration across the plane.
  EXPECT_NEAR(n[0] * qdd[0] + n[1] * qdd[1] + n[2] * qdd[2], 0.0, 1e-12);
  EXPECT_TRUE(std::isfinite(jv[0] + jv[1] + jv[2]));
}

TEST(NoAllocation, AllocationCountOfARunDoesNotGrowWithSteps) {
  // A counting check that can fail: confirm the counter sees allocations,
  // by new and (outside AddressSanitizer) by the C allocator.
  const long before = g_allocations.load();
  int* volatile probe = new int(3);  // volatile: the pair cannot be elided
  delete probe;
  ASSERT_EQ(g_allocations.load() - before, 1);
  if (LAGRANGIAN_COUNT_MALLOC) {
    const long before_c = g_allocations.load();
    void* volatile block = std::calloc(2, 1);
    std::free(block);
    ASSERT_EQ(g_allocations.load() - before_c, 1);
  }

  const DoublePendulum m;
  State<2> s;
  s.q << 1.0, 0.5;
  auto count = [&](Method method, double t_end) {
    SimulationOptions o;
    o.method = method;
    o.t_end = t_end;
    o.output_interval = -1;  // initial and final samples only
    const long start = g_allocations.load();
    const RunReport r = simulate(m, s, o);
    EXPECT_GT(r.steps, 10u);
    return g_allocations.load() - start;
  };
  // bulirsch_stoer is left out: odeint's own try_step allocates a work
  // vector on every call (bulirsch_stoer.hpp, `inv_time_vector work`), as does
  // the uBLAS-based rosenbrock4; docs/performance.md says so.
  for (const Method method : {Method::dopri5, Method::rk4, Method::cash_karp54, Method::fehlberg78, Method::gauss_radau15, Method::variational}) {
    EXPECT_EQ(count(method, 1.0), count(method, 10.0)) << method;
  }
  // A run-time sized model (a 10-link chain): the same.
  const test_models::RuntimeChain chain{10};
  State<Dynamic> c0(10);
  c0.q.setConstant(0.3);
  auto count_chain = [&](Method method, double t_end) {
    SimulationOptions o;
    o.method = method;
    o.t_end = t_end;
    o.output_interval = -1;
    const long start = g_allocations.load();
    const RunReport r = simulate(chain, c0, o);
    EXPECT_GT(r.steps, 10u);
    return g_allocations.load() - start;
  };
  // (The thread's first evaluation takes its per-thread vectors of numbers
  // and Hessian blocks: a first run is made before counting.)
  simulate(chain, c0, SimulationOptions{});
  for (const Method method : {Method::dopri5, Method::fehlberg78, Method::gauss_radau15}) {
    const long shorter = count_chain(method, 2.0);
    EXPECT_EQ(shorter, count_chain(method, 8.0)) << "run-time size, " << method;
  }
}

// Impacts resolve in the run's buffers: an elastic ball (e = 1) dropped
// 1 m onto a floor bounces every 2√(2 · 1 m / g) = 0.903 s, and four times
// the bounces cost two vectors growing twice each (they double): the event
// log, and the energy monitor's impact shifts, kept until the next sample
// (this run has none between its ends). Not an allocation per impact: the
// impulses' solver was built per impact before (16 allocations each).
TEST(NoAllocation, ImpactsDoNotAllocatePerImpact) {
  const BallAndPlane ball(1.0, 0.1, 1.0);
  State<3> s;
  s.q << 0.0, 0.0, 1.1;  // the ball's lowest point 1 m above the floor
  auto count = [&](double t_end, std::size_t impacts) {
    SimulationOptions o;
    o.t_end = t_end;
    o.output_interval = -1;
    const long start = g_allocations.load();
    const RunReport r = simulate(ball, s, o);
    const long used = g_allocations.load() - start;
    EXPECT_EQ(r.impacts, impacts) << t_end;
    return used;
  };
  const long ten = count(9.3, 10), forty = count(36.4, 40);
  EXPECT_LE(forty - ten, 4);
}

// The variational integrator's Newton solves (saddle-point systems by a
// complete orthogonal decomposition) on an orbit, and a constrained model
// with projection after every step: the workspace is allocated once.
TEST(NoAllocation, VariationalAndConstrainedRunsDoNotAllocatePerStep) {
  auto count = [](const auto& model, const auto& state, Method method, double t_end) {
    SimulationOptions o;
    o.method = method;
    o.dt = 1e-3;
    o.t_end = t_end;
    o.output_interval = -1;
    const long start = g_allocations.load();
    const RunReport r = simulate(model, state, o);
    EXPECT_GT(r.steps, 20u);
    return g_allocations.load() - start;
  };
  const KeplerPolar kepler;
  State<2> orbit;
  orbit.q << 1.0, 0.0;
  orbit.qd << 0.0, 1.2;
  EXPECT_EQ(count(kepler, orbit, Method::variational, 1.0), count(kepler, orbit, Method::variational, 4.0));

  const CartesianDoublePendulum chain;
  State<4> s;
  s.q << 0.6, -0.8, 1.4, -1.4;
  s.qd.setZero();
  for (const Method method : {Method::dopri5, Method::gauss_radau15, Method::variational}) {
    EXPECT_EQ(count(chain, s, method, 1.0), count(chain, s, method, 4.0)) << method;
  }
}

}  // namespace
