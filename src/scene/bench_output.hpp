#pragma once
// Internal to `lagrangian bench` (bench.cpp): its output files, the machine
// description, and the number format of its messages.

#include <filesystem>
#include <string>

#include "lagrangian/scene/bench.hpp"
#include "lagrangian/scene/scene.hpp"

namespace lagrangian::scene::detail::bench {

/// v in printf's `format`, or "nan" when not finite.
std::string fmt(double v, const char* format = "%.6g");

/// CPU, cores, compiler and build, the load average before (given) and
/// after (now), and the date (UTC).
std::string machine_description(const std::string& load_before);

/// The text after "key:" on the first line of the file at `path` that
/// starts with `key` ("" when none): the CPU's "model name" in /proc/cpuinfo.
std::string read_first_line_with(const char* path, const std::string& key);

/// The one-minute load average from /proc/loadavg.
std::string load_average();

/// Removes everything a bench writes from `dir` (and their .partial files).
void remove_outputs(const std::filesystem::path& dir);

/// work_precision.csv: one row per run, with the error measure, the
/// reference and the machine in its comments.
std::string csv_text(const Scene& scene, const BenchResult& r);

/// bench.json: the settings, the reference and every run.
std::string json_text(const Scene& scene, const BenchOptions& o, const BenchResult& r);

}  // namespace lagrangian::scene::detail::bench
