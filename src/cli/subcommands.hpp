#pragma once
// The subcommand a command line names, checked before CLI11 parses it: a
// mistyped or foreign subcommand gets a sentence naming it and the ones
// there are, instead of CLI11's "A subcommand is required".

#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "lagrangian/scene/scene.hpp"

namespace lagrangian::cli {

/// The names of app's subcommands, in the order they were added.
inline std::vector<std::string> subcommand_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names.push_back(sub->get_name());
  return names;
}

/// The first argument that is not an option, when it names none of app's
/// subcommands (the top-level options take no values).
inline std::optional<std::string> unknown_subcommand(const CLI::App& app, int argc, char** argv) {
  const std::vector<std::string> names = subcommand_names(app);
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.empty() || arg[0] == '-') continue;
    for (const std::string& name : names)
      if (name == arg) return std::nullopt;
    return arg;
  }
  return std::nullopt;
}

/// "unknown subcommand 'X'; the subcommands are: a, b, c (did you mean 'b'?)".
inline std::string unknown_subcommand_message(const CLI::App& app, const std::string& word) {
  const std::vector<std::string> names = subcommand_names(app);
  std::string list;
  for (const std::string& name : names) list += (list.empty() ? "" : ", ") + name;
  const std::string near = scene::nearest(word, names);
  return "unknown subcommand '" + word + "'; the subcommands are: " + list +
         (near.empty() ? std::string() : " (did you mean '" + near + "'?)");
}

}  // namespace lagrangian::cli
