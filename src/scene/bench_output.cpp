// What a bench writes: work_precision.csv, bench.json, the machine it ran on,
// and the removal of them all (bench_output.hpp).

#include "bench_output.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <utility>

#include "lagrangian/detail/text_output.hpp"

namespace lagrangian::scene::detail::bench {

namespace fs = std::filesystem;

std::string fmt(double v, const char* format) {
  if (!std::isfinite(v)) return "nan";
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string json_number(double v) {
  if (!std::isfinite(v)) return "null";
  return fmt(v, "%.17g");
}

/// Everything a bench writes (removed before a bench starts and when it fails).
constexpr const char* kOutputs[] = {"work_precision.csv",        "bench.json",                "bench.gp",
                                    "work_precision_time.png",   "work_precision_time.svg",   "work_precision_rhs.png",
                                    "work_precision_rhs.svg",    "work_precision_energy.png", "work_precision_energy.svg"};

}  // namespace

std::string read_first_line_with(const char* path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      const auto colon = line.find(':');
      if (colon == std::string::npos) return {};
      std::string v = line.substr(colon + 1);
      while (!v.empty() && v.front() == ' ') v.erase(v.begin());
      return v;
    }
  return {};
}

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  double one = kNaN;
  in >> one;
  return fmt(one, "%.2f");
}

/// CPU, cores, compiler and build, the load average and the date (UTC).
std::string machine_description(const std::string& load_before) {
  std::string cpu = read_first_line_with("/proc/cpuinfo", "model name");
  if (cpu.empty()) cpu = "unknown CPU";
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  std::string out = cpu + ", " + std::to_string(std::thread::hardware_concurrency()) + " hardware threads; ";
#if defined(__clang__)
  out += "clang " __clang_version__;
#elif defined(__GNUC__)
  out += "g++ " __VERSION__;
#endif
#ifdef NDEBUG
  out += " (optimised build)";
#else
  out += " (assertions on: not an optimised build)";
#endif
  out += "; load average " + load_before + " before, " + load_average() + " after; " + date;
  return out;
}

void remove_outputs(const fs::path& dir) {
  std::error_code ec;
  for (const char* name : kOutputs) {
    fs::remove(dir / name, ec);
    fs::remove(dir / (std::string(name) + ".partial"), ec);
  }
}

std::string csv_text(const Scene& scene, const BenchResult& r) {
  std::ostringstream os;
  os << "# work-precision data of scene '" << scene.name << "' (lagrangian bench)\n"
     << "# error: " << r.error_measure << "\n";
  if (!r.reference.empty())
    os << "# reference: " << r.reference << "\n";
  for (const BenchPoint& p : r.points)
    if (p.is_reference)
      os << "# the row " << p.method << " rtol " << fmt(p.rtol, "%.3g")
         << " is the reference run itself: its error is the reference's estimate (resolved = 0)\n";
  for (const std::string& w : r.warnings) os << "# warning: " << w << "\n";
  os << "# wall_time_s: median of the repeats; machine: " << r.machine << "\n"
     << "method,adaptive,rtol,atol,dt,status,error,wall_time_s,wall_time_min_s,wall_time_max_s,repeats,steps,"
        "rejected_steps,rhs_evaluations,energy_drift,momentum_drift,constraint_residual,t_final,resolved\n";
  for (const BenchPoint& p : r.points) {
    std::string status = p.status;
    std::replace(status.begin(), status.end(), ',', ';');
    std::replace(status.begin(), status.end(), '\n', ' ');
    const bool ok = p.ok();
    os << p.method << "," << (p.adaptive ? 1 : 0) << "," << (p.adaptive ? fmt(p.rtol, "%.3g") : "") << ","
       << (p.adaptive ? fmt(p.atol, "%.3g") : "") << "," << (p.adaptive ? "" : fmt(p.dt, "%.6g")) << "," << status
       << "," << (ok ? fmt(p.error, "%.6e") : "") << "," << (ok ? fmt(p.wall_time_s, "%.6e") : "") << ","
       << (ok ? fmt(p.wall_time_min_s, "%.6e") : "") << "," << (ok ? fmt(p.wall_time_max_s, "%.6e") : "") << ","
       << p.repeats << "," << p.steps << "," << p.rejected_steps << "," << p.rhs_evaluations << ","
       << (ok && std::isfinite(p.energy_drift) ? fmt(p.energy_drift, "%.6e") : "") << ","
       << (ok && std::isfinite(p.momentum_drift) ? fmt(p.momentum_drift, "%.6e") : "") << ","
       << (ok && std::isfinite(p.constraint_residual) ? fmt(p.constraint_residual, "%.6e") : "") << ","
       << (ok ? fmt(p.t_final, "%.12g") : "") << "," << (p.resolved ? 1 : 0) << "\n";
  }
  return os.str();
}

