#include "lagrangian/models/centre_of_mass.hpp"

#include <cmath>
#include <sstream>
#include <string>

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include "lagrangian/errors.hpp"
#include "lagrangian/params.hpp"

namespace lagrangian::models {

std::pair<double, double> two_particle_centre(double m1, double m2, double d) {
  require_positive("two_particle_centre", "m1", m1);
  require_positive("two_particle_centre", "m2", m2);
  require_nonnegative("two_particle_centre", "d", d);
  const double m = m1 + m2;
  return {m2 / m * d, m1 / m * d};
}

Eigen::Vector3d centre_of_mass(const std::vector<double>& masses, const std::vector<Eigen::Vector3d>& positions) {
  if (masses.size() != positions.size())
    throw ParameterError("centre_of_mass: " + std::to_string(masses.size()) + " masses for " +
                         std::to_string(positions.size()) + " positions");
  if (masses.empty()) throw ParameterError("centre_of_mass: no particles");
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double total = 0;
  for (std::size_t k = 0; k < masses.size(); ++k) {
    require_positive("centre_of_mass", "m[" + std::to_string(k) + "]", masses[k]);
    if (!positions[k].allFinite())
      throw ParameterError("centre_of_mass: position r[" + std::to_string(k) + "] is not finite");
    sum += masses[k] * positions[k];
    total += masses[k];
  }
  return sum / total;
}

namespace {

// M = ∫ m(u) du and S = ∫ y(u) m(u) du over [a, b]: the mass per unit of a
// parameter u and the position y(u) of that mass element.
template <class Mass, class Position>
MassIntegral parametric_mass_integral(const Mass& m, const Position& y, double a, double b, double tolerance) {
  using Quadrature = boost::math::quadrature::gauss_kronrod<double, 15>;
  double err_m = 0, err_s = 0;
  MassIntegral r;
  r.mass = Quadrature::integrate(m, a, b, 15, tolerance, &err_m);
  r.moment = Quadrature::integrate([&](double u) { return y(u) * m(u); }, a, b, 15, tolerance, &err_s);
  if (!(r.mass > 0)) throw ParameterError("mass_integral: the total mass is not positive");
  r.centre = r.moment / r.mass;
  r.error = (std::abs(err_s) + std::abs(r.centre) * std::abs(err_m)) / r.mass;
  return r;
}

}  // namespace

MassIntegral mass_integral(const std::function<double(double)>& w, double a, double b, double tolerance) {
  require_finite("mass_integral", "a", a);
  require_finite("mass_integral", "b", b);
  if (!(a < b)) {
    std::ostringstream os;
    os.precision(17);
    os << "mass_integral: the interval [" << a << ", " << b << "] is empty";
    throw ParameterError(os.str());
  }
  auto density = [&w](double s) {
    const double v = w(s);
    if (!std::isfinite(v) || v < 0) {
      std::ostringstream os;
      os.precision(17);
      os << "mass_integral: the density must be non-negative and finite, got " << v << " at s = " << s;
      throw ParameterError(os.str());
    }
    return v;
  };
  return parametric_mass_integral(density, [](double s) { return s; }, a, b, tolerance);
}

MassIntegral rod(double L, const std::function<double(double)>& density) {
  require_positive("rod", "L", L);
  return mass_integral(density, 0.0, L);
}

MassIntegral semicircular_arc(double R) {
  require_positive("semicircular_arc", "R", R);
  // In the angle θ ∈ [0, π]: dm = λ R dθ (λ = 1 kg/m) at y = R sin θ.
  return parametric_mass_integral([R](double) { return R; }, [R](double th) { return R * std::sin(th); }, 0.0,
                                  std::acos(-1.0), 1e-13);
}

MassIntegral semicircular_lamina(double R) {
  require_positive("semicircular_lamina", "R", R);
  // Strips at y = R sin φ, φ ∈ [0, π/2], of width 2R cos φ and height
  // dy = R cos φ dφ (σ = 1 kg/m²): smooth in φ, unlike √(R² − y²) in y.
  return parametric_mass_integral([R](double phi) { return 2.0 * R * R * std::cos(phi) * std::cos(phi); },
                                  [R](double phi) { return R * std::sin(phi); }, 0.0, 0.5 * std::acos(-1.0), 1e-13);
}

MassIntegral solid_hemisphere(double R) {
  require_positive("solid_hemisphere", "R", R);
  const double pi = std::acos(-1.0);
  return mass_integral([R, pi](double z) { return pi * (R * R - z * z); }, 0.0, R);
}

MassIntegral solid_cone(double h, double R) {
  require_positive("solid_cone", "h", h);
  require_positive("solid_cone", "R", R);
  const double pi = std::acos(-1.0);
  return mass_integral(
      [h, R, pi](double z) {
        const double r = R * (1.0 - z / h);
        return pi * r * r;
      },
      0.0, h);
}

}  // namespace lagrangian::models
