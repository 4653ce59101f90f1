// A projectile over flat ground and on an inclined plane (course notes 1.5):
// simulated landing against T and R, and the best elevation found by NLopt.
// Usage: projectile [OUTPUT_DIR]   (writes the flat-ground trajectory, events and report)
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "example_checks.hpp"
#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/projectile_aim.hpp"

using namespace lagrangian;
using namespace lagrangian::models;

using example::check;

int main(int argc, char** argv) try {
  const std::string out = argc > 1 ? argv[1] : "";
  const double deg = std::acos(-1.0) / 180, u = 20.0, alpha = 40 * deg, g = 9.81;
  SimulationOptions opt;
  opt.t_end = 100.0;  // the landing event ends the run
  opt.rtol = 1e-12;
  opt.atol = 1e-14;
  opt.output_interval = 0.01;

  // 1. Flat ground.
  const Projectile<> flat(0.145, g);  // a baseball
  Recorder<2> rec;
  RunReport r;
  if (out.empty()) {
    r = simulate(flat, flat.launch(u, alpha), opt, rec);
  } else {
    CsvSink csv(out + "/projectile.csv");
    r = simulate(flat, flat.launch(u, alpha), opt, [&](const Sample<2>& s) {
      rec(s);
      csv(s);
    });
    csv.finish();
    r.write_events_csv(out + "/projectile_events.csv");
    r.write_json(out + "/projectile_report.json");
  }
  std::cout << "flat ground, u = 20 m/s at 40 deg\n" << r.summary();
  const auto& land = rec.samples.back();
  std::printf("  landed at t = %.12f s, x = %.12f m; T = 2u sin(a)/g = %.12f s, R = u^2 sin(2a)/g = %.12f m\n",
              r.stopped_at, land.q[0], flat.flight_time(u, alpha), flat.range(u, alpha));
  check(std::abs(r.stopped_at - flat.flight_time(u, alpha)) < 1e-11, "time of flight");
  check(std::abs(land.q[0] - flat.range(u, alpha)) < 1e-10, "range");
  check(std::abs(r.events[0].t - u * std::sin(alpha) / g) < 1e-12, "apex at u sin(a)/g");

  // 2. Up and down a 20-degree slope.
  for (double beta : {20 * deg, -20 * deg}) {
    const Projectile<> slope(0.145, g, beta);
    Recorder<2> srec;
    const RunReport sr = simulate(slope, slope.launch(u, alpha), opt, srec);
    const double along = std::hypot(srec.samples.back().q[0], srec.samples.back().q[1]);
    std::printf("\n%s a 20 deg slope: T = %.12f s (closed form %.12f), range %.12f m (closed form %.12f)\n",
                beta > 0 ? "up" : "down", sr.stopped_at, slope.flight_time(u, alpha), along,
                slope.range(u, alpha));
    check(std::abs(sr.stopped_at - slope.flight_time(u, alpha)) < 1e-11 &&
              std::abs(along - slope.range(u, alpha)) < 1e-10,
          "landing on the slope where 1.5.1 and 1.5.2 say");
    const Aim best = best_elevation(slope, u, opt);
    std::printf("  NLopt: best elevation %.6f deg (pi/4 + beta/2 = %.6f deg), range %.9f m (u^2/(g(1+sin b)) = %.9f)\n",
                best.alpha / deg, slope.best_elevation() / deg, best.value, slope.max_range(u));
    check(std::abs(best.alpha - slope.best_elevation()) < 1e-6, "best elevation pi/4 + beta/2");
  }
  return example::finish();
} catch (const std::exception& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 2;
}
