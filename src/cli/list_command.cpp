// `lagrangian list [MODEL]`: the built-in models and the example scenes, or
// one model's coordinates (with units) and parameters (with defaults).

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <vector>

#include "commands.hpp"
#include "lagrangian/scene/io.hpp"
#include "lagrangian/scene/models.hpp"

namespace fs = std::filesystem;

namespace lagrangian::cli {
namespace {

/// Directories searched for the example scenes: $LAGRANGIAN_SCENES, the
/// installed share/lagrangian/scenes beside the executable, the source tree's.
std::vector<fs::path> scene_dirs() {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("LAGRANGIAN_SCENES")) dirs.emplace_back(env);
  std::error_code ec;
  const fs::path exe = fs::canonical("/proc/self/exe", ec);
  if (!ec) dirs.push_back(exe.parent_path().parent_path() / "share" / "lagrangian" / "scenes");
#ifdef LAGRANGIAN_SOURCE_SCENES
  dirs.emplace_back(LAGRANGIAN_SOURCE_SCENES);
#endif
  return dirs;
}

int list_model(const std::string& name) {
  const scene::ModelInfo* m = scene::find_model(name);
  if (!m) {
    std::vector<std::string> names;
    for (const auto& info : scene::builtin_models()) names.push_back(info.name);
    const std::string near = scene::nearest(name, names);
    std::cerr << "lagrangian: list: unknown model '" << name << "'"
              << (near.empty() ? std::string() : "; did you mean '" + near + "'?")
              << " (`lagrangian list` names them all)\n";
    return kBadInput;
  }
  std::cout << m->name << ": " << m->description << "\n\ncoordinates (q, in this order; qd in their units per second):\n";
  for (std::size_t i = 0; i < m->coordinates.size(); ++i)
    std::printf("  %-12s %s\n", m->coordinates[i].c_str(), i < m->units.size() ? m->units[i].c_str() : "");
  std::cout << "\nparameters ([model.parameters]; default, unit, meaning):\n";
  if (m->parameters.empty()) std::cout << "  (none)\n";
  for (const auto& p : m->parameters)
    std::printf("  %-12s %-14.12g %-10s %s\n", p.name.c_str(), p.default_value, p.unit.c_str(), p.description.c_str());
  return kOk;
}

int list_all() {
  std::cout << "Built-in models (use in a scene as [model] name = \"...\"):\n";
  for (const auto& m : scene::builtin_models()) std::printf("  %-28s %s\n", m.name.c_str(), m.description.c_str());
  for (const fs::path& dir : scene_dirs()) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) continue;
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir, ec))
      if (e.path().extension() == ".toml") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    std::cout << "\nExample scenes (" << dir.string() << "):\n";
    for (const auto& f : files) {
      std::string what;
      try {
        const scene::Scene s = scene::load_scene(f.string());
        what = s.description.empty() ? s.name : s.description;
      } catch (const Error& e) {
        what = std::string("(does not load: ") + e.what() + ")";
      }
      std::printf("  %-28s %s\n", f.filename().string().c_str(), what.c_str());
    }
    break;  // the first directory that exists
  }
  return kOk;
}

}  // namespace

const Subcommand ListCommand::kInfo{"list",
                               "List the built-in models and the example scenes; `list MODEL`: that model's coordinates and parameters."};

void ListCommand::declare(OptionList& o) {
  o.positional("model", model_, "a built-in model: show its coordinates (with units) and parameters (defaults)", false);
}

int ListCommand::run() { return model_.empty() ? list_all() : list_model(model_); }

}  // namespace lagrangian::cli
