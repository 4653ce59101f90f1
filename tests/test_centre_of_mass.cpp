// Centres of mass of particles and of continuous bodies (quadrature) against
// their closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "lagrangian/errors.hpp"
#include "lagrangian/models/centre_of_mass.hpp"

namespace {

using namespace lagrangian;
using namespace lagrangian::models;
const double kPi = std::acos(-1.0);

TEST(CentreOfMass, TwoParticlesAndNParticles) {
  const auto [r1, r2] = two_particle_centre(2.0, 6.0, 4.0);
  EXPECT_DOUBLE_EQ(r1, 3.0);  // m2 d / (m1 + m2)
  EXPECT_DOUBLE_EQ(r2, 1.0);
  EXPECT_DOUBLE_EQ(2.0 * r1, 6.0 * r2);  // m1 r1 = m2 r2
  const auto [e1, e2] = two_particle_centre(5.0, 5.0, 3.0);
  EXPECT_DOUBLE_EQ(e1, 1.5);
  EXPECT_DOUBLE_EQ(e2, 1.5);
  // n particles: the weighted mean, and the same as grouping (two sub-centres).
  const std::vector<double> m = {1.0, 2.0, 3.0, 4.0};
  const std::vector<Eigen::Vector3d> r = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {1, 1, 3}};
  const Eigen::Vector3d R = centre_of_mass(m, r);
  EXPECT_NEAR(R.x(), (2.0 + 4.0) / 10.0, 1e-15);
  EXPECT_NEAR(R.y(), (6.0 + 4.0) / 10.0, 1e-15);
  EXPECT_NEAR(R.z(), 12.0 / 10.0, 1e-15);
  const Eigen::Vector3d a = centre_of_mass({1.0, 2.0}, {r[0], r[1]});
  const Eigen::Vector3d b = centre_of_mass({3.0, 4.0}, {r[2], r[3]});
  EXPECT_LE((centre_of_mass({3.0, 7.0}, {a, b}) - R).norm(), 1e-15);
}

TEST(CentreOfMass, ContinuousBodiesByQuadrature) {
  const double L = 2.5, R = 0.8, h = 1.7;
  // Uniform rod: L/2. Rod with λ = λ0 (1 + x/L): ∫x(1 + x/L) / ∫(1 + x/L) = (L²/2 + L²/3) / (3L/2) = 5L/9.
  EXPECT_NEAR(rod(L, [](double) { return 3.0; }).centre, L / 2, 1e-14);
  const MassIntegral linear = rod(L, [L](double x) { return 0.4 * (1 + x / L); });
  EXPECT_NEAR(linear.centre, 5 * L / 9, 1e-14);
  EXPECT_NEAR(linear.mass, 0.4 * 1.5 * L, 1e-14);
  // A rod with λ = x²: x̄ = (L⁴/4)/(L³/3) = 3L/4.
  EXPECT_NEAR(rod(L, [](double x) { return x * x; }).centre, 0.75 * L, 1e-14);
  EXPECT_NEAR(semicircular_arc(R).centre, 2 * R / kPi, 1e-14);
  const MassIntegral lamina = semicircular_lamina(R);
  EXPECT_NEAR(lamina.centre, 4 * R / (3 * kPi), 1e-12);
  EXPECT_NEAR(lamina.mass, kPi * R * R / 2, 1e-12);
  EXPECT_LE(lamina.error, 1e-10);
  const MassIntegral hemisphere = solid_hemisphere(R);
  EXPECT_NEAR(hemisphere.centre, 3 * R / 8, 1e-14);
  EXPECT_NEAR(hemisphere.mass, 2 * kPi * R * R * R / 3, 1e-13);
  const MassIntegral cone = solid_cone(h, R);
  EXPECT_NEAR(cone.centre, h / 4, 1e-14);
  EXPECT_NEAR(cone.mass, kPi * R * R * h / 3, 1e-13);
}

TEST(CentreOfMass, BadInputIsAClearError) {
  EXPECT_THROW(two_particle_centre(-1.0, 1.0, 1.0), ParameterError);
  EXPECT_THROW(centre_of_mass({1.0}, {}), ParameterError);
  EXPECT_THROW(centre_of_mass({}, {}), ParameterError);
  try {
    centre_of_mass({1.0, 0.0}, {{0, 0, 0}, {1, 0, 0}});
    FAIL() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("parameter 'm[1]' must be positive and finite, got 0"), std::string::npos)
        << e.what();
  }
  try {
    rod(1.0, [](double x) { return x < 0.5 ? 1.0 : -2.0; });
    FAIL() << "no error";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("the density must be non-negative and finite, got -2 at s = "),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(rod(1.0, [](double) { return std::nan(""); }), ParameterError);
  EXPECT_THROW(rod(0.0, [](double) { return 1.0; }), ParameterError);
  EXPECT_THROW(mass_integral([](double) { return 1.0; }, 1.0, 1.0), ParameterError);
  EXPECT_THROW(solid_cone(1.0, -1.0), ParameterError);
}

}  // namespace
