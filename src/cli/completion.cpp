// The bash completion script, written from the CLI11 application.

#include "completion.hpp"

#include <sstream>
#include <vector>

#include "lagrangian/report.hpp"
#include "lagrangian/scene_models.hpp"

namespace lagrangian::cli {
namespace {

std::string words(const std::vector<std::string>& list) {
  std::string out;
  for (const std::string& w : list) out += (out.empty() ? "" : " ") + w;
  return out;
}

}  // namespace

std::string bash_completion(const CLI::App& app) {
  std::vector<std::string> subs, valued;  // subcommands; options that take a value
  std::ostringstream cases;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    subs.push_back(sub->get_name());
    std::vector<std::string> opts{"--help"};
    for (const CLI::Option* opt : sub->get_options([](const CLI::Option*) { return true; })) {
      if (opt->get_positional()) continue;
      const bool flag = opt->get_expected_max() == 0;  // takes no value
      for (const std::string& l : opt->get_lnames()) {
        opts.push_back("--" + l);
        if (!flag) valued.push_back("--" + l);
      }
      for (const std::string& s : opt->get_snames()) {
        opts.push_back("-" + s);
        if (!flag) valued.push_back("-" + s);
      }
    }
    cases << "    " << sub->get_name() << ") opts=\"" << words(opts) << "\" ;;\n";
  }
  std::vector<std::string> models;
  for (const auto& m : scene::builtin_models()) models.push_back(m.name);
  std::vector<std::string> methods = stepper_names();
  methods.push_back("event_driven");

  std::string pattern;  // the subcommands as a case pattern
  for (const std::string& s : subs) pattern += (pattern.empty() ? "" : "|") + s;

  std::ostringstream rest;
  rest << "# bash completion for lagrangian, written by `lagrangian completion bash`.\n"
       << "# Load: source <(lagrangian completion bash)\n"
       << "_lagrangian() {\n"
       << "  local cur=\"${COMP_WORDS[COMP_CWORD]}\" prev=\"${COMP_WORDS[COMP_CWORD-1]}\" cmd=\"\" w opts\n"
       << "  for w in \"${COMP_WORDS[@]:1:COMP_CWORD-1}\"; do\n"
       << "    case \"$w\" in " << pattern << ") cmd=\"$w\"; break ;; esac\n"
       << "  done\n";
  rest << "  if [ -z \"$cmd\" ]; then\n"
       << "    COMPREPLY=($(compgen -W \"" << words(subs) << " --help --version\" -- \"$cur\"))\n"
       << "    return\n"
       << "  fi\n"
       << "  case \"$prev\" in\n"
       << "    --method|--methods) COMPREPLY=($(compgen -W \"" << words(methods) << "\" -- \"${cur##*,}\"))\n"
       << "      [ \"$prev\" = --methods ] && [[ \"$cur\" == *,* ]] && COMPREPLY=(\"${COMPREPLY[@]/#/${cur%,*},}\")\n"
       << "      return ;;\n"
       << "    --out) mapfile -t COMPREPLY < <(compgen -d -- \"$cur\"); return ;;\n"
       << "    --animate-to) mapfile -t COMPREPLY < <(compgen -f -X '!*.@(mp4|webm|gif)' -- \"$cur\"; compgen -d -- "
          "\"$cur\");"
          " return ;;\n";
  std::string value_pattern;
  for (const std::string& v : valued)
    if (v != "--method" && v != "--methods" && v != "--out" && v != "--animate-to")
      value_pattern += (value_pattern.empty() ? "" : "|") + v;
  if (!value_pattern.empty()) rest << "    " << value_pattern << ") COMPREPLY=(); return ;;\n";
  rest << "  esac\n"
       << "  case \"$cmd\" in\n"
       << cases.str() << "  esac\n"
       << "  if [[ \"$cur\" == -* ]]; then\n"
       << "    COMPREPLY=($(compgen -W \"$opts\" -- \"$cur\"))\n"
       << "  elif [ \"$cmd\" = list ]; then\n"
       << "    COMPREPLY=($(compgen -W \"" << words(models) << "\" -- \"$cur\"))\n"
       << "  elif [ \"$cmd\" != completion ]; then\n"
       << "    mapfile -t COMPREPLY < <(compgen -f -X '!*.toml' -- \"$cur\"; compgen -d -- \"$cur\")\n"
       << "  else\n"
       << "    COMPREPLY=($(compgen -W \"bash\" -- \"$cur\"))\n"
       << "  fi\n"
       << "}\n"
       << "shopt -s extglob\n"
       << "complete -o filenames -F _lagrangian lagrangian\n";
  return rest.str();
}

}  // namespace lagrangian::cli
