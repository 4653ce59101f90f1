// `lagrangian completion bash|zsh`: prints the shell completion script made
// from the application's own subcommands and options (completion.hpp).

#include <iostream>

#include "commands.hpp"
#include "completion.hpp"

namespace lagrangian::cli {

const Subcommand CompletionScriptCommand::kInfo{"completion",
                               "Print a shell completion script: source <(lagrangian completion bash), or zsh"};

void CompletionScriptCommand::declare(OptionList& o) {
  o.positional("shell", shell_, "the shell: bash or zsh", true);
}

int CompletionScriptCommand::run() const {
  if (shell_ == "bash") {
    std::cout << bash_completion(*app_);
  } else if (shell_ == "zsh") {
    std::cout << zsh_completion(*app_);
  } else {
    std::cerr << "lagrangian: completion: unknown shell '" << shell_ << "' (bash and zsh are supported)\n";
    return kBadInput;
  }
  return kOk;
}

}  // namespace lagrangian::cli
