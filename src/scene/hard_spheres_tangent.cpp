// The tangent flow of the event-driven hard-sphere engine
// (scene/hard_spheres_tangent.hpp): tangent vectors carried across the
// engine's impacts by their saltation matrices, Benettin's method and MEGNO
// over them, and the state transition matrix at the samples.

#include "lagrangian/scene/hard_spheres_tangent.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "lagrangian/analysis/lyapunov.hpp"
#include "lagrangian/analysis/sensitivity.hpp"
#include "lagrangian/errors.hpp"

namespace lagrangian::scene {
namespace {

/// k tangent vectors of a gas of N spheres, W (6N × k): rows 3i … 3i+2 hold
/// δr_i at sphere i's own time tau_[i], rows 3N + 3i … δv_i. With `lengths`,
/// each vector's squared length in (r, v) is kept as the quadratic
/// |δx_c(t_ref + τ)|² = A_c + 2 B_c τ + C_c τ² of its flight, updated by
/// the two spheres of each impact.
class GasTangent {
 public:
  GasTangent(const HardSphereSystem& system, Eigen::MatrixXd start, double t0, bool lengths)
      : n_(static_cast<int>(system.spheres.size())),
        k_(static_cast<int>(start.cols())),
        lengths_(lengths),
        w_(std::move(start)),
        tau_(static_cast<std::size_t>(n_), t0),
        t_ref_(t0) {
    for (const HardSphere& s : system.spheres) mass_.push_back(s.mass);
    restart(t0);
  }

  /// Crosses an impact: its spheres' rows brought to its time, then its
  /// saltation matrix (the header's formulas).
  void impact(const HardSphereImpact& e) {
    const int a = static_cast<int>(e.a), b = static_cast<int>(e.b);
    add(a, -1.0);
    if (b >= 0) add(b, -1.0);
    to_time(a, e.t);
    if (b >= 0) to_time(b, e.t);
    if (b >= 0) {
      pair(a, b, e);
    } else {
      wall(a, e);
    }
    add(a, 1.0);
    if (b >= 0) add(b, 1.0);
  }

  /// W with every sphere's rows at time t (no sphere's own time is later).
  Eigen::MatrixXd& at(double t) {
    for (int i = 0; i < n_; ++i) to_time(i, t);
    return w_;
  }

  /// The length sums anew about t, after W changed with every row at t.
  void restart(double t) {
    t_ref_ = t;
    a_.setZero(k_);
    b_.setZero(k_);
    c_.setZero(k_);
    for (int i = 0; i < n_; ++i) add(i, 1.0);
  }

  /// |δx_c(t)|² in (r, v) (m² + m²/s²).
  double length2(int c, double t) const {
    const double tau = t - t_ref_;
    return std::max(a_[c] + (2.0 * b_[c] + c_[c] * tau) * tau, 0.0);
  }

  /// ∫ ln |δx_c|² dt over [t1, t2] in closed form (the header): with
  /// Q = C (u² + h²), u = τ + B/C, h² = (A − B²/C)/C ≥ 1 (Q ≥ |δv|² = C),
  ///   ∫ ln Q dτ = Δ ln Q(τ1) + u2 ln(q2/q1) − 2Δ + 2h [atan(u2/h) − atan(u1/h)],
  /// q = u² + h², Δ = τ2 − τ1, each difference formed without cancellation;
  /// where Q changes by less than 1e-8 of itself over the flight (or the
  /// scales leave double's range), Δ ln Q(τ1) + (B1 Δ² + C Δ³/3)/Q(τ1),
  /// B1 = B + C τ1, whose error is below 1e-16 relative.
  double log_length2_integral(int c, double t1, double t2) const {
    const double d = t2 - t1, q_start = length2(c, t1);
    if (!(d > 0)) return 0.0;
    const double A = a_[c], B = b_[c], C = c_[c];
    const double slope = B + C * (t1 - t_ref_);  // ½ dQ/dτ at τ1
    const double series = d * std::log(q_start) + (slope * d * d + C * d * d * d / 3.0) / q_start;
    if (!(C > 0) || 2.0 * std::abs(slope) * d + C * d * d <= 1e-8 * q_start) return series;
    const double shift = B / C, h2 = std::max((A - B * shift) / C, 1.0);
    if (!std::isfinite(shift) || !std::isfinite(h2)) return series;
    const double h = std::sqrt(h2);
    const double u1 = (t1 - t_ref_) + shift, u2 = (t2 - t_ref_) + shift;
    const double q1 = u1 * u1 + h2;
    return d * std::log(q_start) + u2 * std::log1p(d * (u1 + u2) / q1) - 2.0 * d +
           2.0 * h * std::atan2(d * h, h2 + u1 * u2);
  }

