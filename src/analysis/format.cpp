// Text output of the analyses (analysis.hpp): the tables `lagrangian inspect
// --equilibria --modes` prints.

#include "lagrangian/analysis/analysis.hpp"

#include <cmath>
#include <complex>
#include <cstdio>
#include <string>
#include <vector>

namespace lagrangian {

const char* to_string(EquilibriumKind kind) {
  switch (kind) {
    case EquilibriumKind::minimum: return "minimum";
    case EquilibriumKind::saddle: return "saddle";
    case EquilibriumKind::maximum: return "maximum";
    case EquilibriumKind::degenerate: return "degenerate";
  }
  return "?";
}

namespace {

std::string num(double v, int digits = 10) {
  if (v == 0.0) v = 0.0;  // no "-0"
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

/// "[a, b, …]"; entries below 1e-13 of the largest (round-off, as the
/// -1.5e-33 a converged angle may carry) are printed as 0.
std::string vec(const Eigen::VectorXd& v, int digits = 10) {
  const double big = v.size() ? v.cwiseAbs().maxCoeff() : 0.0;
  std::string out = "[";
  for (int i = 0; i < v.size(); ++i)
    out += (i ? ", " : "") + num(std::abs(v[i]) <= 1e-13 * big ? 0.0 : v[i], digits);
  return out + "]";
}

std::string coordinates_line(const std::vector<std::string>& names, const std::vector<std::string>& units) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i) {
    out += (i ? ", " : "") + names[i];
    if (i < units.size() && !units[i].empty()) out += " (" + units[i] + ")";
  }
  return out;
}

}  // namespace

std::string format_equilibria(const std::vector<Equilibrium>& equilibria, const std::vector<std::string>& names,
                              const std::vector<std::string>& units) {
  std::string out = "Equilibria (stationary points of U = -L(q, qdot = 0) on the constraint manifold), by U\n";
  out += "  q = [" + coordinates_line(names, units) + "]\n";
  if (equilibria.empty()) return out + "  none found from the starts\n";
  int i = 0;
  for (const Equilibrium& e : equilibria) {
    out += "  #" + std::to_string(++i) + "  q = " + vec(e.q) + "  U = " + num(e.potential) + " J  " +
           to_string(e.kind) + (e.stable ? " (stable)" : e.kind == EquilibriumKind::degenerate
                                                             ? " (neutral directions: stability not decided at second order)"
                                                             : " (unstable)") +
           "\n";
    out += "      Hessian of U on the tangent space, eigenvalues " + vec(e.hessian_eigenvalues, 6);
    if (e.zero_eigenvalues) out += " (" + std::to_string(e.zero_eigenvalues) + " zero)";
    out += "\n      residual |dU/dq - G^T lambda| = " + num(e.residual, 3);
    if (e.multipliers.size()) out += ", |g| = " + num(e.constraint_residual, 3) + ", lambda = " + vec(e.multipliers, 8);
    out += "; found by " + e.found_by + "\n";
  }
  return out;
}

std::string format_modes(const Modes& md, const std::vector<std::string>& names,
                         const std::vector<std::string>& units) {
  const double two_pi = 6.283185307179586;
  std::string out = "Small oscillations about q = " + vec(md.q) + "\n";
  if (md.residual > 1e-8 * (1.0 + md.stiffness.cwiseAbs().maxCoeff()))
    out += "  warning: q is not an equilibrium (|dU/dq - G^T lambda| = " + num(md.residual, 3) +
           "); the linearisation has a constant force term not shown\n";
  out += "  tangent dimension " + std::to_string(md.basis.cols()) + " (of " + std::to_string(md.q.size()) +
         " coordinates)\n";
  if (md.gyroscopic_terms)
    out += "  note: gyroscopic terms (T linear in qdot) are present; the modes below ignore them, the state "
           "matrix A and its eigenvalues include them\n";
  out += "  mode  omega^2 (1/s^2)   omega (rad/s)     f (Hz)          period (s)      shape [" +
         coordinates_line(names, units) + "], v^T M v = 1\n";
  for (int j = 0; j < md.omega_squared.size(); ++j) {
    const double w2 = md.omega_squared[j], w = md.omega[j];
    char line[200];
    if (w2 > 0) {
      std::snprintf(line, sizeof line, "  %-4d  %-16s  %-16s  %-14s  %-14s  ", j + 1, num(w2).c_str(), num(w).c_str(),
                    num(w / two_pi, 8).c_str(), num(two_pi / w, 8).c_str());
    } else if (w2 == 0) {
      std::snprintf(line, sizeof line, "  %-4d  %-16s  %-16s  %-14s  %-14s  ", j + 1, "0", "0 (zero mode)", "0", "inf");
    } else {
      std::snprintf(line, sizeof line, "  %-4d  %-16s  %-16s  %-14s  %-14s  ", j + 1, num(w2).c_str(),
                    ("growth " + num(std::sqrt(-w2), 8)).c_str(), "unstable", "-");
    }
    out += line + vec(md.shapes.col(j), 6) + "\n";
  }
  out += "  linear model: state [xi; xidot] with q = q* + Z xi, xidot = A x, eigenvalues of A:";
  const double zbig = md.state_eigenvalues.size() ? md.state_eigenvalues.cwiseAbs().maxCoeff() : 0.0;
  for (int i = 0; i < md.state_eigenvalues.size(); ++i) {
    std::complex<double> z = md.state_eigenvalues[i];
    if (std::abs(z.real()) <= 1e-12 * zbig) z.real(0.0);  // round-off of a purely imaginary pair
    out += (i ? ", " : " ") + num(z.real(), 6) + (z.imag() < 0 ? " - " : " + ") + num(std::abs(z.imag()), 8) + "i";
  }
  return out + "\n";
}

}  // namespace lagrangian
