#pragma once
// `lagrangian completion bash`: a bash completion script made from the
// command's own subcommands and options, so that it cannot fall behind them.

#include <string>

#include <CLI/CLI.hpp>

namespace lagrangian::cli {

/// The script: completes subcommands; each subcommand's options; scene files
/// (*.toml, directories) where a scene is expected; the steppers after
/// --method (and in --methods lists); directories after --out; .mp4, .webm
/// and .gif files after --animate-to; built-in models after `list`.
/// Options that take another value complete to nothing. Load it with
/// `source <(lagrangian completion bash)`, or install it as
/// /etc/bash_completion.d/lagrangian.
std::string bash_completion(const CLI::App& app);

}  // namespace lagrangian::cli
