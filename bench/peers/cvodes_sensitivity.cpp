// Forward sensitivities to the initial conditions, Φ = ∂x(5 s)/∂x(0), of
// the double pendulum (1.3 and 0.8 kg, 1.1 and 0.7 m, from (1.2, −0.4) rad,
// (0.3, 0.8) rad/s) by SUNDIALS CVODES and by lagrangian's sensitivities(),
// over a ladder of tolerances: each run's wall time and its error, the
// largest |Φ − Φ_ref| over the largest |Φ_ref|, against lagrangian's Φ by
// dopri5 at rtol 1e-13 (checked against fehlberg78 at the same tolerance),
// so the two can be compared at equal accuracy.
//
// CVODES side: Adams–Moulton with Newton iterations on a dense linear
// solver, the right-hand side, its Jacobian and the sensitivity right-hand
// side J s written by hand below, the sensitivities in the error control
// (CV_STAGGERED and CV_SIMULTANEOUS both timed). lagrangian side: dopri5,
// J s by automatic differentiation. atol = rtol / 100 on both sides.
// Built and run by bench/peers/run_cvodes.sh (docs/performance.md).
#include <cvodes/cvodes.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include <Eigen/Core>

#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/analysis/tangent_flow.hpp"
#include "lagrangian/models/pendulums.hpp"

#include "../hand_coded.hpp"

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kM1 = 1.3, kM2 = 0.8, kL1 = 1.1, kL2 = 0.7, kG = 9.81, kTEnd = 5.0;
const double kStart[4] = {1.2, -0.4, 0.3, 0.8};

/// The double pendulum by hand (bench/hand_coded.hpp): ẋ = f(x) and, with
/// jac, F = ∂f/∂x (row-major 4 × 4).
struct Hand {
  lagrangian::models::DoublePendulum p{kM1, kM2, kL1, kL2, kG};
  void rhs(const double* x, double* f, double* jac = nullptr) const {
    f[0] = x[2];
    f[1] = x[3];
    double dq[8];
    bench::double_pendulum_qdd(p, x, x + 2, f + 2, jac == nullptr ? nullptr : dq);
    if (jac == nullptr) return;
    for (int j = 0; j < 4; ++j) {
      jac[0 * 4 + j] = j == 2 ? 1.0 : 0.0;
      jac[1 * 4 + j] = j == 3 ? 1.0 : 0.0;
      jac[2 * 4 + j] = dq[j];
      jac[3 * 4 + j] = dq[4 + j];
    }
  }
};

int f_cb(sunrealtype, N_Vector y, N_Vector ydot, void* data) {
  static_cast<const Hand*>(data)->rhs(N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
  return 0;
}

int jac_cb(sunrealtype, N_Vector y, N_Vector, SUNMatrix J, void* data, N_Vector, N_Vector, N_Vector) {
  double f[4], jac[16];
  static_cast<const Hand*>(data)->rhs(N_VGetArrayPointer(y), f, jac);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) SM_ELEMENT_D(J, i, j) = jac[i * 4 + j];
  return 0;
}

int sens_cb(int ns, sunrealtype, N_Vector y, N_Vector, N_Vector* yS, N_Vector* ySdot, void* data, N_Vector,
            N_Vector) {
  double f[4], jac[16];
  static_cast<const Hand*>(data)->rhs(N_VGetArrayPointer(y), f, jac);
  for (int k = 0; k < ns; ++k) {
    const double* s = N_VGetArrayPointer(yS[k]);
    double* out = N_VGetArrayPointer(ySdot[k]);
    for (int i = 0; i < 4; ++i) out[i] = jac[i * 4 + 0] * s[0] + jac[i * 4 + 1] * s[1] + jac[i * 4 + 2] * s[2] +
                                        jac[i * 4 + 3] * s[3];
  }
  return 0;
}

void check(int flag, const char* what) {
  if (flag < 0) throw std::runtime_error(std::string("CVODES: ") + what + " failed with flag " + std::to_string(flag));
}

struct Result {
  Eigen::Matrix4d phi;
  double seconds = 0;
  long steps = 0;
};

/// Φ(5 s) by CVODES at (rtol, rtol / 100), sensitivities by `method`.
Result cvodes_phi(double rtol, int method) {
  Hand hand;
  SUNContext ctx = nullptr;
  check(SUNContext_Create(nullptr, &ctx), "SUNContext_Create");
  const auto start = Clock::now();
  N_Vector y = N_VNew_Serial(4, ctx);
  for (int i = 0; i < 4; ++i) NV_Ith_S(y, i) = kStart[i];
  void* mem = CVodeCreate(CV_ADAMS, ctx);
  check(CVodeInit(mem, f_cb, 0.0, y), "CVodeInit");
  check(CVodeSStolerances(mem, rtol, rtol / 100), "CVodeSStolerances");
  check(CVodeSetUserData(mem, &hand), "CVodeSetUserData");
  check(CVodeSetMaxNumSteps(mem, 1000000), "CVodeSetMaxNumSteps");
  SUNMatrix A = SUNDenseMatrix(4, 4, ctx);
  SUNLinearSolver ls = SUNLinSol_Dense(y, A, ctx);
  check(CVodeSetLinearSolver(mem, ls, A), "CVodeSetLinearSolver");
  check(CVodeSetJacFn(mem, jac_cb), "CVodeSetJacFn");
  N_Vector* yS = N_VCloneVectorArray(4, y);
  for (int k = 0; k < 4; ++k) {
    N_VConst(0.0, yS[k]);
    NV_Ith_S(yS[k], k) = 1.0;
  }
  check(CVodeSensInit(mem, 4, method, sens_cb, yS), "CVodeSensInit");
  check(CVodeSensEEtolerances(mem), "CVodeSensEEtolerances");
  check(CVodeSetSensErrCon(mem, SUNTRUE), "CVodeSetSensErrCon");
  sunrealtype t = 0;
  check(CVode(mem, kTEnd, y, &t, CV_NORMAL), "CVode");
  check(CVodeGetSens(mem, &t, yS), "CVodeGetSens");
  Result r;
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < 4; ++i) r.phi(i, k) = NV_Ith_S(yS[k], i);
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  check(CVodeGetNumSteps(mem, &r.steps), "CVodeGetNumSteps");
  N_VDestroyVectorArray(yS, 4);
  SUNLinSolFree(ls);
  SUNMatDestroy(A);
  N_VDestroy(y);
  CVodeFree(&mem);
  SUNContext_Free(&ctx);
  return r;
}

