#pragma once
// `lagrangian completion bash|zsh`: shell completion scripts made from the
// command's own subcommands and options, so that they cannot fall behind
// them. completion.cpp reads what to offer from the CLI11 application;
// completion_bash.cpp and completion_zsh.cpp write it in each shell's terms.

#include <string>
#include <vector>


namespace CLI {
class App;
}

namespace lagrangian::cli {

/// What may follow an option, or fill a subcommand's positional argument.
struct CompletionValues {
  enum class Kind {
    none,       ///< anything (a number, KEY=VALUE): nothing is offered
    words,      ///< one of `words`
    word_list,  ///< comma-separated words from `words` (--methods a,b)
    directory,  ///< a directory (--out)
    video,      ///< a .mp4, .webm or .gif file (--animate-to)
    scene,      ///< a scene file, *.toml (or - for standard input)
  };
  Kind kind = Kind::none;
  std::vector<std::string> words;
};

/// One option of a subcommand, as completion offers it.
struct CompletionOption {
  std::vector<std::string> names;  ///< "--quiet", "-q": long names first, each once
  bool takes_value = false;        ///< false for flags
  bool repeatable = false;         ///< may be given more than once (--set)
  std::string help;                ///< its help text's first clause
  CompletionValues values;         ///< what may follow it (when takes_value)
};

/// One subcommand.
struct CompletionCommand {
  std::string name;
  std::string help;                       ///< its description's first clause
  std::vector<CompletionOption> options;  ///< --help first, in the order they were added
  CompletionValues positional;            ///< what its positional argument is
};

/// Everything a completion script offers: the subcommands with their
/// options and what their values are (steppers from stepper_names(),
/// stabilizations, discrete rules, sweep output groups, built-in models,
/// shells).
struct CompletionSpec {
  std::vector<CompletionCommand> commands;
  std::vector<CompletionOption> top_options;  ///< --help, --version
};

/// The shells `lagrangian completion SHELL` writes scripts for: bash, zsh.
std::vector<std::string> completion_shells();

/// What to offer, read from the application and the library's lists.
CompletionSpec completion_spec(const CLI::App& app);

/// The bash script: completes subcommands; each subcommand's options, each
/// once; scene files (*.toml, directories) where a scene is expected; the
/// fixed choices after --method, --stabilization, --rule (and in the
/// comma-separated --methods and --output lists); directories after --out;
/// .mp4, .webm and .gif files after --animate-to; built-in models after
/// `list`; shells after `completion`. Options that take another value
/// complete to nothing. Load it with `source <(lagrangian completion bash)`,
/// or install it as /etc/bash_completion.d/lagrangian.
std::string bash_completion(const CLI::App& app);

/// The zsh script, offering the same as bash_completion() with each
/// subcommand's and option's help text (zsh's _arguments). Load it with
/// `source <(lagrangian completion zsh)` after compinit, or save it as
/// `_lagrangian` in a directory of $fpath.
std::string zsh_completion(const CLI::App& app);

}  // namespace lagrangian::cli
