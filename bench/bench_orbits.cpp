// Accuracy and cost on eccentric orbits: two bodies with m2/m1 = 1e-3,
// G = a = 1, from periapsis, for e = 0.5, 0.9, 0.99, in three formulations
// of the same motion (Cartesian coordinates of both bodies, the relative
// coordinate with the reduced mass, and plane polar coordinates), each with
// gauss_radau15 and with fehlberg78 and bulirsch_stoer at rtol 1e-15; and
// for gauss_radau15 the reduced-mass problem with its force correctly
// rounded (reduced_exact_f: the round-off floor of evaluations in double).
// Prints the relative energy error at the end (the final state's energy
// evaluated in long double) and the median wall time of the repeats (docs/performance.md, "Gauss–Radau on eccentric orbits").
//
// Usage: bench_orbits [ORBITS=1000] [REPEATS=3] [RTOL_RADAU=1e-9]
//        bench_orbits --case E RATIO F0 [ORBITS=1000] [RTOL=1e-9]
//
// --case runs one case of the same-run comparison with REBOUND's IAS15
// (bench/peers/run_ias15.sh, bench/peers/ias15_orbits.c): m1 = 1,
// m2 = RATIO, G = a = 1, the relative orbit of eccentricity E started at
// true anomaly F0 (rad), gauss_radau15 at RTOL once in each formulation, one
// line each:
//   gauss_radau15 FORMULATION E RATIO F0 |dE/E0| WALL_S CPU_S STEPS EVALUATIONS
// with |dE/E0| as above and WALL_S / CPU_S the wall and process CPU time of
// simulate() alone.
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "lagrangian/integrate/simulate.hpp"
#include "lagrangian/models/pendulums.hpp"
#include "lagrangian/models/two_body.hpp"