  int spheres() const { return n_; }
  int columns() const { return k_; }
  double mass(int i) const { return mass_[static_cast<std::size_t>(i)]; }

 private:
  void to_time(int i, double t) {
    double& ti = tau_[static_cast<std::size_t>(i)];
    if (t == ti) return;
    w_.middleRows(3 * i, 3) += w_.middleRows(3 * n_ + 3 * i, 3) * (t - ti);
    ti = t;
  }

  /// Sphere i's part of the length sums, added with `sign`.
  void add(int i, double sign) {
    if (!lengths_) return;
    const double back = t_ref_ - tau_[static_cast<std::size_t>(i)];
    for (int c = 0; c < k_; ++c) {
      const Eigen::Vector3d dv = w_.block<3, 1>(3 * n_ + 3 * i, c);
      const Eigen::Vector3d dr = w_.block<3, 1>(3 * i, c) + dv * back;  // δr_i at t_ref
      const double vv = dv.squaredNorm();
      a_[c] += sign * (dr.squaredNorm() + vv);
      b_[c] += sign * dr.dot(dv);
      c_[c] += sign * vv;
    }
  }

  void pair(int a, int b, const HardSphereImpact& e) {
    const Eigen::Vector3d& n = e.normal;
    const Eigen::Vector3d w = e.va_before - e.vb_before;
    const double nw = n.dot(w);  // −u < 0
    const double ma = mass(a), mb = mass(b);
    const double ca = (1 + e.restitution) * (mb / (ma + mb)), cb = (1 + e.restitution) * (ma / (ma + mb));
    const Eigen::Vector3d ja = e.va_after - e.va_before, jb = e.vb_after - e.vb_before;
    for (int c = 0; c < k_; ++c) {
      auto ra = w_.block<3, 1>(3 * a, c), rb = w_.block<3, 1>(3 * b, c);
      auto va = w_.block<3, 1>(3 * n_ + 3 * a, c), vb = w_.block<3, 1>(3 * n_ + 3 * b, c);
      const Eigen::Vector3d rho = ra - rb, dw = va - vb;
      const double s = n.dot(rho) / nw;
      Eigen::Vector3d dn = rho - s * w;
      dn -= n * n.dot(dn);
      dn /= e.distance;
      const Eigen::Vector3d change = dn * nw + n * (dn.dot(w) + n.dot(dw));
      ra += ja * s;
      rb += jb * s;
      va -= ca * change;
      vb += cb * change;
    }
  }

  void wall(int a, const HardSphereImpact& e) {
    const Eigen::Vector3d& n = e.normal;
    const double nv = n.dot(e.va_before);  // < 0
    const Eigen::Vector3d ja = e.va_after - e.va_before;
    for (int c = 0; c < k_; ++c) {
      auto ra = w_.block<3, 1>(3 * a, c);
      auto va = w_.block<3, 1>(3 * n_ + 3 * a, c);
      const double s = n.dot(ra) / nv;
      ra += ja * s;
      va -= ((1 + e.restitution) * n.dot(va)) * n;
    }
  }

  int n_, k_;
  bool lengths_;
  Eigen::MatrixXd w_;
  std::vector<double> tau_, mass_;
  double t_ref_;
  Eigen::VectorXd a_, b_, c_;
};

/// Benettin's method and MEGNO over a GasTangent (the header).
class GasLyapunov {
 public:
  GasLyapunov(const HardSphereSystem& system, const HardSphereOptions& options, int k, double interval)
      : t0_(options.t0), interval_(interval), tangent_(system, start(system, k), options.t0, true),
        sums_(static_cast<std::size_t>(k), 0.0), last_(options.t0), megno_t_(options.t0) {
    reference_lengths();
  }

  void impact(const HardSphereImpact& e) {
    advance_megno(e.t);
    const double before = ell(e.t);
    tangent_.impact(e);
    integral_ += (e.t - t0_) * (ell(e.t) - before);  // ℓ jumps: s dℓ
    y_ = e.t > t0_ ? 2.0 * integral_ / (e.t - t0_) : 0.0;
    ++impacts_;
    if (e.t - last_ >= interval_ || grown(e.t)) renormalise(e.t);
  }

