// The zsh completion script, written from completion_spec(): one
// _arguments specification per subcommand, with the help texts.

#include <sstream>
#include <vector>

#include "completion.hpp"

namespace lagrangian::cli {
namespace {

using Kind = CompletionValues::Kind;

/// `text` inside a single-quoted zsh word.
std::string sq(const std::string& text) {
  std::string out;
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out;
}

/// An option's description inside a single-quoted zsh word, its square
/// brackets escaped as _arguments reads them.
std::string description(const std::string& text) {
  std::string out;
  for (const char c : sq(text)) {
    if (c == '[' || c == ']') out += '\\';
    out += c;
  }
  return out;
}

std::string join(const std::vector<std::string>& list, const std::string& separator) {
  std::string out;
  for (const std::string& w : list) out += (out.empty() ? "" : separator) + w;
  return out;
}

/// The `:message:action` part of an _arguments specification.
std::string action(const std::string& message, const CompletionValues& values) {
  switch (values.kind) {
    case Kind::words: return ":" + message + ":(" + join(values.words, " ") + ")";
    case Kind::word_list: return ":" + message + ":_values -s , " + message + " " + join(values.words, " ");
    case Kind::directory: return ":" + message + ":_files -/";
    case Kind::video: return ":" + message + ":_files -g \"*.(mp4|webm|gif)\"";
    case Kind::scene: return ":" + message + ":_files -g \"*.toml\"";
    case Kind::none: break;
  }
  return ":" + message + ": ";  // a message only: nothing to offer
}

/// The _arguments specification of one option, e.g.
/// '(-q --quiet)'{-q,--quiet}'[print only errors]' or
/// '--method=[stepper]:method:(rk4 dopri5 ...)'. `alone`: the option ends
/// the command line (--help, --version).
std::string option_spec(const CompletionOption& o, bool alone) {
  std::string prefix;  // the options it excludes, then * when repeatable
  if (alone) prefix = "(- *)";
  else if (o.names.size() > 1) prefix = "(" + join(o.names, " ") + ")";
  if (o.repeatable) prefix += "*";
  std::string tail = std::string(o.takes_value ? "=" : "") + "[" + description(o.help) + "]";
  if (o.takes_value) tail += sq(action(o.names.front().substr(o.names.front().find_first_not_of('-')), o.values));
  if (o.names.size() == 1) return "'" + prefix + o.names.front() + tail + "'";
  return "'" + prefix + "'{" + join(o.names, ",") + "}'" + tail + "'";
}

/// The message of a subcommand's positional argument.
std::string positional_message(const std::string& command) {
  if (command == "list") return "model";
  if (command == "completion") return "shell";
  return "scene";
}

}  // namespace

std::string zsh_completion(const CLI::App& app) {
  const CompletionSpec spec = completion_spec(app);
  std::ostringstream out;
  out << "#compdef lagrangian\n"
      << "# zsh completion for lagrangian, written by `lagrangian completion zsh`.\n"
      << "# Load: source <(lagrangian completion zsh) after compinit, or save it as _lagrangian in a directory of\n"
      << "# $fpath.\n\n"
      << "_lagrangian() {\n"
      << "  local curcontext=\"$curcontext\" state line ret=1\n"
      << "  local -a commands\n"
      << "  commands=(\n";
  for (const CompletionCommand& c : spec.commands) out << "    '" << c.name << ":" << sq(c.help) << "'\n";
  out << "  )\n"
      << "  _arguments -C \\\n";
  for (const CompletionOption& o : spec.top_options) out << "    " << option_spec(o, true) << " \\\n";
  out << "    '1: :->command' \\\n"
      << "    '*:: :->argument' && ret=0\n"
      << "  case $state in\n"
      << "    command) _describe -t commands 'lagrangian subcommand' commands && ret=0 ;;\n"
      << "    argument)\n"
      << "      curcontext=\"${curcontext%:*:*}:lagrangian-$words[1]:\"\n"
      << "      case $words[1] in\n";
  for (const CompletionCommand& c : spec.commands) {
    out << "        " << c.name << ")\n"
        << "          _arguments \\\n";
    for (const CompletionOption& o : c.options)
      out << "            " << option_spec(o, o.names.front() == "--help") << " \\\n";
    out << "            '1" << sq(action(positional_message(c.name), c.positional)) << "' && ret=0 ;;\n";
  }
  out << "      esac ;;\n"
      << "  esac\n"
      << "  return ret\n"
      << "}\n\n"
      << "if [ \"$funcstack[1]\" = \"_lagrangian\" ]; then\n"
      << "  _lagrangian \"$@\"\n"
      << "else\n"
      << "  compdef _lagrangian lagrangian\n"
      << "fi\n";
  return out.str();
}

}  // namespace lagrangian::cli
