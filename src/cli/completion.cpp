// What the completion scripts offer, read from the CLI11 application and
// from the library's own lists of names.

#include "completion.hpp"

#include <CLI/CLI.hpp>

#include <algorithm>

#include "lagrangian/integrate/discrete.hpp"
#include "lagrangian/integrate/report.hpp"
#include "lagrangian/scene/models.hpp"
#include "lagrangian/scene/sweep.hpp"

namespace lagrangian::cli {
namespace {

using Kind = CompletionValues::Kind;

/// A help text up to its first clause (". ", ": ", "; ", " (" or ", e.g."),
/// for a one-line description in a menu.
std::string first_clause(const std::string& text) {
  std::size_t end = text.size();
  for (const char* stop : {". ", ": ", "; ", " (", ", e.g.", ".\n"}) end = std::min(end, text.find(stop));
  std::string out = text.substr(0, end);
  std::replace(out.begin(), out.end(), '\n', ' ');
  return out;
}

/// The steppers `--method` accepts: stepper_names() and event_driven.
std::vector<std::string> method_words() {
  std::vector<std::string> methods = stepper_names();
  methods.push_back("event_driven");
  return methods;
}

/// What may follow the option named `name` (its long name, "--method").
CompletionValues option_values(const std::string& name) {
  if (name == "--method") return {Kind::words, method_words()};
  if (name == "--methods") return {Kind::word_list, method_words()};
  if (name == "--stabilization")
    return {Kind::words,
            {to_string(Stabilization::none), to_string(Stabilization::baumgarte),
             to_string(Stabilization::projection)}};
  if (name == "--rule") return {Kind::words, {to_string(DiscreteRule::midpoint), to_string(DiscreteRule::trapezoidal)}};
  if (name == "--output") return {Kind::word_list, scene::SweepOptions::output_groups()};
  if (name == "--out") return {Kind::directory, {}};
  if (name == "--animate-to") return {Kind::video, {}};
  return {};
}

/// What fills the positional argument of the subcommand `command`.
CompletionValues positional_values(const std::string& command) {
  if (command == "list") {
    std::vector<std::string> models;
    for (const auto& m : scene::builtin_models()) models.push_back(m.name);
    return {Kind::words, models};
  }
  if (command == "completion") return {Kind::words, completion_shells()};
  return {Kind::scene, {}};
}

/// The options of `app` (not its positionals), each name once, --help first.
std::vector<CompletionOption> options_of(const CLI::App& app) {
  std::vector<CompletionOption> options;
  std::vector<std::string> seen;
  const CLI::Option* help = app.get_help_ptr();
  std::vector<const CLI::Option*> all = app.get_options([](const CLI::Option*) { return true; });
  std::stable_partition(all.begin(), all.end(), [&](const CLI::Option* o) { return o == help; });
  for (const CLI::Option* opt : all) {
    if (opt->get_positional()) continue;
    CompletionOption o;
    for (const std::string& l : opt->get_lnames()) o.names.push_back("--" + l);
    for (const std::string& s : opt->get_snames()) o.names.push_back("-" + s);
    std::erase_if(o.names, [&](const std::string& n) { return std::find(seen.begin(), seen.end(), n) != seen.end(); });
    if (o.names.empty()) continue;
    seen.insert(seen.end(), o.names.begin(), o.names.end());
    o.takes_value = opt->get_expected_max() != 0;
    o.repeatable = opt->get_expected_max() > 1;
    o.help = first_clause(opt->get_description());
    if (o.takes_value) o.values = option_values(o.names.front());
    options.push_back(std::move(o));
  }
  return options;
}

}  // namespace

std::vector<std::string> completion_shells() { return {"bash", "zsh"}; }

CompletionSpec completion_spec(const CLI::App& app) {
  CompletionSpec spec;
  spec.top_options = options_of(app);
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) {
    CompletionCommand c;
    c.name = sub->get_name();
    c.help = first_clause(sub->get_description());
    c.options = options_of(*sub);
    c.positional = positional_values(c.name);
    spec.commands.push_back(std::move(c));
  }
  return spec;
}

}  // namespace lagrangian::cli
