#pragma once
// ad::WidthScope: the number of directions that run-time-width
// ad::EomJet numbers carry in a pass (run-time sized models).

namespace lagrangian::ad {

namespace detail {
/// The number of directions the run-time-width numbers of this thread
/// carry (EomJet<C, true>): set for a pass by WidthScope.
inline constinit thread_local int eom_width = 0;
}  // namespace detail

/// Run-time widths are rounded up to a multiple of this (the directions
/// beyond the model's n stay zero), so that loops over them run in whole
/// unrolled chunks.
inline constexpr int kWidthStep = 4;

/// Sets the width of this thread's run-time-width EomJet numbers for a
/// scope (a pass), and restores the previous width at its end.
class WidthScope {
 public:
  explicit WidthScope(int width) : previous_(detail::eom_width) {
    detail::eom_width = (width + kWidthStep - 1) / kWidthStep * kWidthStep;
  }
  ~WidthScope() { detail::eom_width = previous_; }
  WidthScope(const WidthScope&) = delete;
  WidthScope& operator=(const WidthScope&) = delete;

 private:
  int previous_;
};

}  // namespace lagrangian::ad
