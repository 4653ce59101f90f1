// Impacts that cycle, replaced by their limit (integrate/detail/impact_cycle.hpp):
// the round detection, the limit against the closed form and against
// iterating the round until it settles, and a light sphere pinned between a
// heavy one and a wall at mass ratio 1e-9, which the sequential rule alone
// would need ~1e9 pairwise impacts to settle.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "lagrangian/integrate/detail/impact_cycle.hpp"
#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/impacts.hpp"

namespace {

using namespace lagrangian;
using detail::ImpactCycle;

TEST(ImpactCycle, FindsTheRoundThatRepeats) {
  ImpactCycle c;
  c.record(3, 1.0);  // a different first impact
  for (int k = 0; k < 4; ++k) {
    c.record(1, 1.0);
    c.record(8, 0.0);
  }
  const auto round = c.round(4, 100);
  ASSERT_EQ(round.size(), 2u);
  EXPECT_EQ(round[0].contact, 1);
  EXPECT_EQ(round[1].contact, 8);
  EXPECT_EQ(round[1].e, 0.0);
  ImpactCycle irregular;  // no period: the latest window once twice as long is recorded
  for (int k = 0; k < 8; ++k) irregular.record(k % 3 == 0 ? 2 : k % 2, 1.0);
  EXPECT_TRUE(irregular.round(2, 5).empty());
  for (int k = 0; k < 4; ++k) irregular.record(k, 1.0);
  EXPECT_EQ(irregular.round(2, 5).size(), 5u);
}

/// One round on a line: a light sphere (mass m, velocity v[0], towards the
/// wall positive) bounces off the wall (e = 1), then meets the heavy one
/// (M, v[1]) plastically; each sphere also slides along the wall (v[2],
/// v[3]), which neither impact touches.
void round_on_a_line(double m, double M, const double* in, double* out) {
  const double light = -in[0];                       // the wall reverses it
  const double common = (m * light + M * in[1]) / (m + M);  // plastic: one velocity
  out[0] = common;
  out[1] = common;
  out[2] = in[2];
  out[3] = in[3];
}

TEST(ImpactCycle, TheLimitIsTheClosedFormAndWhatIteratingReaches) {
  // Each round multiplies the normal velocity by (M − m)/(M + m) and leaves
  // the sliding untouched: the limit stops both normal velocities and keeps
  // the tangential ones, at any mass ratio.
  for (const double m : {1e-9, 1e-3, 0.5}) {
    const double M = 1.0;
    const std::array<double, 4> v{0.8, 0.8, 0.3, -0.2};
    auto round = [&](const double* in, double* out) { round_on_a_line(m, M, in, out); };
    std::array<double, 4> limit{};
    ASSERT_TRUE(detail::round_limit(4, v.data(), detail::round_map(round), limit.data())) << "m = " << m;
    EXPECT_NEAR(limit[0], 0.0, 1e-6) << "m = " << m;  // conditioning: ε M/(2m)
    EXPECT_NEAR(limit[1], 0.0, 1e-6) << "m = " << m;
    EXPECT_NEAR(limit[2], 0.3, 1e-12) << "m = " << m;
    EXPECT_NEAR(limit[3], -0.2, 1e-12) << "m = " << m;
    if (m >= 1e-3) {
      // The rounds themselves: 1e5 of them leave (1 − 2e-3)^1e5 = e^-200.
      std::array<double, 4> it = v, next{};
      for (int k = 0; k < 100000; ++k) {
        round(it.data(), next.data());
        it = next;
      }
      for (int i = 0; i < 4; ++i) EXPECT_NEAR(limit[static_cast<std::size_t>(i)], it[static_cast<std::size_t>(i)], 1e-12);
    }
  }
}

TEST(ImpactCycle, ARoundThatOnlyReflectsHasNoLimit) {
  // Two elastic walls and nothing else: the velocity flips forever.
  auto reflect = [](const double* in, double* out) { out[0] = -in[0]; };
  const double v = 0.7;
  double out = 0;
  EXPECT_FALSE(detail::round_limit(1, &v, detail::round_map(reflect), &out));
  EXPECT_EQ(out, 0.0);
}

TEST(ImpactCycle, APartThatTurnsKeepsTheRoundFromSettling) {
  // Velocities 0 and 1 turn by a quarter turn each round (|λ| = 1, λ = ±i),
  // velocity 2 halves, velocity 3 is kept: C^k v has no limit.
  auto turn = [](const double* in, double* out) {
    out[0] = -in[1];
    out[1] = in[0];
    out[2] = 0.5 * in[2];
    out[3] = in[3];
  };
  const std::array<double, 4> v{0.3, 0.1, 0.8, -0.4};
  std::array<double, 4> out{};
  EXPECT_FALSE(detail::round_limit(4, v.data(), detail::round_map(turn), out.data()));
  // Without the turning part the same round settles: velocity 2 to 0, 3 kept.
  auto damp = [](const double* in, double* out) {
    out[0] = in[0];
    out[1] = in[1];
    out[2] = 0.5 * in[2] + 0.25 * in[3];
    out[3] = in[3];
  };
  ASSERT_TRUE(detail::round_limit(4, v.data(), detail::round_map(damp), out.data()));
  // x ← x/2 + w/4 with w fixed tends to w/2.
  EXPECT_NEAR(out[2], -0.2, 1e-15);
  EXPECT_EQ(out[3], -0.4);
  EXPECT_EQ(out[0], 0.3);  // untouched by the round: copied
  EXPECT_EQ(out[1], 0.1);
}

TEST(ImpactCycle, APinnedLightSphereStopsTheHeavyOneAtTheWall) {
  // A sphere of mass 1e-9 kg rests against the left wall of a 1 m box; one of
  // 1 kg arrives along the line of centres at 1 m/s. Walls elastic, the pair
  // plastic: by the sequential rule the pair's velocity shrinks by
  // (M − m)/(M + m) per round of two impacts, so the limit is both at rest
  // against the wall, all ½ M v² taken by the impacts, the wall's impulse M v.
  // A third sphere rests in a far corner, out of the way (the library's
  // three-sphere box).
  const double m = 1e-9, M = 1.0, v = 1.0, R = 0.1, r = 0.07;
  const models::SpheresInBox<3> box({m, M, 1.0}, {R, r, 0.05}, 1.0, 1.0, 1.0, 0.0);
  State<6> s;
  s.q << R, 0.5, 0.6, 0.5, 0.85, 0.85;
  s.qd << 0.0, 0.0, -v, 0.0, 0.0, 0.0;
  SimulationOptions o;
  o.t_end = 1.0;
  Recorder<6> rec;
  const RunReport rep = simulate(box, s, o, rec);
  const auto& end = rec.samples.back();
  EXPECT_EQ(rep.t_final, 1.0);
  EXPECT_NEAR(end.qd[0], 0.0, 1e-9);
  EXPECT_NEAR(end.qd[2], 0.0, 1e-9);
  EXPECT_NEAR(end.q[0], R, 1e-9);
  EXPECT_NEAR(end.q[2], 2 * R + r, 1e-9);  // touching its neighbour, which touches the wall
  EXPECT_EQ(end.q[4], 0.85);
  EXPECT_EQ(end.qd[4], 0.0);
  EXPECT_NEAR(rep.impact_energy_loss, 0.5 * M * v * v, 1e-9);
  double wall = 0;
  for (const EventRecord& e : rep.events)
    if (e.kind == EventKind::impact && e.name == "s1-left") wall += e.impulse;
  EXPECT_NEAR(wall, M * v, 1e-6);
  EXPECT_LT(rep.impacts, 20u);  // the accumulation is one entry per contact, not 1e9
}

}  // namespace
