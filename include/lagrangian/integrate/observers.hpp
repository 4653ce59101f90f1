#pragma once
/// \file observers.hpp
/// Sinks for the samples a run produces.
///
/// An observer is any callable `void(const Sample<n>&)`. It may also have
///  - `void begin(const Columns&)`, called once before the first sample, and
///  - `void finish()`, called only when the run completed successfully.
/// A sink that writes files commits them in finish(), so a failed run never
/// leaves output that looks complete.

#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "lagrangian/model.hpp"

namespace lagrangian {

/// One sample of a run: time (s), state, and the energies (J).
template <int N>
struct Sample {
  double t = 0;
  Vec<double, N> q;
  Vec<double, N> qd;
  double energy = 0;  ///< energy function h = p·q̇ − L (J)
  double total_energy = std::numeric_limits<double>::quiet_NaN();  ///< T + V (J), NaN if the model has no T, V split
  /// Constrained models: the Lagrange multipliers λ (force along +∇ of each
  /// constraint) and the generalized constraint forces Cᵀλ; empty otherwise.
  Eigen::VectorXd multipliers;
  Eigen::VectorXd constraint_forces;
};

/// What a run will sample, for observers that write headers.
struct Columns {
  std::vector<std::string> coordinates;  ///< coordinate names
  std::vector<std::string> constraints;  ///< constraint names (empty without constraints)
  bool total_energy = false;             ///< T + V is sampled
  /// SI unit of each coordinate ("m", "rad"); empty, or "" for one, when not known.
  std::vector<std::string> units;
  /// SI unit of each constraint's multiplier λ; empty, or "" for one, when not known.
  std::vector<std::string> constraint_units;
};

/// Observer that ignores every sample.
struct NullObserver {
  template <int N>
  void operator()(const Sample<N>&) const noexcept {}
};

/// Observer that keeps every sample in memory.
template <int N>
struct Recorder {
  std::vector<Sample<N>> samples;
  void operator()(const Sample<N>& s) { samples.push_back(s); }
};

/// Writes samples as CSV with a header row:
///   t, <q names...>, <name>_dot..., energy[, total_energy]
///   [, lambda_<constraint>..., Qc_<coordinate>...]   (constrained models)
/// each field followed by its SI unit where known: "t [s]", "theta [rad]",
/// "theta_dot [rad/s]", "energy [J]", "Qc_theta [N*m]" (pandas keeps the
/// field whole: df["theta [rad]"]). Values use 17 significant digits. The file is written as `<path>.partial`
/// and renamed to `<path>` by finish(); it is removed if the run fails.
class CsvSink {
 public:
  /// Opens `<path>.partial` for writing; throws OptionError naming the path
  /// when it cannot be created.
  explicit CsvSink(std::string path);
  CsvSink(const CsvSink&) = delete;
  CsvSink& operator=(const CsvSink&) = delete;
  CsvSink(CsvSink&& other) noexcept;
  ~CsvSink();

  void begin(const Columns& columns);

  template <int N>
  void operator()(const Sample<N>& s) {
    write_row(s.t, s.q.data(), s.qd.data(), static_cast<int>(s.q.size()), s.energy, s.total_energy);
    write_extra(s.multipliers, s.constraint_forces);
  }

  /// Flushes and renames the partial file to its final name.
  void finish();
  /// Final path of the file.
  const std::string& path() const { return path_; }

 private:
  void write_row(double t, const double* q, const double* qd, int n, double energy, double total_energy);
  void write_extra(const Eigen::VectorXd& multipliers, const Eigen::VectorXd& forces);
  std::string path_;
  std::FILE* file_ = nullptr;
  bool total_energy_ = false;
  bool finished_ = false;
};

}  // namespace lagrangian
