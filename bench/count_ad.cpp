// Instructions per q̈ evaluation, AD against hand-coded, counted with
// callgrind (scripts/count-instructions). Unlike wall time, the count does
// not move with the load on the machine. Each evaluation sits in its own
// non-inlined function so callgrind can attribute it; every input changes on
// every call so nothing can be hoisted or memoised across calls.
#include <cstdio>
#include <cstdlib>

#include "hand_coded.hpp"
#include "lagrangian/dynamics.hpp"
#include "lagrangian/models/pendulums.hpp"

namespace {

using lagrangian::Vec;
using lagrangian::Workspace;
using lagrangian::models::DoublePendulum;
using lagrangian::models::PendulumChain;

__attribute__((noinline)) void chain10_ad(const PendulumChain<10>& p, Workspace<10>& ws, const Vec<double, 10>& q,
                                          const Vec<double, 10>& qd, Vec<double, 10>& out) {
  lagrangian::accelerations(p, ws, q, qd, 0.0, out);
}
__attribute__((noinline)) void chain10_hand(const PendulumChain<10>& p, bench::ChainHand<10>& hand,
                                            const Vec<double, 10>& q, const Vec<double, 10>& qd,
                                            Vec<double, 10>& out) {
  hand.qdd(p, q, qd, out);
}
__attribute__((noinline)) void double_pendulum_ad(const DoublePendulum& p, Workspace<2>& ws, const Vec<double, 2>& q,
                                                  const Vec<double, 2>& qd, Vec<double, 2>& out) {
  lagrangian::accelerations(p, ws, q, qd, 0.0, out);
}
__attribute__((noinline)) void double_pendulum_hand(const DoublePendulum& p, const Vec<double, 2>& q,
                                                    const Vec<double, 2>& qd, Vec<double, 2>& out) {
  bench::double_pendulum_qdd(p, q.data(), qd.data(), out.data());
}

}  // namespace

int main(int argc, char** argv) {
  const int calls = argc > 1 ? std::atoi(argv[1]) : 1000;
  const PendulumChain<10> chain;
  Workspace<10> ws10;
  bench::ChainHand<10> hand10;
  Vec<double, 10> q = Vec<double, 10>::LinSpaced(0.1, 0.9), qd = Vec<double, 10>::LinSpaced(-0.5, 0.5), a, b;
  const DoublePendulum dp;
  Workspace<2> ws2;
  Vec<double, 2> q2(0.7, -0.4), qd2(1.1, 0.3), a2, b2;
  double worst = 0;  // AD and hand-coded must agree, or the count means nothing
  for (int i = 0; i < calls; ++i) {
    q.array() += 1e-9;
    qd[0] += 1e-9;
    chain10_ad(chain, ws10, q, qd, a);
    chain10_hand(chain, hand10, q, qd, b);
    q2[0] += 1e-9;
    q2[1] -= 1e-9;
    qd2[0] += 1e-9;
    double_pendulum_ad(dp, ws2, q2, qd2, a2);
    double_pendulum_hand(dp, q2, qd2, b2);
    worst = std::max({worst, (a - b).norm() / b.norm(), (a2 - b2).norm() / b2.norm()});
  }
  std::printf("%d calls each; largest relative difference AD vs hand-coded: %.1e\n", calls, worst);
  return worst < 1e-12 ? 0 : 1;
}
