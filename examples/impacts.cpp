// Impacts: a ball bouncing to rest on a floor (a Zeno accumulation), and
// Newton's cradle. Writes the bouncing ball's trajectory and event log.
// Usage: impacts [OUTPUT_DIR]   (default: no files)
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "example_checks.hpp"
#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/impacts.hpp"

using namespace lagrangian;
using namespace lagrangian::models;

using example::check;

int main(int argc, char** argv) try {
  const std::string out = argc > 1 ? argv[1] : "";

  // 1. A ball (m = 0.2 kg, R = 5 cm) dropped from 1 m onto a floor, e = 0.5.
  //    Impact k happens at t_k = t_1 + 2 v_1 (e + … + e^(k−1)) / g; the
  //    bounces accumulate at t∞ = t_1 + 2 v_1 e / (g (1 − e)), where the
  //    simulator switches to resting contact and carries on.
  const double m = 0.2, R = 0.05, e = 0.5, g = 9.81, h = 1.0;
  const BallAndPlane ball(m, R, e, g);
  State<3> x0;
  x0.q << 0.0, 0.0, h + R;
  x0.qd << 0.3, 0.0, 0.0;  // drifting sideways at 0.3 m/s: the floor is smooth, so it keeps that
  SimulationOptions opt;
  opt.t_end = 5.0;
  opt.output_interval = 0.01;
  Recorder<3> rec;
  RunReport report;
  if (out.empty()) {
    report = simulate(ball, x0, opt, rec);
  } else {
    CsvSink csv(out + "/bouncing_ball.csv");
    report = simulate(ball, x0, opt, [&](const Sample<3>& s) {
      rec(s);
      csv(s);
    });
    csv.finish();
    report.write_events_csv(out + "/bouncing_ball_events.csv");
    report.write_json(out + "/bouncing_ball_report.json");
  }
  std::cout << "bouncing ball\n" << report.summary();
  const double t1 = std::sqrt(2 * h / g), v1 = std::sqrt(2 * g * h);
  const double t_inf = t1 + 2 * v1 * e / (g * (1 - e));
  double worst = 0, t_k = t1, v_k = v1;
  for (int k = 0; k < 10; ++k) {
    worst = std::max(worst, std::abs(report.events[static_cast<std::size_t>(k)].t - t_k));
    v_k *= e;
    t_k += 2 * v_k / g;
  }
  std::printf("  first impact at %.15f s (sqrt(2h/g) = %.15f s)\n", report.events[0].t, t1);
  std::printf("  first 10 impact times vs the geometric series: max |error| %.2e s\n", worst);
  std::printf("  accumulation point t_inf = %.9f s; rest event at %.9f s\n", t_inf, report.events.back().t);
  const auto& end = rec.samples.back();
  check(std::abs(report.events[0].t - t1) < 1e-12, "first impact at sqrt(2h/g) to 1e-12 s");
  check(worst < 1e-11, "impact times follow the geometric series");
  check(report.events.back().kind == EventKind::rest && std::abs(report.events.back().t - t_inf) < 1e-5,
        "resting contact from the accumulation point on");
  check(std::abs(end.q[2] - R) < 1e-12 && std::abs(end.qd[2]) < 1e-12 && std::abs(end.qd[0] - 0.3) < 1e-12,
        "at rest on the floor at t_end, still sliding at 0.3 m/s");
  check(std::abs(report.impact_energy_loss - m * g * h) < 1e-9, "the impacts took exactly m g h");

  // 2. Newton's cradle: five equal steel balls, four touching in a row, the
  //    fifth arriving at 1 m/s. Simultaneous contacts are resolved pairwise in
  //    sequence, which passes the momentum down the row.
  const double r = 0.0125, mb = 0.066;
  const SpheresOnLine<5> cradle({mb, mb, mb, mb, mb}, {r, r, r, r, r}, 1.0);
  State<5> c0;
  c0.q << -0.1, 2 * r, 4 * r, 6 * r, 8 * r;
  c0.qd << 1.0, 0, 0, 0, 0;
  SimulationOptions copt;
  copt.t_end = 0.5;
  copt.output_interval = -1;
  Recorder<5> crec;
  const RunReport cr = simulate(cradle, c0, copt, crec);
  std::cout << "\nNewton's cradle\n" << cr.summary();
  const auto& ce = crec.samples.back();
  std::printf("  velocities at t_end: %.3g %.3g %.3g %.3g %.3g m/s\n", ce.qd[0], ce.qd[1], ce.qd[2], ce.qd[3],
              ce.qd[4]);
  check(std::abs(ce.qd[4] - 1.0) < 1e-14 && ce.qd.head<4>().cwiseAbs().maxCoeff() < 1e-14,
        "the last ball leaves with the first ball's velocity, the others stay");
  check(std::abs(mb * ce.qd.sum() - mb) < 1e-15 && std::abs(ce.total_energy - 0.5 * mb) < 1e-15,
        "momentum and energy conserved");

  return example::finish();
} catch (const std::exception& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 2;
}
