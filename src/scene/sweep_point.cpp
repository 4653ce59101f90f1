// One sweep point: its scene from the scene file's TOML document (scene keys
// parsed into paths, the point's values written at them), its run and the
// SweepRecord of the outcome with the --first-time crossings (from the
// samples in memory) and, when asked, the largest Lyapunov exponent and
// MEGNO, and the record's text form passed between ranks (MPI).

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <stdexcept>

#include "sweep_detail.hpp"
#include "lagrangian/errors.hpp"
#include "particle_engine.hpp"
#include "toml_document.hpp"
#include "lagrangian/scene/analysis.hpp"
#include "lagrangian/scene/models.hpp"
#include "lagrangian/scene/run.hpp"
#include "text_model_spec.hpp"

namespace lagrangian::scene::detail {

/// The document of one point, with its values written in; `values` gets the
/// varied then the set values.
Scene point_scene(const Plan& plan, const SweepOptions& o, toml::table& doc, std::vector<double>& values) {
  std::vector<double> vars;
  for (std::size_t slot : plan.variable_slots) vars.push_back(values[slot]);
  for (std::size_t k = 0; k < o.vary.size(); ++k)
    if (!plan.vary_paths[k].empty()) assign(doc, "--vary", o.vary[k].key, plan.vary_paths[k], values[k]);
  for (std::size_t k = 0; k < o.set.size(); ++k) {
    const double v = plan.set_expressions[k].evaluate(vars.data());
    values.push_back(v);
    if (!std::isfinite(v))
      throw OptionError("--set " + o.set[k].key + ": the expression " + q(o.set[k].expression) + " gives " +
                        (std::isnan(v) ? "NaN" : "an infinite value") + " at this point");
    assign(doc, "--set", o.set[k].key, plan.set_paths[k], v);
  }
  return detail::scene_from_document(doc, plan.file);
}

}  // namespace lagrangian::scene::detail

namespace lagrangian::scene::detail {

/// Names a --first-time expression may use for `scene`: t, the coordinates
/// and their rates as in trajectory.csv, energy and total_energy.
std::vector<std::string> trajectory_names(const Scene& scene) {
  std::vector<std::string> coords;
  if (scene.model) {
    if (const auto info = detail::model_info(*scene.model)) coords = info->coordinates;
  } else {
    Scene expanded = scene;
    expanded.expand_gas();
    coords = body_coordinates(expanded);
  }
  std::vector<std::string> names{"t"};
  names.insert(names.end(), coords.begin(), coords.end());
  for (const auto& c : coords) names.push_back(c + "_dot");
  names.emplace_back("energy");
  names.emplace_back("total_energy");
  return names;
}

namespace {

/// The first times of the --first-time expressions, from the run's samples
/// as they come (see FirstTimeSpec): each expression over t, q, q̇, energy
/// and total_energy (trajectory_names()), its first positive value located
/// by linear interpolation between that sample and the one before.
class FirstTimes {
 public:
  FirstTimes(const Scene& scene, const SweepOptions& o) : times_(o.first_times.size(), kNaN), prev_(times_.size(), kNaN) {
    const std::vector<std::string> names = trajectory_names(scene);
    for (const FirstTimeSpec& f : o.first_times) exprs_.emplace_back(f.expression, names, "--first-time " + f.name);
    row_.resize(names.size());
  }
  void operator()(const SampleRow& s) {
    if (open_ == 0) return;
    // t, q, q̇, energy, total_energy, as trajectory_names() lists them.
    if (row_.size() != 3 + s.q.size() + s.qd.size())
      throw std::logic_error("--first-time: a sample of " + std::to_string(s.q.size()) +
                             " coordinates against names for " + std::to_string((row_.size() - 3) / 2));
    std::size_t c = 0;
    row_[c++] = s.t;
    for (double v : s.q) row_[c++] = v;
    for (double v : s.qd) row_[c++] = v;
    row_[c++] = s.energy;
    row_[c++] = s.total_energy;
    for (std::size_t k = 0; k < exprs_.size(); ++k) {
      if (!std::isnan(times_[k])) continue;
      const double v = exprs_[k].evaluate(row_.data());
      if (v > 0) {
        times_[k] = std::isfinite(prev_[k]) && prev_[k] <= 0 && v != prev_[k]
                        ? prev_t_ + (s.t - prev_t_) * (0 - prev_[k]) / (v - prev_[k])
                        : s.t;
        --open_;
      }
      prev_[k] = v;
    }
    prev_t_ = s.t;
  }
  const std::vector<double>& times() const { return times_; }