std::string json_text(const Scene& scene, const BenchOptions& o, const BenchResult& r) {
  using lagrangian::detail::json_string;
  std::ostringstream os;
  os << "{\n  \"scene\": ";
  json_string(os, scene.name);
  os << ",\n  \"engine\": ";
  json_string(os, r.engine);
  os << ",\n  \"t0\": " << json_number(scene.run.t0) << ", \"t_end\": " << json_number(scene.run.t_end);
  os << ",\n  \"closed_form\": " << (r.closed_form ? "true" : "false") << ",\n  \"error_measure\": ";
  json_string(os, r.error_measure);
  os << ",\n  \"reference_kind\": ";
  json_string(os, r.reference_kind);
  os << ",\n  \"reference\": ";
  json_string(os, r.reference);
  os << ",\n  \"reference_accuracy\": " << json_number(r.reference_accuracy)
     << ",\n  \"reference_time_s\": " << json_number(r.reference_time_s);
  for (const auto& [key, v] : {std::pair{"reference_q", &r.reference_q}, std::pair{"reference_qd", &r.reference_qd}}) {
    os << ",\n  \"" << key << "\": [";
    for (std::size_t k = 0; k < v->size(); ++k) os << (k ? ", " : "") << json_number((*v)[k]);
    os << "]";
  }
  os << ",\n  \"warnings\": [";
  for (std::size_t k = 0; k < r.warnings.size(); ++k) {
    if (k) os << ", ";
    json_string(os, r.warnings[k]);
  }
  os << "]";
  os << ",\n  \"machine\": ";
  json_string(os, r.machine);
  os << ",\n  \"settings\": {\"methods\": [";
  for (std::size_t k = 0; k < o.methods.size(); ++k) {
    if (k) os << ", ";
    json_string(os, std::string(to_string(o.methods[k])));
  }
  os << "], \"tolerance_loose\": " << json_number(o.tolerance_loose)
     << ", \"tolerance_tight\": " << json_number(o.tolerance_tight) << ", \"per_decade\": " << o.per_decade
     << ", \"repeat\": " << o.repeat << ", \"reference_tolerance\": " << json_number(o.reference_tolerance)
     << "},\n  \"points\": [";
  for (std::size_t k = 0; k < r.points.size(); ++k) {
    const BenchPoint& p = r.points[k];
    os << (k ? ",\n" : "\n") << "    {\"method\": ";
    json_string(os, p.method);
    os << ", \"adaptive\": " << (p.adaptive ? "true" : "false") << ", \"rtol\": " << json_number(p.rtol)
       << ", \"atol\": " << json_number(p.atol) << ", \"dt\": " << json_number(p.dt) << ", \"status\": ";
    json_string(os, p.status);
    const bool ok = p.ok();
    os << ", \"error\": " << json_number(ok ? p.error : kNaN)
       << ", \"wall_time_s\": " << json_number(ok ? p.wall_time_s : kNaN)
       << ", \"wall_time_min_s\": " << json_number(ok ? p.wall_time_min_s : kNaN)
       << ", \"wall_time_max_s\": " << json_number(ok ? p.wall_time_max_s : kNaN) << ", \"repeats\": " << p.repeats
       << ", \"steps\": " << p.steps << ", \"rejected_steps\": " << p.rejected_steps
       << ", \"rhs_evaluations\": " << p.rhs_evaluations
       << ", \"energy_drift\": " << json_number(ok ? p.energy_drift : kNaN)
       << ", \"momentum_drift\": " << json_number(ok ? p.momentum_drift : kNaN)
       << ", \"constraint_residual\": " << json_number(ok ? p.constraint_residual : kNaN)
       << ", \"t_final\": " << json_number(ok ? p.t_final : kNaN)
       << ", \"resolved\": " << (p.resolved ? "true" : "false")
       << ", \"is_reference\": " << (p.is_reference ? "true" : "false") << "}";
  }
  os << "\n  ]\n}\n";
  return os.str();
}

}  // namespace lagrangian::scene::detail::bench
