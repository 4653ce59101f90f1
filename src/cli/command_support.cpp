// What the subcommands share (see command_support.hpp).

#include "command_support.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "lagrangian/integrate/method.hpp"
#include "lagrangian/params.hpp"
#include "lagrangian/scene/io.hpp"
#include "written_files.hpp"

namespace lagrangian::cli {

void SceneArgument::add(OptionList& options, const std::string& help) { options.positional("scene", path, help, true); }

void SceneArgument::add_settings(OptionList& options) {
  options.values("--set", settings,
                 "KEY=VALUE: set a numeric scene key, as if the file said so (e.g. model.parameters.e=0.5, "
                 "bodies[0].velocity[2]=3, run.rtol=1e-8); repeatable");
}

scene::Scene SceneArgument::load() const {
  std::vector<scene::KeySetting> parsed;
  for (const std::string& text : settings) parsed.push_back(scene::parse_key_setting(text));
  return scene::load_scene(path, parsed);
}

void override_t_end(scene::Scene& scene, const std::optional<double>& t_end) {
  if (!t_end) return;
  if (!std::isfinite(*t_end) || !(*t_end > scene.run.t0))
    throw BadInput{"command line: --t-end: must be finite and > t0 = " + detail::format_number(scene.run.t0) +
                   " s, got " + detail::format_number(*t_end)};
  scene.run.t_end = *t_end;
  scene.source.overrides["run.t_end"] = "--t-end";
}

void RunOverrides::add(OptionList& o, const std::string& method_help, bool with_t_end) {
  if (with_t_end) o.value("--t-end", t_end, "end time (s), overrides run.t_end");
  o.value("--method", method, method_help);
  o.value("--rtol", rtol, "relative tolerance, overrides run.rtol");
  o.value("--atol", atol, "absolute tolerance, overrides run.atol");
}

void RunOverrides::apply(scene::Scene& scene, bool event_driven) const {
  override_t_end(scene, t_end);
  if (rtol) {
    check_positive("--rtol", *rtol);
    scene.run.rtol = *rtol;
    scene.source.overrides["run.rtol"] = "--rtol";
  }
  if (atol) {
    check_positive("--atol", *atol);
    scene.run.atol = *atol;
    scene.source.overrides["run.atol"] = "--atol";
  }
  if (!method) return;
  if (event_driven && *method == "event_driven") {
    // The event-driven engine, by the name of a stepper.
    scene.run.engine = "event_driven";
    scene.run.engine_key = "run.method";
  } else {
    auto names = stepper_names();
    if (event_driven) names.push_back("event_driven");
    const std::optional<Method> m = find_method(*method);
    if (!m) {
      const std::string near = scene::nearest(*method, names);
      throw BadInput{"command line: --method: unknown stepper '" + *method + "'" +
                     (near.empty() ? std::string() : "; did you mean '" + near + "'?")};
    }
    scene.run.method = *m;
    if (scene.run.engine == "event_driven") scene.run.engine = "ode";
  }
  scene.source.overrides["run.method"] = "--method";
}

std::string scene_stem(const std::string& path) {
  return path == "-" ? "stdin" : std::filesystem::path(path).stem().string();
}

void check_positive(const char* flag, double v) {
  if (!(v > 0) || !std::isfinite(v))
    throw BadInput{std::string("command line: ") + flag + ": must be a positive finite number, got " +
                   detail::format_number(v)};
}

std::vector<double> parse_numbers(const char* flag, const std::string& text) {
  std::vector<double> out;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, ',')) {
    const char* begin = item.c_str();
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    while (end && *end == ' ') ++end;
    if (item.empty() || end == begin || *end != '\0')
      throw BadInput{std::string("command line: ") + flag + ": '" + item + "' is not a number (in '" + text + "')"};
    if (!std::isfinite(v))
      throw BadInput{std::string("command line: ") + flag + ": '" + item + "' is not finite (in '" + text + "')"};
    out.push_back(v);
  }
  if (out.empty()) throw BadInput{std::string("command line: ") + flag + ": no values in '" + text + "'"};
  return out;
}

std::vector<std::string> comma_list(const std::string& text) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, ',')) out.push_back(item);
  return out;
}

void print_progress(const std::string& line) { std::cerr << "  " << line << "\n"; }

void print_outputs(const std::string& plot_note, const std::vector<std::string>& files, bool quiet) {
  if (!quiet) {
    if (!plot_note.empty()) std::cout << "note: " << plot_note << "\n";
    print_written(files);
  } else if (!plot_note.empty() && plot_note.rfind("plots failed", 0) == 0) {
    std::cerr << "lagrangian: " << plot_note << "\n";
  }
}

}  // namespace lagrangian::cli
