#pragma once
/// \file centre_of_mass.hpp
/// Centres of mass (course notes 2.1): of particles, R = Σ m_k r_k / Σ m_k,
/// and of continuous bodies, R = (1/M) ∫ r dm, by adaptive Gauss–Kronrod
/// quadrature (Boost.Math, compiled once in src/models/centre_of_mass.cpp). SI
/// units; densities in kg/m, kg/m² or kg/m³ as the body's dimension.

#include <functional>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace lagrangian::models {

/// Distances of the centre of mass of two particles m₁, m₂ (kg) a distance
/// d (m) apart from each of them: r₁ = m₂ d/(m₁ + m₂), r₂ = m₁ d/(m₁ + m₂),
/// so that m₁ r₁ = m₂ r₂ (notes 2.1.1).
std::pair<double, double> two_particle_centre(double m1, double m2, double d);

/// R = Σ m_k r_k / Σ m_k (m) for n particles (notes 2.1.2). Throws
/// ParameterError for a size mismatch, an empty set, or a mass that is not
/// positive and finite (naming its index).
Eigen::Vector3d centre_of_mass(const std::vector<double>& masses, const std::vector<Eigen::Vector3d>& positions);

/// A one-dimensional mass integral: M = ∫ w(s) ds and S = ∫ s w(s) ds over
/// [a, b], with w the mass per unit s (kg/m), and the centre S/M.
struct MassIntegral {
  double mass = 0;    ///< M (kg)
  double moment = 0;  ///< S (kg·m)
  double centre = 0;  ///< S / M (m)
  double error = 0;   ///< the quadrature's error estimate for the centre (m)
};

/// M and S of the mass density w on [a, b] by adaptive Gauss–Kronrod (15
/// points) to the relative tolerance. Throws ParameterError when a ≥ b, or
/// when w is negative or not finite at a quadrature node (naming s and w),
/// or when M is not positive.
MassIntegral mass_integral(const std::function<double(double)>& w, double a, double b, double tolerance = 1e-13);

/// A straight rod of length L (m) along x from its end, with linear density
/// λ(x) (kg/m): x̄ = ∫ x λ dx / ∫ λ dx. Uniform: L/2.
MassIntegral rod(double L, const std::function<double(double)>& density);

/// A uniform semicircular arc (wire) of radius R (m), symmetric about y:
/// dm = λ R dθ at y = R sin θ, θ ∈ [0, π]: ȳ = 2R/π.
MassIntegral semicircular_arc(double R);

/// A uniform semicircular lamina of radius R (m): strips at height y of
/// width 2√(R² − y²): ȳ = 4R/(3π). Integrated in φ with y = R sin φ, where
/// the integrand is smooth (in y its derivative is singular at y = R).
MassIntegral semicircular_lamina(double R);

/// A uniform solid hemisphere of radius R (m) on its flat face: discs at
/// height z of area π(R² − z²): z̄ = 3R/8.
MassIntegral solid_hemisphere(double R);

/// A uniform solid right circular cone, height h (m), base radius R (m),
/// standing on its base: discs at height z of radius R(1 − z/h): z̄ = h/4.
MassIntegral solid_cone(double h, double R);

}  // namespace lagrangian::models
