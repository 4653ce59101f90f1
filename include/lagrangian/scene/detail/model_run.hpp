#pragma once
// Internal: a scene's run of a generalized-coordinate model — simulate() with
// trajectory output and progress ticks — shared by the registry's entries
// (src/scene/) and scene::run_model() for a user's C++ model
// (scene/model_run.hpp), and a user's model as the scene runner sees it.

#include <array>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "lagrangian/mechanics/constraints.hpp"
#include "lagrangian/scene/detail/registry.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/model.hpp"
#include "lagrangian/integrate/observers.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/models.hpp"
#include "lagrangian/integrate/simulate.hpp"
#include "lagrangian/view/view.hpp"

namespace lagrangian::scene::detail {

/// The observer of a scene run: CSV rows (committed by finish(), which
/// simulate() calls only on success) and a tick with each sample.
template <int N>
struct SceneObserver {
  CsvSink* csv = nullptr;
  const SampleTick* tick = nullptr;
  FinalState* final_state = nullptr;
  void begin(const Columns& c) {
    if (csv) csv->begin(c);
  }
  void operator()(const Sample<N>& s) {
    if (csv) (*csv)(s);
    if (tick) {
      const auto n = static_cast<std::size_t>(s.q.size());
      (*tick)(SampleRow{s.t, {s.q.data(), n}, {s.qd.data(), n}, s.energy, s.total_energy});
    }
    if (final_state) {
      final_state->t = s.t;
      final_state->q.assign(s.q.data(), s.q.data() + s.q.size());
      final_state->qd.assign(s.qd.data(), s.qd.data() + s.qd.size());
    }
  }
  void finish() {
    if (csv) csv->finish();
  }
};

/// Runs simulate() on a built-in model, writing the trajectory to `csv_path`
/// when it is not empty (through `<csv_path>.partial`, renamed only when the
/// run succeeds), calling tick(t) for every sample and keeping the last
/// sample in `*final_state` when given. An initial state that
/// violates the model's constraints is a SceneError keyed "model.q"; a file
/// that cannot be created is keyed "output.directory".
template <class M>
RunReport run_model(const M& model, const State<coordinate_count_v<M>>& initial, const SimulationOptions& options,
                    const std::string& csv_path, const SampleTick& tick, FinalState* final_state = nullptr) {
  std::optional<CsvSink> csv;
  if (!csv_path.empty()) {
    try {
      csv.emplace(csv_path);
    } catch (const SceneError&) {
      throw;
    } catch (const OptionError& e) {
      throw SceneError("output.directory", e.what());
    }
  }
  SceneObserver<coordinate_count_v<M>> observer{csv ? &*csv : nullptr, tick ? &tick : nullptr, final_state};
  try {
    return simulate(model, initial, options, observer);
  } catch (const ConstraintError& e) {
    throw SceneError("model.q", std::string("inconsistent initial state: ") + e.what());
  } catch (const DomainError& e) {
    throw SceneError("model.q", e.what());
  }
}

/// A C++ model handed to scene::run_model() (scene/model_run.hpp), with its
/// initial state: what ModelSpec::user holds.
class UserModel {
 public:
  virtual ~UserModel() = default;
  /// Name, coordinates and units (no parameters: the model holds its own).
  virtual ModelInfo info() const = 0;
  /// simulate() from the initial state (see run_model above).
  virtual RunReport run(const SimulationOptions& options, const std::string& csv_path, const SampleTick& tick,
                        FinalState* final_state) const = 0;
  /// The model's particles as point masses placed by their coordinates, or
  /// a figure with no bodies (see ModelEntry::picture).
  virtual view::Figure picture(const double* t, const double* q, std::size_t rows, std::vector<double>& xyz) const = 0;
  /// Each particle's coordinate indices of x, y, z (see ModelEntry::particle_axes).
  virtual std::vector<std::array<int, 3>> particle_axes() const = 0;
};

template <class M>
class UserModelOf final : public UserModel {
 public:
  UserModelOf(const M& model, const State<coordinate_count_v<M>>& initial, std::string name)
      : model_(model), initial_(initial), name_(std::move(name)) {}

  ModelInfo info() const override {
    ModelInfo i;
    i.name = name_;
    i.description = "a model written in C++";
    i.coordinates = coordinate_names(model_);
    i.units = coordinate_units(model_);
    return i;
  }
  RunReport run(const SimulationOptions& options, const std::string& csv_path, const SampleTick& tick,
                FinalState* final_state) const override {
    return run_model(model_, initial_, options, csv_path, tick, final_state);
  }
  view::Figure picture(const double*, const double* q, std::size_t rows, std::vector<double>& xyz) const override {
    view::Figure f;
    const std::vector<std::array<int, 3>> axes = particle_axes();
    for (std::size_t b = 0; b < axes.size(); ++b) f.bodies.push_back({"particle " + std::to_string(b + 1), 0.0, -1});
    const std::size_t n = static_cast<std::size_t>(model_size(model_)), nb = axes.size();
    xyz.assign(rows * nb * 3, 0.0);
    for (std::size_t r = 0; r < rows; ++r)
      for (std::size_t b = 0; b < nb; ++b)
        for (std::size_t a = 0; a < 3; ++a)
          if (axes[b][a] >= 0) xyz[(r * nb + b) * 3 + a] = q[r * n + static_cast<std::size_t>(axes[b][a])];
    return f;
  }
  std::vector<std::array<int, 3>> particle_axes() const override {
    std::vector<std::array<int, 3>> axes;
    if constexpr (has_particles_v<M>)
      for (const Particle& p : model_.particles()) axes.push_back(p.axes);
    return axes;
  }

 private:
  M model_;
  State<coordinate_count_v<M>> initial_;
  std::string name_;
};

}  // namespace lagrangian::scene::detail
