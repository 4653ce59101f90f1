#pragma once
// The `sweep` subcommand, shared by `lagrangian` (threads on one machine)
// and `lagrangian-mpi` (MPI ranks, each with its threads).

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "lagrangian/scene/sweep.hpp"

namespace lagrangian::cli {

class SweepCommand {
 public:
  /// Adds the `sweep` subcommand and its options to `app`.
  CLI::App* add(CLI::App& app);
  /// Runs the parsed command on this rank; prints only on rank 0. Returns
  /// the exit code: 0 every run succeeded, 1 some runs failed (their rows
  /// say why) or the sweep failed, 2 bad input.
  int run(int rank = 0, int ranks = 1, std::function<std::string(const std::string&)> gather = {});
  /// The message of the error that ended run(), if one did (printed there on rank 0 only).
  const std::string& error() const { return error_; }

 private:
  std::string scene_path_;
  std::vector<std::string> vary_, set_, first_time_;
  std::optional<long long> monte_carlo_;
  long long seed_ = 1;
  std::optional<int> threads_;
  std::optional<std::string> outputs_, plot_, out_dir_;
  bool no_plots_ = false, quiet_ = false;
  std::string error_;
  int fail(bool speak, const std::string& message, int code);
};

}  // namespace lagrangian::cli
