#pragma once
// Odeint's rosenbrock4 works on Boost.uBLAS types, which Boost 1.74 cannot
// compile as C++20 (std::allocator::construct was removed). The stepper is
// therefore compiled in src/integrate/stiff.cpp as C++17 and reached through this
// plain interface; this header must stay valid C++17.

#include <memory>

namespace lagrangian::detail {

/// Right-hand side f(x, t) and its Jacobian for the stiff stepper.
struct StiffSystem {
  void* context;
  void (*rhs)(void* context, const double* x, double* dxdt, double t);
  /// J is row-major m×m; dfdt = ∂f/∂t.
  void (*jacobian)(void* context, const double* x, double* J, double* dfdt, double t);
};

/// Odeint's rosenbrock4_controller<rosenbrock4<double>> for a state of size m.
class Rosenbrock4Stepper {
 public:
  Rosenbrock4Stepper(int m, double atol, double rtol);
  ~Rosenbrock4Stepper();
  Rosenbrock4Stepper(const Rosenbrock4Stepper&) = delete;
  Rosenbrock4Stepper& operator=(const Rosenbrock4Stepper&) = delete;

  /// One controlled step attempt from (x, t) with step dt. On success x and t
  /// advance and dt holds the next suggested step; on failure dt is reduced.
  bool try_step(const StiffSystem& system, double* x, double& t, double& dt);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace lagrangian::detail
