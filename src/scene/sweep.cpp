// Parameter sweeps and ensembles of a scene (include/lagrangian/scene/sweep.hpp):
// sweep() — the plan, point 0's checks, the thread pool, the gathering of
// results by point index and the writing of the table and plots.

#include "lagrangian/scene/sweep.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <stdexcept>
#include <thread>

#include <toml++/toml.h>

#include "lagrangian/detail/text_output.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/scene/analysis.hpp"
#include "lagrangian/scene/progress.hpp"
#include "lagrangian/scene/scene.hpp"
#include "lagrangian/scene/io.hpp"
#include "lagrangian/scene/run.hpp"
#include "output_manifest.hpp"
#include "sweep_detail.hpp"
#include "toml_document.hpp"

namespace lagrangian::scene {
namespace {

namespace fs = std::filesystem;

using detail::deserialize;
using detail::make_table;
using detail::parse_path;
using detail::Plan;
using detail::plot;
using detail::point_scene;
using detail::run_point;
using detail::serialize;
using detail::Table;
using detail::to_csv;
using detail::trajectory_names;

/// What every point's scene is made from: the scene file's text, the keys
/// --vary and --set change, and the variables --set may use.
Plan make_plan(const std::string& scene_path, const SweepOptions& o) {
  Plan plan;
  plan.file = scene_path;
  plan.text = detail::read_scene_text(scene_path);
  for (std::size_t k = 0; k < o.vary.size(); ++k) {
    if (o.vary[k].variable()) {
      plan.vary_paths.emplace_back();
      plan.variables.push_back(o.vary[k].key);
      plan.variable_slots.push_back(k);
    } else {
      plan.vary_paths.push_back(parse_path("--vary", o.vary[k].key));
    }
  }
  for (const SetSpec& s : o.set) {
    plan.set_paths.push_back(parse_path("--set", s.key));
    plan.set_expressions.emplace_back(s.expression, plan.variables, "--set " + s.key);
  }
  return plan;
}

/// `--output chaos` needs the tangent flow of the scene's model or bodies:
/// a scene the tangent flow is not derived for (a text model of more
/// coordinates than it takes, a particle scene of more bodies) is refused
/// here (OptionError "--output chaos: …", the reason scene::lyapunov()
/// gives) rather than failing every run. The check starts point 0's run
/// with a budget of one step: the refusal comes before any step, and the
/// run stops (SimulationError, max_steps) after the first.
void check_tangent_flow(Scene s) {
  s.run.max_steps = 1;
  try {
    (void)lyapunov(s, LyapunovRequest{1, 0.0});
  } catch (const OptionError& e) {
    std::string why = e.what();
    if (why.rfind("lyapunov: ", 0) == 0) why.erase(0, 10);  // the command's prefix, not this option's
    throw OptionError("--output chaos: " + why);
  } catch (const Error&) {
    // The step budget, or a run that fails: the point's run says which.
  }
}

/// Point 0 decides what is bad input rather than a failed run: a key the
/// scene cannot take (unknown key, unknown model parameter, an element the
/// scene does not write) throws here. Values that are merely invalid fail
/// their run.
void check_first_point(const Plan& plan, const SweepOptions& o) {
  toml::table doc = toml::parse(plan.text, plan.file);
  std::vector<double> values = point_values(o, 0);
  try {
    const Scene s = point_scene(plan, o, doc, values);
    for (const FirstTimeSpec& f : o.first_times)  // names checked here, against the scene's coordinates
      Expression(f.expression, trajectory_names(s), "--first-time " + f.name);
    (void)inspect(s);
    if (o.wants("chaos")) check_tangent_flow(s);
  } catch (const SceneError& e) {
    const std::string m = e.message();
    if (m.find("unknown key") != std::string::npos || m.find("unknown parameter") != std::string::npos ||
        m.find("has no parameter") != std::string::npos)
      throw;
  } catch (const OptionError& e) {
    const std::string m = e.what();
    if (m.rfind("--vary", 0) == 0 || m.rfind("--set", 0) == 0 || m.rfind("--first-time", 0) == 0 ||
        m.rfind("--output", 0) == 0) {
      if (m.find("gives NaN") == std::string::npos && m.find("infinite value") == std::string::npos) throw;
    }
  } catch (const Error&) {
  }
}

/// The points `mine` on `threads` threads, with a progress bar on rank 0;
/// SweepInterrupted when cancelled before all are done.
std::vector<SweepRecord> run_points(const Plan& plan, const SweepOptions& o, const std::vector<std::uint64_t>& mine,
                                    int threads) {
  std::vector<SweepRecord> local(mine.size());
  std::atomic<std::size_t> next{0}, done{0};
  auto cancelled = [&] { return o.cancel != nullptr && o.cancel->load(); };
  auto worker = [&] {
    for (;;) {
      if (cancelled()) return;
      const std::size_t k = next.fetch_add(1);
      if (k >= mine.size()) return;
      local[k] = run_point(plan, o, mine[k]);
      done.fetch_add(1);
    }
  };
  {
    Progress progress(0, static_cast<double>(mine.size()), o.progress && o.rank == 0 && Progress::stderr_is_terminal());
    progress.set_format("run %.0f");
    std::vector<std::thread> pool;
    for (int id = 0; id < threads; ++id) pool.emplace_back(worker);
    if (o.progress && o.rank == 0) {
      while (done.load() < mine.size() && !cancelled()) {
        progress.update(static_cast<double>(done.load()));
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
    }
    for (auto& t : pool) t.join();
    progress.finish();
  }
  if (done.load() < mine.size()) throw SweepInterrupted(done.load(), mine.size());
  return local;
}

}  // namespace

SweepResult sweep(const std::string& scene_path, const SweepOptions& o) {
  o.validate();
  const auto start = std::chrono::steady_clock::now();
  // The scene as it is must load: its own errors come first, with its lines.
  const Scene base = load_scene(scene_path);
  const Plan plan = make_plan(scene_path, o);

  check_first_point(plan, o);
  const std::uint64_t n = point_count(o);

  // This rank's points: i = rank, rank + ranks, ... (cyclic, so that points
  // whose cost grows along the grid spread evenly).
  std::vector<std::uint64_t> mine;
  for (std::uint64_t i = static_cast<std::uint64_t>(o.rank); i < n; i += static_cast<std::uint64_t>(o.ranks))
    mine.push_back(i);
  int threads = o.threads > 0 ? o.threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  threads = static_cast<int>(
      std::min<std::uint64_t>(static_cast<std::uint64_t>(threads), std::max<std::size_t>(1, mine.size())));

  const fs::path out_dir = o.out_dir;
  const fs::path csv_path = out_dir / "sweep.csv";
  if (o.rank == 0) {
    std::error_code ec;
    fs::create_directories(out_dir, ec);
    if (ec || !fs::is_directory(out_dir))
      throw OptionError("--out: cannot create the directory '" + o.out_dir + "'" + (ec ? ": " + ec.message() : ""));
    // An earlier sweep's table and plots must not look like this one's.
    detail::remove_listed_outputs(o.out_dir, {"sweep.csv"});
  }
  std::vector<SweepRecord> local = run_points(plan, o, mine, threads);
  const auto computed = std::chrono::steady_clock::now();

  SweepResult result;
  result.warnings = sweep_warnings(o);
  result.points = n;
  result.threads = threads;
  result.ranks = o.ranks;
  std::vector<SweepRecord> all(n);
  std::vector<bool> filled(n, false);
  if (o.ranks > 1) {
    std::string text;
    for (std::size_t k = 0; k < mine.size(); ++k) text += serialize(mine[k], local[k]);
    const std::string gathered = o.gather(text);
    result.run_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (o.rank != 0) {
      result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return result;
    }
    deserialize(gathered, all, filled);
    for (std::uint64_t i = 0; i < n; ++i)
      if (!filled[i]) throw std::runtime_error("sweep: no result for point " + std::to_string(i) + " from its rank");
  } else {
    result.run_time_s = std::chrono::duration<double>(computed - start).count();
    for (std::size_t k = 0; k < mine.size(); ++k) all[mine[k]] = std::move(local[k]);
  }
  for (const SweepRecord& r : all) result.failed += r.ok() ? 0 : 1;
  const Table table = make_table(o, all);
  lagrangian::detail::write_text_file(csv_path.string(), to_csv(table, base), "sweep table");
  result.files.push_back(csv_path.string());
  result.header = table.header;
  if (o.plots) plot(o, table, base, result);
  if (o.rank == 0) detail::write_output_manifest(o.out_dir, result.files);
  result.records = std::move(all);
  result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace lagrangian::scene
