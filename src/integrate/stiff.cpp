// Compiled as C++17: see include/lagrangian/integrate/detail/stiff.hpp.
#include "lagrangian/integrate/detail/stiff.hpp"

#include <utility>
#include <vector>

#include <boost/numeric/odeint/stepper/rosenbrock4.hpp>
#include <boost/numeric/odeint/stepper/rosenbrock4_controller.hpp>

namespace lagrangian::detail {

namespace odeint = boost::numeric::odeint;
using Vector = boost::numeric::ublas::vector<double>;
using Matrix = boost::numeric::ublas::matrix<double>;

struct Rosenbrock4Stepper::Impl {
  int m;
  odeint::rosenbrock4_controller<odeint::rosenbrock4<double>> controller;
  Vector x;
  std::vector<double> xa, fa, jac;
  Impl(int size, double atol, double rtol)
      : m(size), controller(atol, rtol), x(size), xa(size), fa(size), jac(static_cast<std::size_t>(size) * size) {}
};

Rosenbrock4Stepper::Rosenbrock4Stepper(int m, double atol, double rtol) : impl_(new Impl(m, atol, rtol)) {}
Rosenbrock4Stepper::~Rosenbrock4Stepper() = default;

bool Rosenbrock4Stepper::try_step(const StiffSystem& system, double* x, double& t, double& dt) {
  Impl& s = *impl_;
  const int m = s.m;
  auto rhs = [&](const Vector& xv, Vector& dxdt, double tt) {
    for (int i = 0; i < m; ++i) s.xa[i] = xv[i];
    system.rhs(system.context, s.xa.data(), s.fa.data(), tt);
    for (int i = 0; i < m; ++i) dxdt[i] = s.fa[i];
  };
  auto jac = [&](const Vector& xv, Matrix& J, double tt, Vector& dfdt) {
    for (int i = 0; i < m; ++i) s.xa[i] = xv[i];
    system.jacobian(system.context, s.xa.data(), s.jac.data(), s.fa.data(), tt);
    for (int i = 0; i < m; ++i) {
      dfdt[i] = s.fa[i];
      for (int j = 0; j < m; ++j) J(i, j) = s.jac[static_cast<std::size_t>(i) * m + j];
    }
  };
  for (int i = 0; i < m; ++i) s.x[i] = x[i];
  const odeint::controlled_step_result r = s.controller.try_step(std::make_pair(rhs, jac), s.x, t, dt);
  if (r != odeint::success) return false;
  for (int i = 0; i < m; ++i) x[i] = s.x[i];
  return true;
}

}  // namespace lagrangian::detail
