#pragma once
// The "wrote: …" line the commands print after a run, a bench or a sweep.

#include <filesystem>
#include <iostream>
#include <string>
#include <system_error>
#include <vector>

namespace lagrangian::cli {

/// How a command names a file it wrote: relative to the working directory
/// when the file is inside it ("out/report.json"), absolute otherwise, the
/// same rule for every file of one list, however each path was given.
inline std::string shown_path(const std::string& file) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path absolute = fs::absolute(file, ec).lexically_normal();
  if (ec) return file;
  const fs::path cwd = fs::current_path(ec);
  if (ec) return absolute.string();
  const fs::path relative = absolute.lexically_relative(cwd);
  if (!relative.empty() && *relative.begin() != "..") return relative.string();
  return absolute.string();
}

/// "wrote: a b c" on standard output, each path as shown_path() names it.
inline void print_written(const std::vector<std::string>& files) {
  std::cout << "wrote:";
  for (const auto& f : files) std::cout << " " << shown_path(f);
  std::cout << "\n";
}

}  // namespace lagrangian::cli