  LyapunovResult finish(double t_end) {
    advance_megno(t_end);
    if (renormalisations_ == 0 || t_end > last_) renormalise(t_end);
    for (double s : sums_)
      if (!std::isfinite(s))
        throw SimulationError("lyapunov: the gas's tangent vectors lost their independence (a zero or non-finite "
                              "diagonal of R at a renormalisation); no exponents are reported",
                              t_end);
    if (!std::isfinite(y_) || !std::isfinite(mean_integral_))
      throw SimulationError("lyapunov: MEGNO of the gas's first tangent vector is not finite", t_end);
    LyapunovResult r;
    const double T = t_end - t0_;
    for (double s : sums_) r.spectrum.push_back(s / T);
    std::sort(r.spectrum.begin(), r.spectrum.end(), [](double x, double y) { return x > y; });
    for (double l : r.spectrum) r.sum += l;
    r.t_final = t_end;
    r.renormalisations = renormalisations_;
    r.interval_min = interval_min_;
    r.interval_max = interval_max_;
    r.impacts = impacts_;
    r.megno = y_;
    r.megno_mean = T > 0 ? mean_integral_ / T : 0.0;
    return r;
  }

 private:
  /// The first k canonical unit vectors of (r, p), as (δr, δv = δp/m).
  static Eigen::MatrixXd start(const HardSphereSystem& system, int k) {
    const int n = static_cast<int>(system.spheres.size());
    Eigen::MatrixXd w = Eigen::MatrixXd::Zero(6 * n, k);
    for (int j = 0; j < k; ++j)
      w(j, j) = j < 3 * n ? 1.0 : 1.0 / system.spheres[static_cast<std::size_t>((j - 3 * n) / 3)].mass;
    return w;
  }

  /// ℓ(t) = ln |δx_1(t)| up to a constant: MEGNO takes only its changes
  /// (∫ s dℓ), so the constant a renormalisation would add cancels.
  double ell(double t) const { return 0.5 * std::log(tangent_.length2(0, t)); }

  /// I(t) = ∫₀ˢ s' dℓ after the flight from megno_t_ to t (no impact in
  /// between): ∫ s dℓ = [s ℓ] − ∫ ℓ ds, exactly.
  double integral_at(double t) const {
    const double s1 = megno_t_ - t0_, s2 = t - t0_;
    const double area = 0.5 * tangent_.log_length2_integral(0, megno_t_, t);
    return integral_ + s2 * ell(t) - s1 * ell(megno_t_) - area;
  }

  /// MEGNO over the flight to t: Y = 2 I / s exactly, ⟨Y⟩'s integral by
  /// Simpson's rule with Y at the flight's midpoint.
  void advance_megno(double t) {
    if (!(t > megno_t_)) return;
    const double s1 = megno_t_ - t0_, s2 = t - t0_, mid = 0.5 * (megno_t_ + t);
    const double y_mid = 2.0 * integral_at(mid) / (mid - t0_);
    integral_ = integral_at(t);
    const double y2 = 2.0 * integral_ / s2;
    mean_integral_ += (s2 - s1) * (y_ + 4.0 * y_mid + y2) / 6.0;
    y_ = y2;
    megno_t_ = t;
  }

  bool grown(double t) const {
    for (int c = 0; c < tangent_.columns(); ++c) {
      const double ratio = tangent_.length2(c, t) / reference_[static_cast<std::size_t>(c)];
      if (ratio > kGrowth2 || ratio < 1.0 / kGrowth2) return true;
    }
    return false;
  }

  void reference_lengths() {
    reference_.resize(static_cast<std::size_t>(tangent_.columns()));
    for (int c = 0; c < tangent_.columns(); ++c) reference_[static_cast<std::size_t>(c)] = tangent_.length2(c, last_);
  }

  /// Z = P W = Q R in (r, p); log R_jj summed, W ← P⁻¹ Q.
  void renormalise(double t) {
    Eigen::MatrixXd& w = tangent_.at(t);
    const int n = tangent_.spheres(), k = tangent_.columns();
    Eigen::MatrixXd z = w;
    for (int i = 0; i < n; ++i) z.middleRows(3 * n + 3 * i, 3) *= tangent_.mass(i);
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(z);
    const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(6 * n, k);
    const Eigen::MatrixXd& r = qr.matrixQR();
    for (int j = 0; j < k; ++j) {
      const double rjj = r(j, j);
      w.col(j) = rjj < 0 ? Eigen::VectorXd(-q.col(j)) : Eigen::VectorXd(q.col(j));
      sums_[static_cast<std::size_t>(j)] += std::log(std::abs(rjj));
    }
    for (int i = 0; i < n; ++i) w.middleRows(3 * n + 3 * i, 3) /= tangent_.mass(i);
    tangent_.restart(t);
    const double gap = t - last_;
    if (renormalisations_ == 0 || gap < interval_min_) interval_min_ = gap;
    if (renormalisations_ == 0 || gap > interval_max_) interval_max_ = gap;
    ++renormalisations_;
    last_ = t;
    reference_lengths();
  }

  static constexpr double kGrowth2 = 7.38905609893065;  // e², a length changed by more than e

