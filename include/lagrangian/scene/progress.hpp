#pragma once
/// \file progress.hpp
/// A one-line progress bar for long runs, on stderr.

#include <chrono>
#include <cstdint>

namespace lagrangian {

/// Progress of a run on stderr, shown only when stderr is a terminal and the
/// run has lasted more than about 1 s; quiet in pipes and CI.
///
/// \code
/// lagrangian::Progress progress(opts.t0, opts.t_end);
/// ... for each sample: progress.update(sample.t);
/// progress.finish();
/// \endcode
/// The line reads `[#########             ]  42%  t = 4.2 s  ETA 3 s` and is
/// redrawn in place with a carriage return, at most every 100 ms.
class Progress {
 public:
  /// A run from t0 to t_end (s). With enabled = false nothing is ever written.
  Progress(double t0, double t_end, bool enabled = stderr_is_terminal());
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;
  /// Clears the line if it was drawn (as finish()).
  ~Progress();

  /// The run has reached time t (s). Cheap: it reads the clock only every
  /// few calls — at most every 1000 calls when calls are fast, adapting so
  /// that the clock is read about every 50 ms — and redraws only then.
  void update(double t);
  /// Clears the line if it was drawn; later updates draw nothing.
  void finish();
  /// How the position is shown after the percentage: printf format with one
  /// %g-style conversion of the value passed to update() (default
  /// "t = %.4g s"; a sweep shows "run %.0f").
  void set_format(const char* format) { format_ = format; }

  /// True when stderr is a terminal (isatty), TERM is not "dumb" and the
  /// environment variable CI is not set.
  static bool stderr_is_terminal();

 private:
  using Clock = std::chrono::steady_clock;
  void draw(double t, Clock::time_point now);

  double t0_, t_end_;
  bool enabled_;
  bool drawn_ = false;
  Clock::time_point start_;
  Clock::time_point last_check_;
  Clock::time_point last_draw_;
  std::uint32_t calls_ = 0;   ///< calls since the clock was last read
  std::uint32_t stride_ = 1;  ///< calls between clock reads
  const char* format_ = "t = %.4g s";
};

}  // namespace lagrangian
