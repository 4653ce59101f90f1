#pragma once
// Internal: finding gnuplot and running a plot script with it, its images
// renamed into place only when gnuplot succeeded.

#include <filesystem>
#include <string>
#include <vector>

#include "lagrangian/scene/plots.hpp"

namespace lagrangian::plots_detail {

namespace fs = std::filesystem;

/// gnuplot is on PATH and runs: its path, else "".
std::string working_gnuplot();

/// gnuplot's path when it runs and an image format is enabled; otherwise ""
/// with result.message saying why nothing will be drawn.
std::string gnuplot_for(bool png, bool svg, PlotResult& result);

// Runs gnuplot on `script` in `dir`; the script writes each image as
// <name>.partial.<ext> (its variable `suffix`), renamed here only when
// gnuplot succeeded. Fills result.files (images, then the script) and
// result.message; on failure removes every image of this call and throws.
void run_script(const std::string& exe, const fs::path& dir, const fs::path& script,
                const std::vector<std::string>& names, bool png, bool svg, PlotResult& result);

}  // namespace lagrangian::plots_detail
