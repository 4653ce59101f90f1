// The constrained systems of the course notes: degrees of freedom from the
// constraint Jacobians, and a short run of each checked against what it must do.
#include <algorithm>
#include <cmath>
#include <iostream>

#include "example_checks.hpp"
#include "lagrangian/lagrangian.hpp"
#include "lagrangian/models/constrained.hpp"
#include "lagrangian/models/pendulums.hpp"

using namespace lagrangian;
using namespace lagrangian::models;

namespace {

using example::check;

template <class M, int N>
RunReport run(const char* title, const M& model, const State<N>& s, double t_end) {
  std::cout << "== " << title << "\n" << dof_report(model, s).summary();
  SimulationOptions o;
  o.t_end = t_end;
  const RunReport r = simulate(model, s, o);
  std::cout << r.summary();
  return r;
}

}  // namespace

int main() try {
  {  // An abacus bead on a straight wire inclined at α: s̈ = −g sin α.
    const BeadOnWire bead(1.0, 0.4, 9.81);
    lagrangian::Recorder<2> rec;
    State<2> s;
    SimulationOptions o;
    o.t_end = 1.0;
    o.output_interval = -1;
    std::cout << "== bead on a wire\n" << dof_report(bead, s).summary();
    simulate(bead, s, o, rec);
    const double along = -(rec.samples.back().q.norm());
    check(std::abs(along - (-0.5 * 9.81 * std::sin(0.4))) < 1e-9, "distance along the wire = ½ g sin α t²");
  }
  {  // The wire spinning at ω: r(t) = r0 cosh ωt.
    const BeadOnRotatingWire bead(1.0, 2.0);
    State<2> s;
    s.q << 0.1, 0.0;
    s.qd << 0.0, 0.2;
    const RunReport r = run("bead on a rotating wire", bead, s, 1.0);
    check(!r.conservative, "the moving wire does work (energy not conserved)");
  }
  {  // A particle on a sphere: 2 degrees of freedom; the same motion as the
     // spherical pendulum in the angles (θ from the downward vertical, φ).
    const double th = 1.0, phd = 1.5;
    State<3> s;
    s.q << std::sin(th), 0.0, -std::cos(th);
    s.qd << 0.0, std::sin(th) * phd, 0.0;
    const RunReport r = run("particle on a sphere", ParticleOnSphere{}, s, 5.0);
    check(dof_report(ParticleOnSphere{}, s).degrees_of_freedom == 2, "3 coordinates − 1 constraint = 2 DOF");
    check(r.total_energy_drift_max < 1e-8, "energy conserved");
    State<2> a;
    a.q << th, 0.0;
    a.qd << 0.0, phd;
    SimulationOptions o;
    o.t_end = 5.0;
    o.rtol = 1e-11;
    o.atol = 1e-13;
    o.output_interval = 0.5;
    Recorder<3> cart;
    Recorder<2> angles;
    simulate(ParticleOnSphere{}, s, o, cart);
    simulate(SphericalPendulum{}, a, o, angles);
    double worst = 0;
    for (std::size_t k = 0; k < cart.samples.size(); ++k) {
      const auto& q = angles.samples[k].q;
      const Vec<double, 3> p(std::sin(q[0]) * std::cos(q[1]), std::sin(q[0]) * std::sin(q[1]), -std::cos(q[0]));
      worst = std::max(worst, (p - cart.samples[k].q).norm());
    }
    std::cout << "  max distance Cartesian vs spherical coordinates: " << worst << " m\n";
    check(worst < 1e-8, "Cartesian with the constraint = spherical coordinates");
  }
  {  // Atwood machine: constant acceleration (m1 − m2) g / (m1 + m2).
    const AtwoodMachine atwood(3.0, 1.0);
    State<2> s;
    const RunReport r = run("Atwood machine", atwood, s, 1.0);
    check(r.constraints.max_position_residual < 1e-12, "string length kept");
  }
  {  // Double pendulum in Cartesian coordinates: 4 − 2 = 2 DOF.
    State<4> s;
    s.q << std::sin(1.0), -std::cos(1.0), std::sin(1.0) + std::sin(2.0), -std::cos(1.0) - std::cos(2.0);
    const RunReport r = run("double pendulum, Cartesian", CartesianDoublePendulum{}, s, 5.0);
    check(dof_report(CartesianDoublePendulum{}, s).degrees_of_freedom == 2, "2 degrees of freedom");
    check(r.total_energy_drift_max < 1e-8, "energy conserved");
  }
  {  // Knife edge: 3 configuration but 2 velocity degrees of freedom.
    State<3> s;
    s.qd << 1.0, 0.0, 0.5;
    const RunReport r = run("knife edge (nonholonomic)", KnifeEdge{}, s, 5.0);
    const DofReport d = dof_report(KnifeEdge{}, s);
    check(d.degrees_of_freedom == 3 && d.velocity_degrees_of_freedom == 2, "DOF 3, velocity DOF 2");
    check(r.conserved_momenta.size() == 1 && r.conserved_momenta[0].coordinate == "phi",
          "p_phi conserved; p_x, p_y are not (the constraint acts on x, y)");
  }
  {  // A particle released near the top of a smooth sphere slides and leaves
     // it where the normal force vanishes: cos θ* = (2/3) cos θ0.
    const double theta0 = 0.05, R = 1.0;
    const ParticleOffSphere sphere(1.0, R, 9.81);
    State<2> s;
    s.q << R * std::sin(theta0), R * std::cos(theta0);
    SimulationOptions o;
    o.t_end = 2.0;
    o.rtol = 1e-12;
    o.atol = 1e-14;
    o.output_interval = 0;
    Recorder<2> rec;
    std::cout << "== particle sliding off a sphere (unilateral)\n";
    const RunReport r = simulate(sphere, s, o, rec);
    std::cout << r.summary();
    double cos_release = 0;
    for (const auto& x : rec.samples)
      if (!r.events.empty() && x.t == r.events[0].t) cos_release = x.q[1] / R;
    std::cout << "  leaves at cos θ = " << cos_release << ", (2/3) cos θ0 = " << 2.0 / 3.0 * std::cos(theta0) << "\n";
    check(r.events.size() == 1 && r.events[0].kind == lagrangian::EventKind::release && std::abs(cos_release - 2.0 / 3.0 * std::cos(theta0)) < 1e-9,
          "leaves the sphere at cos θ = (2/3) cos θ0");
  }
  return example::finish();
} catch (const std::exception& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 2;
}
