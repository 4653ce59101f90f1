#pragma once
/// \file fpe.hpp
/// Debugging aid: trap the floating-point exception FE_INVALID (0/0, ∞ − ∞,
/// √−1, …) so that the first operation that makes a NaN stops the program
/// with SIGFPE at that instruction (run it under gdb, or read the core
/// dump's backtrace), instead of the NaN spreading until a check far away
/// reports it.
///
/// Scoped: `lagrangian::FloatingPointTrap trap;` enables the trap in the
/// current thread and restores the previous setting when it goes out of
/// scope. Configuring with `-DLAGRANGIAN_TRAP_FE_INVALID=ON` makes every
/// simulate() run inside such a scope. glibc (feenableexcept) only; elsewhere
/// the class does nothing and `FloatingPointTrap::supported` is false.

#include <cfenv>

namespace lagrangian {

class FloatingPointTrap {
 public:
#if defined(__GLIBC__)
  static constexpr bool supported = true;
  explicit FloatingPointTrap(int excepts = FE_INVALID) : previous_(fegetexcept()) {
    std::feclearexcept(excepts);
    feenableexcept(excepts);
  }
  ~FloatingPointTrap() {
    fedisableexcept(FE_ALL_EXCEPT);
    feenableexcept(previous_);
  }
#else
  static constexpr bool supported = false;
  explicit FloatingPointTrap(int = 0) {}
#endif
  FloatingPointTrap(const FloatingPointTrap&) = delete;
  FloatingPointTrap& operator=(const FloatingPointTrap&) = delete;

 private:
#if defined(__GLIBC__)
  int previous_;
#endif
};

}  // namespace lagrangian