 private:
  std::vector<Expression> exprs_;
  std::vector<double> times_, prev_, row_;
  double prev_t_ = kNaN;
  std::size_t open_ = times_.size();
};

}  // namespace

SweepRecord run_point(const Plan& plan, const SweepOptions& o, std::uint64_t index) {
  SweepRecord rec;
  rec.values = point_values(o, index);
  try {
    toml::table doc = toml::parse(plan.text, plan.file);  // the worker's own document
    Scene scene = point_scene(plan, o, doc, rec.values);
    RunControls controls;
    controls.write_outputs = false;
    std::optional<FirstTimes> first;
    if (!o.first_times.empty()) {
      first.emplace(scene, o);
      controls.on_sample = [&first](const SampleRow& row) { (*first)(row); };
    }
    const RunResult r = run(scene, controls);
    const RunReport& rep = r.report;
    rec.coordinates = rep.coordinates;
    rec.q = r.q_final;
    rec.qd = r.qd_final;
    rec.t_final = rep.t_final;
    rec.energy_drift_max = rep.energy_drift_max;
    rec.energy_drift_final = rep.energy_drift_final;
    rec.energy_drift_relative_to_initial = rep.energy_drift_relative_to_initial();
    rec.impact_energy_loss = rep.impact_energy_loss;
    rec.has_reference = rep.has_reference;
    rec.reference_error_final = rep.reference_error_final;
    rec.steps = rep.steps;
    rec.rejected_steps = rep.rejected_steps;
    rec.rhs_evaluations = rep.rhs_evaluations;
    rec.wall_time_s = rep.wall_time_s;
    for (const EventRecord& e : rep.events) {
      SweepRecord::EventGroup& g = rec.events[e.kind == EventKind::watched ? e.name : to_string(e.kind)];
      if (g.count == 0) g.first = e.t;
      g.last = e.t;
      ++g.count;
    }
    if (first) rec.first_times = first->times();
    if (o.wants("chaos")) {
      const LyapunovRun chaos = lyapunov(scene, LyapunovRequest{1, 0.0});
      rec.lyapunov_max = chaos.result.spectrum.front();
      rec.megno = chaos.result.megno_mean;
    }
  } catch (const std::exception& e) {
    std::string msg = e.what();
    std::replace(msg.begin(), msg.end(), '\n', ' ');
    rec.status = "failed: " + msg;
    rec.values.resize(o.vary.size() + o.set.size(), kNaN);
  }
  return rec;
}

}  // namespace lagrangian::scene::detail

