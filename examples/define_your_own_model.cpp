// Define your own model: a double pendulum in about thirty lines.
// Usage: define_your_own_model [OUTPUT_DIR]   (writes trajectory.csv, report.json)
#include <cmath>
#include <iostream>
#include <string>

#include "lagrangian/lagrangian.hpp"

// θ1, θ2 from the downward vertical; unit masses and rods; g = 9.81 m/s².
struct MyDoublePendulum {
  static constexpr int coordinate_count = 2;
  double m1 = 1, m2 = 1, l1 = 1, l2 = 1, g = 9.81;
  std::string name() const { return "my_double_pendulum"; }
  std::array<std::string, 2> coordinate_names() const { return {"theta1", "theta2"}; }
  std::array<std::string, 2> coordinate_units() const { return {"rad", "rad"}; }  // CSV: theta1 [rad]

  template <class S>  // T = ½(m1+m2) l1² θ̇1² + ½ m2 l2² θ̇2² + m2 l1 l2 θ̇1 θ̇2 cos(θ1−θ2)
  S kinetic(const lagrangian::Vec<S, 2>& q, const lagrangian::Vec<S, 2>& qd, const S&) const {
    using std::cos;
    return 0.5 * (m1 + m2) * l1 * l1 * qd[0] * qd[0] + 0.5 * m2 * l2 * l2 * qd[1] * qd[1] +
           m2 * l1 * l2 * qd[0] * qd[1] * cos(q[0] - q[1]);
  }
  template <class S>  // V = −(m1+m2) g l1 cos θ1 − m2 g l2 cos θ2
  S potential(const lagrangian::Vec<S, 2>& q, const S&) const {
    using std::cos;
    return -(m1 + m2) * g * l1 * cos(q[0]) - m2 * g * l2 * cos(q[1]);
  }
};

int main(int argc, char** argv) try {
  const std::string out = argc > 1 ? argv[1] : "";
  lagrangian::State<2> x0;
  x0.q << 2.0, 2.0;  // released at rest from θ1 = θ2 = 2 rad: chaotic motion
  lagrangian::SimulationOptions opt;
  opt.t_end = 20.0;
  opt.rtol = 1e-10;
  opt.atol = 1e-12;
  opt.output_interval = 0.01;
  lagrangian::RunReport report;
  if (out.empty()) {
    report = lagrangian::simulate(MyDoublePendulum{}, x0, opt);
  } else {
    report = lagrangian::simulate(MyDoublePendulum{}, x0, opt, lagrangian::CsvSink(out + "/trajectory.csv"));
    report.write_json(out + "/report.json");
  }
  std::cout << report.summary();
  if (!out.empty()) std::cout << "wrote " << out << "/trajectory.csv and " << out << "/report.json\n";
  // A conservative system: the energy must be kept to the tolerance's order.
  return report.total_energy_drift_max < 1e-7 ? 0 : 1;
} catch (const std::exception& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 2;
}