namespace {

using namespace lagrangian;
namespace lm = lagrangian::models;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

struct Result {
  double error = 0;  ///< |E(t_end) − E(0)| / |E(0)|
  double wall = 0;   ///< median wall time (s)
  double cpu = 0;    ///< process CPU time of the run of median wall time (s)
  std::uint64_t steps = 0, evaluations = 0;
};

/// The energy of a state, in long double so that its own round-off (T and V
/// are 200 times |E| at the periapsis of e = 0.99) does not hide the
/// integrator's: `energy(q, q̇)` of the formulation.
template <int N, class M, class Energy>
Result measure(const M& model, const State<N>& x0, SimulationOptions o, int repeats, const Energy& energy) {
  Result r;
  std::vector<std::pair<double, double>> walls;  // (wall, CPU)
  for (int k = 0; k < repeats; ++k) {
    Recorder<N> rec;
    const double cpu_start = cpu_seconds();
    const auto start = std::chrono::steady_clock::now();
    const RunReport rep = simulate(model, x0, o, rec);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    walls.emplace_back(wall, cpu_seconds() - cpu_start);
    const long double e0 = energy(rec.samples.front()), e1 = energy(rec.samples.back());
    r.error = static_cast<double>(std::abs((e1 - e0) / e0));
    r.steps = rep.steps;
    r.evaluations = rep.rhs_evaluations;
  }
  std::sort(walls.begin(), walls.end());
  r.wall = walls[walls.size() / 2].first;
  r.cpu = walls[walls.size() / 2].second;
  return r;
}

/// The reduced-mass problem with its force −k r/r³ computed in long double
/// and rounded once, as a generalized force (V = 0): q̈ correctly rounded,
/// the floor of what any evaluation in double can give. Only for
/// gauss_radau15, to show where its energy error comes from.
struct CorrectlyRoundedKepler {
  static constexpr int coordinate_count = 2;
  static constexpr bool constant_mass_matrix = true;
  double mu, k;
  template <class S>
  S kinetic(const Vec<S, 2>&, const Vec<S, 2>& qd, const S&) const {
    return 0.5 * mu * (qd[0] * qd[0] + qd[1] * qd[1]);
  }
  template <class S>
  S potential(const Vec<S, 2>&, const S&) const {
    return S(0);
  }
  Vec<double, 2> generalized_forces(const Vec<double, 2>& q, const Vec<double, 2>&, double) const {
    using L = long double;
    const L x = q[0], y = q[1], r2 = x * x + y * y, f = L(k) / (r2 * std::sqrt(r2));
    return Vec<double, 2>(static_cast<double>(-f * x), static_cast<double>(-f * y));
  }
};

/// One case of the comparison with IAS15 (--case): gauss_radau15 at `rtol`
/// in the three formulations, the relative orbit of eccentricity e started at
/// true anomaly f0, masses 1 and `ratio`; one line per formulation.
int run_case(double e, double ratio, double f0, double orbits, double rtol, const char* const* text) {
  const double G = 1, a = 1, m1 = 1, m2 = ratio;
  const double M = m1 + m2, mu = m1 * m2 / M, k = G * m1 * m2, gm = G * M;
  const double period = 2 * std::acos(-1.0) * std::sqrt(a * a * a / gm);
  // r = p/(1 + e cos f), v = √(GM/p) (−sin f, e + cos f) (as ias15_orbits.c)
  const double p = a * (1 - e * e), r = p / (1 + e * std::cos(f0)), h = std::sqrt(gm / p);
  const double x = r * std::cos(f0), y = r * std::sin(f0), vx = -h * std::sin(f0), vy = h * (e + std::cos(f0));
  SimulationOptions o;
  o.method = Method::gauss_radau15;
  o.rtol = rtol;
  o.atol = 1e-300;
  o.t_end = orbits * period;
  o.dt = 1e-6 * period;
  o.output_interval = -1;
  o.max_steps = 500'000'000;
  auto row = [&](const char* form, const Result& res) {
    std::printf("gauss_radau15 %s %s %s %s %.6e %.6e %.6e %llu %llu\n", form, text[0], text[1], text[2], res.error,
                res.wall, res.cpu, static_cast<unsigned long long>(res.steps),
                static_cast<unsigned long long>(res.evaluations));
    std::fflush(stdout);
  };
  {  // both bodies, centre of mass at rest at the origin (the energy as in main)
    State<4> s;
    s.q << -m2 / M * x, -m2 / M * y, m1 / M * x, m1 / M * y;
    s.qd << -m2 / M * vx, -m2 / M * vy, m1 / M * vx, m1 / M * vy;
    const auto energy = [&](const Sample<4>& z) {
      using L = long double;
      const L dx = L(z.q[2]) - z.q[0], dy = L(z.q[3]) - z.q[1];
      const L v1 = L(z.qd[0]) * z.qd[0] + L(z.qd[1]) * z.qd[1], v2 = L(z.qd[2]) * z.qd[2] + L(z.qd[3]) * z.qd[3];
      return L(0.5) * m1 * v1 + L(0.5) * m2 * v2 - k / std::sqrt(dx * dx + dy * dy);
    };
    row("two_body", measure(lm::TwoBody<2>(m1, m2, lm::NewtonianGravity{k}), s, o, 1, energy));
  }
  {  // the relative coordinate, reduced mass μ
    State<2> s;
    s.q << x, y;
    s.qd << vx, vy;
    const auto energy = [&](const Sample<2>& z) {
      using L = long double;
      const L v2 = L(z.qd[0]) * z.qd[0] + L(z.qd[1]) * z.qd[1];
      return L(0.5) * mu * v2 - k / std::sqrt(L(z.q[0]) * z.q[0] + L(z.q[1]) * z.q[1]);
    };
    row("reduced_mass", measure(lm::RelativeMotion<2>(mu, lm::NewtonianGravity{k}), s, o, 1, energy));
  }
  {  // plane polar coordinates (r, φ): ṙ = √(GM/p) e sin f, r φ̇ = √(GM/p) (1 + e cos f)
    State<2> s;
    s.q << r, f0;
    s.qd << h * e * std::sin(f0), h * (1 + e * std::cos(f0)) / r;
    const auto energy = [&](const Sample<2>& z) {
      using L = long double;
      const L rr = z.q[0], rd = z.qd[0], phid = z.qd[1];
      return L(0.5) * mu * (rd * rd + rr * rr * phid * phid) - k / rr;
    };
    row("kepler_polar", measure(lm::KeplerPolar(mu, k), s, o, 1, energy));
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--case") {
    if (argc < 5) {
      std::fprintf(stderr, "usage: %s --case E RATIO F0 [ORBITS=1000] [RTOL=1e-9]\n", argv[0]);
      return 2;
    }
    return run_case(std::atof(argv[2]), std::atof(argv[3]), std::atof(argv[4]), argc > 5 ? std::atof(argv[5]) : 1000,
                    argc > 6 ? std::atof(argv[6]) : 1e-9, argv + 2);
  }
  const double orbits = argc > 1 ? std::atof(argv[1]) : 1000;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 3;
  const double radau_rtol = argc > 3 ? std::atof(argv[3]) : 1e-9;
  const double G = 1, a = 1, m1 = 1, m2 = 1e-3;
  const double M = m1 + m2, mu = m1 * m2 / M, k = G * m1 * m2, gm = G * M;
  const double period = 2 * std::acos(-1.0) * std::sqrt(a * a * a / gm);
  std::printf("two bodies, m2/m1 = %g, G = a = 1, %g orbits from periapsis; relative energy error at the end, "
              "median wall of %d\n",
              m2 / m1, orbits, repeats);
  std::printf("%-6s %-16s %-26s %12s %10s %10s %12s\n", "e", "formulation", "method", "|dE/E|", "wall (s)", "steps",
              "evaluations");
  for (const double e : {0.5, 0.9, 0.99}) {
    const double rp = a * (1 - e), vp = std::sqrt(gm * (1 + e) / (a * (1 - e)));  // relative periapsis and speed
    struct Method {
      std::string name;
      double rtol;
    };
    const std::vector<Method> methods{{"gauss_radau15", radau_rtol}, {"fehlberg78", 1e-15}, {"bulirsch_stoer", 1e-15}};
    for (const Method& method : methods) {
      SimulationOptions o;
      o.method = parse_method(method.name, "method");
      o.rtol = method.rtol;
      o.atol = 1e-300;  // relative error only, as IAS15 controls it
      o.t_end = orbits * period;
      o.dt = 1e-6 * period;  // a first step short enough for the periapsis of e = 0.99
      o.output_interval = -1;
      o.max_steps = 500'000'000;
      const std::string label = method.name + " rtol " + [&] {
        char b[16];
        std::snprintf(b, sizeof b, "%.0e", method.rtol);
        return std::string(b);
      }();
      auto row = [&](const char* form, const Result& r) {
        std::printf("%-6.2f %-16s %-26s %12.2e %10.3f %10llu %12llu\n", e, form, label.c_str(), r.error, r.wall,
                    static_cast<unsigned long long>(r.steps), static_cast<unsigned long long>(r.evaluations));
        std::fflush(stdout);
      };
      {  // both bodies, centre of mass at rest at the origin
        State<4> s;
        s.q << -m2 / M * rp, 0, m1 / M * rp, 0;
        s.qd << 0, -m2 / M * vp, 0, m1 / M * vp;
        const auto energy = [&](const Sample<4>& x) {
          using L = long double;
          const L dx = L(x.q[2]) - x.q[0], dy = L(x.q[3]) - x.q[1];
          const L v1 = L(x.qd[0]) * x.qd[0] + L(x.qd[1]) * x.qd[1], v2 = L(x.qd[2]) * x.qd[2] + L(x.qd[3]) * x.qd[3];
          return L(0.5) * m1 * v1 + L(0.5) * m2 * v2 - k / std::sqrt(dx * dx + dy * dy);
        };
        row("two_body", measure(lm::TwoBody<2>(m1, m2, lm::NewtonianGravity{k}), s, o, repeats, energy));
      }
      {  // the relative coordinate, reduced mass μ
        State<2> s;
        s.q << rp, 0;
        s.qd << 0, vp;
        const auto energy = [&](const Sample<2>& x) {
          using L = long double;
          const L v2 = L(x.qd[0]) * x.qd[0] + L(x.qd[1]) * x.qd[1];
          return L(0.5) * mu * v2 - k / std::sqrt(L(x.q[0]) * x.q[0] + L(x.q[1]) * x.q[1]);
        };
        row("reduced_mass", measure(lm::RelativeMotion<2>(mu, lm::NewtonianGravity{k}), s, o, repeats, energy));
        if (method.name == "gauss_radau15")
          row("reduced_exact_f", measure(CorrectlyRoundedKepler{mu, k}, s, o, repeats, energy));
      }
      {  // plane polar coordinates (r, φ) of the relative coordinate
        State<2> s;
        s.q << rp, 0;
        s.qd << 0, vp / rp;
        const auto energy = [&](const Sample<2>& x) {
          using L = long double;
          const L r = x.q[0], rd = x.qd[0], phid = x.qd[1];
          return L(0.5) * mu * (rd * rd + r * r * phid * phid) - k / r;
        };
        row("kepler_polar", measure(lm::KeplerPolar(mu, k), s, o, repeats, energy));
      }
    }
  }
  return 0;
}
