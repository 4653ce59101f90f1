// Centres of mass (course notes 2.1): two particles, n particles, and
// continuous bodies by Boost.Math quadrature against their closed forms.
#include <cmath>
#include <cstdio>
#include <iostream>

#include "lagrangian/models/centre_of_mass.hpp"

using namespace lagrangian::models;

int main() try {
  bool ok = true;
  auto row = [&](const char* body, double got, double expected, const char* formula) {
    const bool good = std::abs(got - expected) <= 1e-12 * std::max(1.0, std::abs(expected));
    std::printf("  %-34s %.15f  (%s = %.15f)%s\n", body, got, formula, expected, good ? "" : "  FAIL");
    ok = ok && good;
  };
  const double pi = std::acos(-1.0), L = 2.0, R = 1.0, h = 3.0;
  const auto [r1, r2] = two_particle_centre(1.0, 3.0, 2.0);
  std::printf("two particles, 1 kg and 3 kg, 2 m apart: %.3f m from the first, %.3f m from the second\n", r1, r2);
  row("rod, uniform", rod(L, [](double) { return 1.0; }).centre, L / 2, "L/2");
  row("rod, density 1 + x/L", rod(L, [L](double x) { return 1 + x / L; }).centre, 5 * L / 9, "5L/9");
  row("semicircular arc", semicircular_arc(R).centre, 2 * R / pi, "2R/pi");
  row("semicircular lamina", semicircular_lamina(R).centre, 4 * R / (3 * pi), "4R/(3 pi)");
  row("solid hemisphere (from the face)", solid_hemisphere(R).centre, 3 * R / 8, "3R/8");
  row("solid cone (from the base)", solid_cone(h, R).centre, h / 4, "h/4");
  std::cout << (ok ? "all checks passed\n" : "SOME CHECKS FAILED\n");
  return ok ? 0 : 1;
} catch (const std::exception& e) {
  std::cerr << "error: " << e.what() << "\n";
  return 2;
}