/// Φ(5 s) by lagrangian's sensitivities(), `method` (dopri5 unless said)
/// at (rtol, rtol / 100).
Result lagrangian_phi(double rtol, lagrangian::Method method = lagrangian::Method::dopri5) {
  const lagrangian::models::DoublePendulum dp(kM1, kM2, kL1, kL2, kG);
  lagrangian::State<2> s;
  s.q << kStart[0], kStart[1];
  s.qd << kStart[2], kStart[3];
  lagrangian::SensitivityOptions o;
  o.run.t_end = kTEnd;
  o.run.rtol = rtol;
  o.run.atol = rtol / 100;
  o.run.output_interval = -1;
  o.run.method = method;
  const auto start = Clock::now();
  const lagrangian::SensitivityResult res = lagrangian::sensitivities(dp, s, o);
  Result r;
  r.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  r.phi = res.sensitivities.back();
  r.steps = static_cast<long>(res.steps);
  return r;
}

double error_of(const Eigen::Matrix4d& phi, const Eigen::Matrix4d& ref) {
  return (phi - ref).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff();
}

/// The fastest of `repeats` runs (the machine's noise only adds time).
template <class F>
Result best_of(int repeats, F&& run) {
  Result best = run();
  for (int k = 1; k < repeats; ++k) {
    const Result r = run();
    if (r.seconds < best.seconds) best = r;
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 5;
  // The hand-written Jacobian against the library's AD one at the start.
  {
    const lagrangian::models::DoublePendulum dp(kM1, kM2, kL1, kL2, kG);
    lagrangian::Vec<double, 2> q(kStart[0], kStart[1]), qd(kStart[2], kStart[3]), qdd;
    Eigen::Matrix<double, 2, 4> ad;
    lagrangian::state_jacobian(dp, q, qd, 0.0, qdd, ad);
    double f[4], jac[16];
    Hand().rhs(kStart, f, jac);
    double worst = std::max(std::abs(f[2] - qdd[0]), std::abs(f[3] - qdd[1]));
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 4; ++j) worst = std::max(worst, std::abs(jac[(2 + i) * 4 + j] - ad(i, j)));
    std::printf("hand-written q'' and Jacobian against the AD ones: largest difference %.1e\n", worst);
    if (!(worst < 1e-12)) {
      std::fprintf(stderr, "the hand-written Jacobian disagrees with the AD one\n");
      return 1;
    }
  }
  const Eigen::Matrix4d ref = lagrangian_phi(1e-13).phi;
  const double other = error_of(lagrangian_phi(1e-13, lagrangian::Method::fehlberg78).phi, ref);
  const double cross = error_of(cvodes_phi(1e-12, CV_SIMULTANEOUS).phi, ref);
  std::printf("reference: lagrangian, dopri5 at rtol 1e-13; fehlberg78 at 1e-13 differs from it by %.1e, CVODES "
              "at 1e-12 by %.1e\n",
              other, cross);
  if (!(other < 1e-10)) {
    std::fprintf(stderr, "the reference is not converged\n");
    return 1;
  }
  std::printf("%-8s %-28s %12s %10s %10s\n", "rtol", "solver", "seconds", "steps", "error");
  for (double rtol : {1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11}) {
    const Result ours = best_of(repeats, [&] { return lagrangian_phi(rtol); });
    const Result stag = best_of(repeats, [&] { return cvodes_phi(rtol, CV_STAGGERED); });
    const Result simu = best_of(repeats, [&] { return cvodes_phi(rtol, CV_SIMULTANEOUS); });
    std::printf("%-8.0e %-28s %12.6f %10ld %10.2e\n", rtol, "lagrangian dopri5 (AD J s)", ours.seconds, ours.steps,
                error_of(ours.phi, ref));
    std::printf("%-8.0e %-28s %12.6f %10ld %10.2e\n", rtol, "CVODES Adams, staggered", stag.seconds, stag.steps,
                error_of(stag.phi, ref));
    std::printf("%-8.0e %-28s %12.6f %10ld %10.2e\n", rtol, "CVODES Adams, simultaneous", simu.seconds, simu.steps,
                error_of(simu.phi, ref));
  }
}