namespace lagrangian::scene::detail {
namespace {

// -- serialization between ranks ---------------------------------------------------

constexpr char kField = '\x1f', kRecord = '\x1e';

void put(std::string& out, double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest text that reads back exactly
  out.append(buf, r.ptr);
  out += kField;
}
void put(std::string& out, std::uint64_t v) {
  out += std::to_string(v);
  out += kField;
}
void put(std::string& out, std::string s) {
  std::replace(s.begin(), s.end(), kField, ' ');
  std::replace(s.begin(), s.end(), kRecord, ' ');
  out += s;
  out += kField;
}

}  // namespace

std::string serialize(std::uint64_t index, const SweepRecord& r) {
  std::string out;
  put(out, index);
  put(out, r.status);
  put(out, static_cast<std::uint64_t>(r.values.size()));
  for (double v : r.values) put(out, v);
  put(out, static_cast<std::uint64_t>(r.coordinates.size()));
  for (std::size_t k = 0; k < r.coordinates.size(); ++k) {
    put(out, r.coordinates[k]);
    put(out, k < r.q.size() ? r.q[k] : kNaN);
    put(out, k < r.qd.size() ? r.qd[k] : kNaN);
  }
  for (double v : {r.t_final, r.energy_drift_max, r.energy_drift_final, r.energy_drift_relative_to_initial,
                   r.impact_energy_loss, r.reference_error_final, r.wall_time_s})
    put(out, v);
  put(out, static_cast<std::uint64_t>(r.has_reference));
  for (std::uint64_t v : {r.steps, r.rejected_steps, r.rhs_evaluations}) put(out, v);
  put(out, static_cast<std::uint64_t>(r.events.size()));
  for (const auto& [name, g] : r.events) {
    put(out, name);
    put(out, g.count);
    put(out, g.first);
    put(out, g.last);
  }
  put(out, static_cast<std::uint64_t>(r.first_times.size()));
  for (double v : r.first_times) put(out, v);
  put(out, r.lyapunov_max);
  put(out, r.megno);
  out += kRecord;
  return out;
}

namespace {

class Reader {
 public:
  explicit Reader(const std::string& s) : s_(s) {}
  bool more() const { return pos_ < s_.size(); }
  std::string text() {
    const std::size_t end = s_.find(kField, pos_);
    if (end == std::string::npos) throw std::runtime_error("sweep: malformed results from a rank");
    std::string out = s_.substr(pos_, end - pos_);
    pos_ = end + 1;
    return out;
  }
  double number() {
    const std::string t = text();
    double v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc()) {
      if (t.find("nan") != std::string::npos) return kNaN;
      if (t.find("inf") != std::string::npos) return t[0] == '-' ? -INFINITY : INFINITY;
      throw std::runtime_error("sweep: malformed number from a rank: " + t);
    }
    return v;
  }
  std::uint64_t count() { return std::stoull(text()); }
  void end_record() {
    if (pos_ >= s_.size() || s_[pos_] != kRecord) throw std::runtime_error("sweep: malformed record from a rank");
    ++pos_;
  }

 private:
  const std::string& s_;
  std::size_t pos_ = 0;
};

}  // namespace

void deserialize(const std::string& text, std::vector<SweepRecord>& slots, std::vector<bool>& filled) {
  Reader in(text);
  while (in.more()) {
    const std::uint64_t index = in.count();
    if (index >= slots.size()) throw std::runtime_error("sweep: a rank sent point " + std::to_string(index));
    SweepRecord r;
    r.status = in.text();
    r.values.resize(in.count());
    for (double& v : r.values) v = in.number();
    const std::uint64_t n = in.count();
    for (std::uint64_t k = 0; k < n; ++k) {
      r.coordinates.push_back(in.text());
      r.q.push_back(in.number());
      r.qd.push_back(in.number());
    }
    for (double* v : {&r.t_final, &r.energy_drift_max, &r.energy_drift_final, &r.energy_drift_relative_to_initial,
                      &r.impact_energy_loss, &r.reference_error_final, &r.wall_time_s})
      *v = in.number();
    r.has_reference = in.count() != 0;
    for (std::uint64_t* v : {&r.steps, &r.rejected_steps, &r.rhs_evaluations}) *v = in.count();
    const std::uint64_t groups = in.count();
    for (std::uint64_t k = 0; k < groups; ++k) {
      const std::string name = in.text();
      SweepRecord::EventGroup& g = r.events[name];
      g.count = in.count();
      g.first = in.number();
      g.last = in.number();
    }
    r.first_times.resize(in.count());
    for (double& v : r.first_times) v = in.number();
    r.lyapunov_max = in.number();
    r.megno = in.number();
    in.end_record();
    // Coordinates that a run without a final state left empty: q, qd stay empty.
    if (n == 0) {
      r.q.clear();
      r.qd.clear();
    }
    slots[index] = std::move(r);
    filled[index] = true;
  }
}

}  // namespace lagrangian::scene::detail
