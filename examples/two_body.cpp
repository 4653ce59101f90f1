// The two-body problem and its reduced mass (course notes 1.6): a binary
// star integrated as two bodies and as one body of reduced mass, checked
// against Kepler's orbit; and the reduced mass of hydrogen.
// Usage: two_body [OUTPUT_DIR]   (writes the binary's trajectory and report)
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "example_checks.hpp"
#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/two_body.hpp"

using namespace lagrangian;
using namespace lagrangian::models;

using example::check;

int main(int argc, char** argv) try {
  const std::string out = argc > 1 ? argv[1] : "";
  // Two stars of 2 and 1 solar masses, semi-major axis 1 au, eccentricity 0.6.
  const double G = 6.6743e-11, msun = 1.98847e30, au = 1.495978707e11;
  const double m1 = 2 * msun, m2 = msun;
  const KeplerOrbit orbit(au, 0.6, G * (m1 + m2));
  const auto pair = gravitational_two_body<3>(m1, m2, G);
  const auto reduced = gravitational_relative_motion<3>(m1, m2, G);

  // Start at periapsis, centre of mass at rest at the origin.
  const auto s = orbit.state(0.0);
  const double f1 = m2 / (m1 + m2), f2 = m1 / (m1 + m2);
  State<6> x0;
  x0.q << -f1 * s[0], -f1 * s[1], 0, f2 * s[0], f2 * s[1], 0;
  x0.qd << -f1 * s[2], -f1 * s[3], 0, f2 * s[2], f2 * s[3], 0;
  State<3> r0;
  r0.q << s[0], s[1], 0;
  r0.qd << s[2], s[3], 0;

  SimulationOptions opt;
  opt.method = Method::fehlberg78;
  opt.t_end = 20 * orbit.period();
  opt.rtol = 1e-13;
  opt.atol = 1e-3;  // m and m/s: 1 mm on an orbit of 1.5e11 m
  opt.output_interval = orbit.period() / 50;
  Recorder<6> two;
  Recorder<3> one;
  RunReport report;
  if (out.empty()) {
    report = simulate(pair, x0, opt, two);
  } else {
    CsvSink csv(out + "/two_body.csv");
    report = simulate(pair, x0, opt, [&](const Sample<6>& x) {
      two(x);
      csv(x);
    });
    csv.finish();
    report.write_json(out + "/two_body_report.json");
  }
  const RunReport rr = simulate(reduced, r0, opt, one);
  std::cout << "binary star, two bodies\n" << report.summary() << "\nthe same, one body of reduced mass\n"
            << rr.summary();

  double dev = 0, kepler = 0, com = 0;
  for (std::size_t k = 0; k < two.samples.size() && k < one.samples.size(); ++k) {
    const auto& a = two.samples[k];
    const auto& b = one.samples[k];
    const Vec<double, 3> rel = a.q.tail<3>() - a.q.head<3>();
    dev = std::max(dev, (rel - b.q - (a.t - b.t) * b.qd).norm() / au);
    const auto ref = orbit.state(b.t);
    kepler = std::max(kepler, std::hypot(b.q[0] - ref[0], b.q[1] - ref[1]) / au);
    com = std::max(com, (m1 * a.q.head<3>() + m2 * a.q.tail<3>()).norm() / (m1 + m2) / au);
  }
  double period = 0;
  if (rr.events.size() >= 2) period = (rr.events.back().t - rr.events.front().t) / double(rr.events.size() - 1);
  std::printf("\n20 orbits of P = %.6f days:\n", orbit.period() / 86400);
  std::printf("  relative motion, two-body vs reduced mass: max %.2e au\n", dev);
  std::printf("  reduced mass vs Kepler's equation:        max %.2e au\n", kepler);
  std::printf("  centre of mass drift:                      max %.2e au\n", com);
  std::printf("  period from %zu periapsis passages: %.9f days (2 pi sqrt(a^3/GM): %.9f)\n", rr.events.size(),
              period / 86400, orbit.period() / 86400);
  check(dev < 1e-9, "the relative motion of the two bodies is the reduced-mass motion");
  check(kepler < 1e-8, "the orbit is Kepler's");
  check(com < 1e-10, "the centre of mass stays at rest");
  check(std::abs(period - orbit.period()) < 1e-9 * orbit.period(), "Kepler's third law");

  // Hydrogen (CODATA 2018): μ = m_e m_p / (m_e + m_p) ≈ m_e (1 − m_e/m_p).
  const double mu = reduced_mass(electron_mass, proton_mass);
  const double approx = electron_mass * (1 - electron_mass / proton_mass);
  std::printf("\nhydrogen: mu = %.10e kg = %.8f m_e; m_e (1 - m_e/m_p) = %.10e kg (relative error %.2e)\n", mu,
              mu / electron_mass, approx, (mu - approx) / mu);
  check(std::abs((mu - approx) / mu - 2.97e-7) < 1e-9, "the approximation is good to (m_e/m_p)^2 = 3e-7");

  return example::finish();
} catch (const std::exception& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 2;
}