  double t0_, interval_;
  GasTangent tangent_;
  std::vector<double> sums_, reference_;
  double last_;  // time of the last renormalisation (s)
  int renormalisations_ = 0, impacts_ = 0;
  double interval_min_ = 0, interval_max_ = 0;
  double megno_t_, integral_ = 0, y_ = 0, mean_integral_ = 0;
};

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", x);
  return buf;
}

void require_positive_restitutions(const HardSphereSystem& system) {
  auto check = [](const std::string& field, double e) {
    if (e == 0.0)
      throw OptionError("lyapunov: " + field +
                        " = 0: a plastic impact's saltation matrix is singular (determinant e^2 = 0), so the "
                        "tangent flow of a gas is taken for restitution coefficients > 0");
  };
  check("pair_restitution", system.pair_restitution);
  check("box_restitution", system.box_restitution);
  for (std::size_t k = 0; k < system.walls.size(); ++k)
    check("walls[" + std::to_string(k) + "].restitution", system.walls[k].restitution);
}

}  // namespace

LyapunovResult lyapunov_hard_spheres(const HardSphereSystem& system, const HardSphereOptions& options, int exponents,
                                     double interval) {
  lagrangian::validate(system, options);
  const int d = 6 * static_cast<int>(system.spheres.size());
  if (exponents < 0 || exponents > d)
    throw OptionError("lyapunov: exponents must be in [0, " + std::to_string(d) + "] (0: all " + std::to_string(d) +
                      " of " + std::to_string(d / 6) + " spheres), got " + std::to_string(exponents));
  const int k = exponents == 0 ? d : exponents;
  if (k > kMaxHardSphereExponents)
    throw OptionError("lyapunov: " + std::string(exponents == 0 ? "all " : "") + std::to_string(k) +
                      " exponents asked of a gas of " + std::to_string(d / 6) +
                      " spheres; its tangent run carries at most " + std::to_string(kMaxHardSphereExponents) +
                      " vectors (the whole spectrum of 100 spheres): ask for fewer (--exponents K)");
  if (!std::isfinite(interval) || interval < 0)
    throw OptionError("lyapunov: interval must be a finite time >= 0 s (0: T/100), got " + number(interval));
  require_positive_restitutions(system);
  const auto started = std::chrono::steady_clock::now();
  HardSphereOptions run = options;
  run.output_interval = 0.0;       // samples at t0 and t_end: the final state
  run.max_recorded_events = 0;     // the impacts reach the tangent run through the observer
  GasLyapunov lyapunov(system, run, k, interval > 0 ? interval : (run.t_end - run.t0) / 100);
  std::vector<double> q, qd;
  const auto sampler = [&](double, const std::vector<HardSphere>& spheres) {
    q.clear();
    qd.clear();
    for (const HardSphere& s : spheres)
      for (int c = 0; c < 3; ++c) {
        q.push_back(s.position[c]);
        qd.push_back(s.velocity[c]);
      }
  };
  const RunReport report =
      lagrangian::run_hard_spheres(system, run, sampler, [&](const HardSphereImpact& e) { lyapunov.impact(e); });
  LyapunovResult r = lyapunov.finish(run.t_end);
  r.steps = report.steps;
  r.q_final = std::move(q);
  r.qd_final = std::move(qd);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return r;
}

SensitivityResult sensitivities_hard_spheres(const HardSphereSystem& system, const HardSphereOptions& options) {
  lagrangian::validate(system, options);
  const int n = static_cast<int>(system.spheres.size());
  if (n > kMaxHardSphereSensitivitySpheres)
    throw OptionError("sensitivity: a gas of " + std::to_string(n) + " spheres; the state transition matrix (6N x 6N) "
                      "is taken for at most " + std::to_string(kMaxHardSphereSensitivitySpheres) + " spheres");
  const auto started = std::chrono::steady_clock::now();
  GasTangent tangent(system, Eigen::MatrixXd::Identity(6 * n, 6 * n), options.t0, false);
  SensitivityResult r;
  r.state_columns = 6 * n;
  const auto sampler = [&](double t, const std::vector<HardSphere>& spheres) {
    Eigen::VectorXd x(6 * n);
    for (int i = 0; i < n; ++i) {
      x.segment<3>(3 * i) = spheres[static_cast<std::size_t>(i)].position;
      x.segment<3>(3 * n + 3 * i) = spheres[static_cast<std::size_t>(i)].velocity;
    }
    r.times.push_back(t);
    r.states.push_back(std::move(x));
    r.sensitivities.push_back(tangent.at(t));
  };
  HardSphereOptions run = options;
  run.max_recorded_events = 0;
  const RunReport report = lagrangian::run_hard_spheres(system, run, sampler, [&](const HardSphereImpact& e) {
    tangent.impact(e);
    ++r.impacts;
  });
  r.steps = report.steps;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return r;
}

}  // namespace lagrangian::scene
