// The bash completion script, written from completion_spec().

#include <algorithm>
#include <sstream>
#include <vector>

#include "completion.hpp"

namespace lagrangian::cli {
namespace {

using Kind = CompletionValues::Kind;

std::string words(const std::vector<std::string>& list) {
  std::string out;
  for (const std::string& w : list) out += (out.empty() ? "" : " ") + w;
  return out;
}

/// The bash commands that fill COMPREPLY with `values` for the word $cur.
std::string reply(const CompletionValues& values) {
  switch (values.kind) {
    case Kind::words: return "COMPREPLY=($(compgen -W \"" + words(values.words) + "\" -- \"$cur\"))";
    case Kind::word_list:  // complete the last item, keep the ones before it
      return "COMPREPLY=($(compgen -W \"" + words(values.words) +
             "\" -- \"${cur##*,}\")); [[ \"$cur\" == *,* ]] && COMPREPLY=(\"${COMPREPLY[@]/#/${cur%,*},}\")";
    case Kind::directory: return "mapfile -t COMPREPLY < <(compgen -d -- \"$cur\")";
    case Kind::video:
      return "mapfile -t COMPREPLY < <(compgen -f -X '!*.@(mp4|webm|gif)' -- \"$cur\"; compgen -d -- \"$cur\")";
    case Kind::scene:
      return "mapfile -t COMPREPLY < <(compgen -f -X '!*.toml' -- \"$cur\"; compgen -d -- \"$cur\")";
    case Kind::none: break;
  }
  return "COMPREPLY=()";
}

}  // namespace

std::string bash_completion(const CLI::App& app) {
  const CompletionSpec spec = completion_spec(app);
  std::vector<std::string> subs, top;
  for (const CompletionCommand& c : spec.commands) subs.push_back(c.name);
  for (const CompletionOption& o : spec.top_options) top.insert(top.end(), o.names.begin(), o.names.end());

  // Each option that takes a value, once, with what follows it (an option
  // has the same values in every subcommand that has it).
  std::vector<std::string> valued;
  std::ostringstream value_cases;
  for (const CompletionCommand& c : spec.commands)
    for (const CompletionOption& o : c.options) {
      if (!o.takes_value) continue;
      std::string pattern;
      for (const std::string& n : o.names) {
        if (std::find(valued.begin(), valued.end(), n) != valued.end()) continue;
        valued.push_back(n);
        pattern += (pattern.empty() ? "" : "|") + n;
      }
      if (!pattern.empty()) value_cases << "    " << pattern << ") " << reply(o.values) << "; return ;;\n";
    }

  std::ostringstream option_cases, positional_cases;
  for (const CompletionCommand& c : spec.commands) {
    std::vector<std::string> opts;
    for (const CompletionOption& o : c.options) opts.insert(opts.end(), o.names.begin(), o.names.end());
    option_cases << "    " << c.name << ") opts=\"" << words(opts) << "\" ;;\n";
    positional_cases << "    " << c.name << ") " << reply(c.positional) << " ;;\n";
  }

  std::string pattern;  // the subcommands as a case pattern
  for (const std::string& s : subs) pattern += (pattern.empty() ? "" : "|") + s;

  std::ostringstream out;
  out << "# bash completion for lagrangian, written by `lagrangian completion bash`.\n"
      << "# Load: source <(lagrangian completion bash)\n"
      << "_lagrangian() {\n"
      << "  local cur=\"${COMP_WORDS[COMP_CWORD]}\" prev=\"${COMP_WORDS[COMP_CWORD-1]}\" cmd=\"\" w opts\n"
      << "  for w in \"${COMP_WORDS[@]:1:COMP_CWORD-1}\"; do\n"
      << "    case \"$w\" in " << pattern << ") cmd=\"$w\"; break ;; esac\n"
      << "  done\n"
      << "  if [ -z \"$cmd\" ]; then\n"
      << "    COMPREPLY=($(compgen -W \"" << words(subs) << " " << words(top) << "\" -- \"$cur\"))\n"
      << "    return\n"
      << "  fi\n"
      << "  case \"$prev\" in\n"
      << value_cases.str() << "  esac\n"
      << "  case \"$cmd\" in\n"
      << option_cases.str() << "  esac\n"
      << "  if [[ \"$cur\" == -* ]]; then\n"
      << "    COMPREPLY=($(compgen -W \"$opts\" -- \"$cur\"))\n"
      << "    return\n"
      << "  fi\n"
      << "  case \"$cmd\" in\n"
      << positional_cases.str() << "  esac\n"
      << "}\n"
      << "shopt -s extglob\n"
      << "complete -o filenames -F _lagrangian lagrangian\n";
  return out.str();
}

}  // namespace lagrangian::cli
