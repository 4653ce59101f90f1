// The chaotic double pendulum (m = l = 1, g = 9.81, θ₁ = θ₂ = 2 rad from
// rest) to t = 5 s and 20 s: the final-state error against the 36-digit
// reference of bench/reference/double_pendulum.txt, and the median wall
// time, for gauss_radau15 and for fehlberg78 and bulirsch_stoer over their
// tolerances (docs/performance.md, "Gauss–Radau on the chaotic double
// pendulum").
//
// Usage: bench_double_pendulum [REPEATS=5]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "lagrangian/integrate/simulate.hpp"
#include "lagrangian/models/pendulums.hpp"

int main(int argc, char** argv) {
  using namespace lagrangian;
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 5;
  // bench/reference/double_pendulum.txt (70-digit run), rounded to double.
  struct Reference {
    double t;
    std::array<double, 4> x;
  };
  const std::array<Reference, 2> refs{
      Reference{5.0,
                {-1.410706688941584255089104615020398236118, -4.041716878877189687566077358790925909559,
                 -1.984147306034064825616346511085029318764, -5.429525625408064226171414122363918190494}},
      Reference{20.0,
                {0.1331110409533288179392626946627098523853, -30.15572941228644871906116174598442574834,
                 3.892915415262310090929197793596436874494, 4.799273316583681084173939753666041202325}}};
  struct Method {
    std::string name;
    std::vector<double> rtols;
  };
  const std::vector<Method> methods{{"gauss_radau15", {1e-7, 1e-8, 1e-9, 1e-10, 1e-11}},
                                    {"fehlberg78", {1e-10, 1e-11, 1e-12, 1e-13, 1e-14, 1e-15}},
                                    {"bulirsch_stoer", {1e-10, 1e-12, 1e-14, 1e-15}}};
  std::printf("double pendulum from (2, 2) rad at rest; error = max |x_i - reference| over (theta, theta_dot); "
              "median wall of %d\n",
              repeats);
  std::printf("%-6s %-16s %8s %12s %12s %10s %12s\n", "t_end", "method", "rtol", "error", "wall (ms)", "steps",
              "evaluations");
  for (const Reference& ref : refs) {
    for (const Method& m : methods) {
      for (const double rtol : m.rtols) {
        SimulationOptions o;
        o.method = parse_method(m.name, "method");
        o.rtol = rtol;
        o.atol = rtol * 1e-2;
        o.t_end = ref.t;
        o.output_interval = -1;
        State<2> s;
        s.q << 2.0, 2.0;
        s.qd << 0.0, 0.0;
        std::vector<double> walls;
        double error = 0;
        RunReport rep;
        for (int k = 0; k < repeats; ++k) {
          Recorder<2> rec;
          const auto start = std::chrono::steady_clock::now();
          rep = simulate(models::DoublePendulum(1, 1, 1, 1, 9.81), s, o, rec);
          walls.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
          const auto& end = rec.samples.back();
          error = 0;
          for (int i = 0; i < 2; ++i)
            error = std::max({error, std::abs(end.q[i] - ref.x[static_cast<std::size_t>(i)]),
                              std::abs(end.qd[i] - ref.x[static_cast<std::size_t>(2 + i)])});
        }
        std::sort(walls.begin(), walls.end());
        std::printf("%-6g %-16s %8.0e %12.2e %12.3f %10llu %12llu\n", ref.t, m.name.c_str(), rtol, error,
                    1e3 * walls[walls.size() / 2], static_cast<unsigned long long>(rep.steps),
                    static_cast<unsigned long long>(rep.rhs_evaluations));
        std::fflush(stdout);
      }
    }
  }
  return 0;
}
