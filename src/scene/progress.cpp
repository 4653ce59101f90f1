#include "lagrangian/scene/progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace lagrangian {

namespace {

constexpr auto kShowAfter = std::chrono::seconds(1);        // stay quiet for short runs
constexpr auto kRedrawEvery = std::chrono::milliseconds(100);
constexpr auto kCheckEvery = std::chrono::milliseconds(50);  // target interval between clock reads
constexpr std::uint32_t kMaxStride = 1000;
constexpr int kBarWidth = 30;

// "3 s", "2 min 05 s", "1 h 07 min".
std::string format_duration(double s) {
  char buf[64];
  if (!std::isfinite(s) || s < 0) return "?";
  if (s < 60) {
    std::snprintf(buf, sizeof buf, "%.0f s", std::ceil(s));
  } else if (s < 3600) {
    const long total = std::lround(s);
    std::snprintf(buf, sizeof buf, "%ld min %02ld s", total / 60, total % 60);
  } else {
    const long total = std::lround(s / 60);
    std::snprintf(buf, sizeof buf, "%ld h %02ld min", total / 60, total % 60);
  }
  return buf;
}

void write_stderr(const std::string& s) {
  const char* p = s.data();
  std::size_t left = s.size();
  while (left > 0) {
    const ssize_t n = ::write(STDERR_FILENO, p, left);
    if (n <= 0) return;  // best effort: a progress bar never fails a run
    p += n;
    left -= static_cast<std::size_t>(n);
  }
}

}  // namespace

Progress::Progress(double t0, double t_end, bool enabled)
    : t0_(t0), t_end_(t_end), enabled_(enabled), start_(Clock::now()), last_check_(start_), last_draw_(start_) {}

Progress::~Progress() { finish(); }

bool Progress::stderr_is_terminal() {
  if (!::isatty(STDERR_FILENO)) return false;
  const char* term = std::getenv("TERM");
  if (term && std::strcmp(term, "dumb") == 0) return false;
  const char* ci = std::getenv("CI");
  if (ci && *ci) return false;
  return true;
}

void Progress::update(double t) {
  if (!enabled_) return;
  if (++calls_ < stride_) return;
  calls_ = 0;
  const Clock::time_point now = Clock::now();
  // Adapt the stride so that the clock is read about every kCheckEvery.
  const auto since_check = now - last_check_;
  last_check_ = now;
  if (since_check < kCheckEvery / 2) {
    stride_ = std::min(kMaxStride, stride_ * 2);
  } else if (since_check > kCheckEvery * 2 && stride_ > 1) {
    stride_ = std::max<std::uint32_t>(1, stride_ / 2);
  }
  if (now - start_ < kShowAfter) return;
  if (drawn_ && now - last_draw_ < kRedrawEvery) return;
  draw(t, now);
}

void Progress::draw(double t, Clock::time_point now) {
  const double span = t_end_ - t0_;
  double f = span > 0 ? (t - t0_) / span : 1.0;
  if (!std::isfinite(f)) f = 0;
  f = std::clamp(f, 0.0, 1.0);
  const int filled = static_cast<int>(f * kBarWidth + 1e-9);
  const double elapsed = std::chrono::duration<double>(now - start_).count();

  std::string line = "\r[";
  line.append(static_cast<std::size_t>(filled), '#');
  line.append(static_cast<std::size_t>(kBarWidth - filled), ' ');
  char buf[160];
  std::snprintf(buf, sizeof buf, "] %3d%%  ", static_cast<int>(f * 100));
  line += buf;
  std::snprintf(buf, sizeof buf, format_, t);
  line += buf;
  if (f > 0 && f < 1) line += "  ETA " + format_duration(elapsed * (1 - f) / f);
  line += "\x1b[K";  // clear the rest of a longer previous line
  write_stderr(line);
  drawn_ = true;
  last_draw_ = now;
}

void Progress::finish() {
  if (drawn_) write_stderr("\r\x1b[K");
  drawn_ = false;
  enabled_ = false;
}

}  // namespace lagrangian
