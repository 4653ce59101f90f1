#include "lagrangian/integrate/detail/run.hpp"

#include <sstream>

#include "lagrangian/errors.hpp"

namespace lagrangian::detail {

Run::Run(System& system, const SimulationOptions& options, RunReport& report)
    : system_(system),
      opt_(options),
      report_(report),
      size_(system.coordinate_count()),
      events_(system.has_events()),
      constraints_(system.has_constraints()),
      last_t_(options.t0),
      buf_(static_cast<std::size_t>(2 * size_), 0.0) {
  update_next_output();
}

void Run::emit(double t, const double* x) {
  system_.sample(t, x);
  ++report_.samples;
  last_emitted_ = t;
}

void Run::update_next_output() {
  constexpr double inf = std::numeric_limits<double>::infinity();
  const double dt_out = opt_.output_interval;
  next_output_ = dt_out > 0 ? opt_.t0 + static_cast<double>(next_output_index_) * dt_out : inf;
  sample_due_ = dt_out > 0 ? next_output_ : dt_out == 0 ? -inf : inf;
  sample_slack_ = dt_out > 0 ? 1e-12 * dt_out : 0.0;
}

void Run::accepted_slow(double t_old, double t, const double* x, const Interpolator& interpolate) {
  if (!all_finite(x)) throw_non_finite(t_old, t, x);
  if (report_.steps > opt_.max_steps) throw_max_steps(t);
  if (opt_.output_interval == 0) {
    emit(t, x);
  } else if (opt_.output_interval > 0) {
    const double tol = 1e-12 * std::max(std::abs(t), opt_.output_interval);
    for (double to = next_output_time(); to <= t + tol && to <= opt_.t_end + tol; to = next_output_time()) {
      ++next_output_index_;
      update_next_output();
      if (std::abs(to - t) <= tol) {
        emit(t, x);
      } else {
        interpolate(to, buf_.data());
        emit(to, buf_.data());
      }
    }
  }
}

void Run::rejected(double t, double dt) {
  ++report_.rejected_steps;
  if (++consecutive_rejections_ > 1000 || !(dt > 1e-15 * std::max(1.0, std::abs(t)))) {
    std::ostringstream os;
    os.precision(17);
    os << "step size underflow at t = " << t << " (dt = " << dt << " after " << consecutive_rejections_
       << " rejected steps); the problem may be stiff (try method rosenbrock4) or singular";
    throw SimulationError(os.str(), t);
  }
}

void Run::finish(const double* x) {
  report_.t_final = last_t_;
  const bool sample_end = opt_.output_interval != 0 && last_emitted_ != last_t_;
  system_.finish(last_t_, x, sample_end);
  if (sample_end) {
    ++report_.samples;
    last_emitted_ = last_t_;
  }
}

namespace {
/// "x = [x0, x1, …] (q then qd)" at full precision, for the messages below.
void write_state(std::ostringstream& os, const double* x, int n) {
  os << "x = [";
  for (int k = 0; k < 2 * n; ++k) os << (k ? ", " : "") << x[k];
  os << "] (q then qd)";
}
}  // namespace

void Run::throw_non_finite(double t_old, double t, const double* x) const {
  std::ostringstream os;
  os.precision(17);
  os << "non-finite state after the step from t = " << t_old << " to t = " << t << ": ";
  write_state(os, x, size_);
  os << "; the run was stopped";
  throw SimulationError(os.str(), t);
}

void throw_non_finite_energy(double t, double energy, const double* x, int n) {
  std::ostringstream os;
  os.precision(17);
  os << "the energy is not finite at t = " << t << " (E = " << energy << " J) although the state is: ";
  write_state(os, x, n);
  os << "; the state reached a singularity of the model (a collision, r = 0 of a central force) or its terms "
        "overflow double precision (about 1e308), so the run was stopped";
  throw SimulationError(os.str(), t);
}

void Run::throw_max_steps(double t) const {
  std::ostringstream os;
  os << "max_steps = " << opt_.max_steps << " reached at t = " << t << " before t_end = " << opt_.t_end;
  throw SimulationError(os.str(), t);
}

}  // namespace lagrangian::detail
