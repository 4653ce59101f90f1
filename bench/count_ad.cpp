// Instructions per q̈ evaluation, AD against hand-coded, counted with
// callgrind (scripts/count-instructions). Unlike wall time, the count does
// not move with the load on the machine. Each evaluation sits in its own
// non-inlined function so callgrind can attribute it; every input changes on
// every call so nothing can be hoisted or memoised across calls.
// Pendulum chains of n = 2, 5, 10, 20, 40 links: hand-coded (M and f by
// formula, an Eigen LLT), AD with n fixed at compile time, AD with n chosen
// at run time; and the double pendulum, hand-coded (Cramer), AD, and AD on
// the same T and V stated as text (text::TextModel, run-time size).
#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "hand_coded.hpp"
#include "lagrangian/mechanics/dynamics.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/text/text_model.hpp"
#include "runtime_chain.hpp"
#include "text_double_pendulum.hpp"

namespace {

using lagrangian::Vec;
using lagrangian::Workspace;
using lagrangian::models::DoublePendulum;
using lagrangian::models::PendulumChain;

template <int N>
__attribute__((noinline)) void chain_ad(const PendulumChain<N>& p, Workspace<N>& ws, const Vec<double, N>& q,
                                        const Vec<double, N>& qd, Vec<double, N>& out) {
  lagrangian::accelerations(p, ws, q, qd, 0.0, out);
}
template <int N>
__attribute__((noinline)) void chain_runtime(const lagrangian::test_models::RuntimeChain& p,
                                             Workspace<lagrangian::Dynamic>& ws, const Eigen::VectorXd& q,
                                             const Eigen::VectorXd& qd, Eigen::VectorXd& out) {
  if (q.size() != N) std::abort();  // (also keeps the sizes' functions apart for callgrind)
  lagrangian::accelerations(p, ws, q, qd, 0.0, out);
}
template <int N>
__attribute__((noinline)) void chain_hand(const PendulumChain<N>& p, bench::ChainHand<N>& hand,
                                          const Vec<double, N>& q, const Vec<double, N>& qd, Vec<double, N>& out) {
  hand.qdd(p, q, qd, out);
}
__attribute__((noinline)) void double_pendulum_ad(const DoublePendulum& p, Workspace<2>& ws, const Vec<double, 2>& q,
                                                  const Vec<double, 2>& qd, Vec<double, 2>& out) {
  lagrangian::accelerations(p, ws, q, qd, 0.0, out);
}
__attribute__((noinline)) void double_pendulum_as_text(const lagrangian::text::TextModel& p,
                                                       Workspace<lagrangian::Dynamic>& ws, const Eigen::VectorXd& q,
                                                       const Eigen::VectorXd& qd, Eigen::VectorXd& out) {
  lagrangian::accelerations(p, ws, q, qd, 0.0, out);
}
__attribute__((noinline)) void double_pendulum_hand(const DoublePendulum& p, const Vec<double, 2>& q,
                                                    const Vec<double, 2>& qd, Vec<double, 2>& out) {
  bench::double_pendulum_qdd(p, q.data(), qd.data(), out.data());
}

/// Runs the three chain evaluations `calls` times each; returns the largest
/// relative difference of the AD results from the hand-coded one.
template <int N>
double chains(int calls) {
  const PendulumChain<N> chain;
  const lagrangian::test_models::RuntimeChain runtime{N};
  Workspace<N> ws;
  Workspace<lagrangian::Dynamic> wsx(N);
  bench::ChainHand<N> hand;
  Vec<double, N> q = Vec<double, N>::LinSpaced(N, 0.1, 0.9), qd = Vec<double, N>::LinSpaced(N, -0.5, 0.5), a, b;
  Eigen::VectorXd qx(N), qdx(N), c(N);
  double worst = 0;
  for (int i = 0; i < calls; ++i) {
    q.array() += 1e-9;
    qd[0] += 1e-9;
    qx = q;
    qdx = qd;
    chain_ad<N>(chain, ws, q, qd, a);
    chain_runtime<N>(runtime, wsx, qx, qdx, c);
    chain_hand<N>(chain, hand, q, qd, b);
    worst = std::max({worst, (a - b).norm() / b.norm(), (c - Eigen::VectorXd(b)).norm() / b.norm()});
  }
  return worst;
}

}  // namespace

int main(int argc, char** argv) {
  const int calls = argc > 1 ? std::atoi(argv[1]) : 1000;
  const DoublePendulum dp;
  Workspace<2> ws2;
  Vec<double, 2> q2(0.7, -0.4), qd2(1.1, 0.3), a2, b2;
  const lagrangian::text::TextModel text(bench::double_pendulum_text(dp));
  Workspace<lagrangian::Dynamic> wst(2);
  Eigen::VectorXd qt(2), qdt(2), ct(2);
  double worst = 0;  // AD and hand-coded must agree, or the count means nothing
  for (int i = 0; i < calls; ++i) {
    q2[0] += 1e-9;
    q2[1] -= 1e-9;
    qd2[0] += 1e-9;
    qt = q2;
    qdt = qd2;
    double_pendulum_ad(dp, ws2, q2, qd2, a2);
    double_pendulum_as_text(text, wst, qt, qdt, ct);
    double_pendulum_hand(dp, q2, qd2, b2);
    worst = std::max({worst, (a2 - b2).norm() / b2.norm(), (ct - Eigen::VectorXd(b2)).norm() / b2.norm()});
  }
  worst = std::max({worst, chains<2>(calls), chains<5>(calls), chains<10>(calls), chains<20>(calls),
                    chains<40>(calls)});
  std::printf("%d calls each; largest relative difference AD vs hand-coded: %.1e\n", calls, worst);
  return worst < 1e-12 ? 0 : 1;
}
