// `lagrangian solve-bvp SCENE --from Q0 --to Q1 --time T`: the path of
// stationary discrete action between two configurations.

#include <iostream>

#include "commands.hpp"

namespace lagrangian::cli {

const Subcommand BvpCommand::kInfo{"solve-bvp",
                               "Boundary-value problem by stationary action: the path of the scene's model from q(t0) = FROM to "
                   "q(t1) = TO that makes the discrete action stationary (Newton's method); writes bvp_path.csv and "
                   "plots, and says whether the action is a minimum there."};

void BvpCommand::declare(OptionList& o) {
  scene_.add(o, "scene file (TOML) with a built-in model or one stated as text");
  o.value("--from", from_, "q(t0): comma-separated, one value per coordinate", true);
  o.value("--to", to_, "q(t1): comma-separated, one value per coordinate", true);
  o.value("--time", time_, "T (from the scene's t0) or t0:t1, in s", true);
  o.value("--steps", request_.steps, "number of time steps K (default 200)");
  o.value("--rule", request_.rule, "discrete Lagrangian: midpoint (default) or trapezoidal");
  o.value("--out", out_dir_, "output directory (default out/bvp/<scene file name>)");
  o.flag("--no-plots", no_plots_, "do not make plots");
  o.flag("-q,--quiet", quiet_, "print only errors");
}

/// q(t0), q(t1), t0 and t1 from --from, --to and --time (BadInput naming the flag).
void BvpCommand::read_times(const scene::Scene& scene) {
  request_.from = parse_numbers("--from", from_);
  request_.to = parse_numbers("--to", to_);
  const auto colon = time_.find(':');
  if (colon == std::string::npos) {
    const std::vector<double> T = parse_numbers("--time", time_);
    if (T.size() != 1 || !(T[0] > 0))
      throw BadInput{"command line: --time: must be a positive duration T or t0:t1, got '" + time_ + "'"};
    request_.t0 = scene.run.t0;
    request_.t1 = scene.run.t0 + T[0];
  } else {
    const std::vector<double> a = parse_numbers("--time", time_.substr(0, colon));
    const std::vector<double> b = parse_numbers("--time", time_.substr(colon + 1));
    if (a.size() != 1 || b.size() != 1 || !(b[0] > a[0]))
      throw BadInput{"command line: --time: need t0:t1 with t1 > t0, got '" + time_ + "'"};
    request_.t0 = a[0];
    request_.t1 = b[0];
  }
}

int BvpCommand::run() {
  const std::optional<scene::Scene> scene = scene_or_say([&] {
    scene::Scene s = scene_.load();
    read_times(s);
    return s;
  });
  if (!scene) return kBadInput;
  request_.out_dir = out_dir_ ? *out_dir_ : "out/bvp/" + scene_stem(scene_.path);
  request_.plots = !no_plots_;
  request_.png = scene->output.png;
  request_.svg = scene->output.svg;
  return guarded("solve-bvp", [&] {
    const scene::BvpRun r = scene::solve_bvp(*scene, request_);
    if (!quiet_) std::cout << "scene " << scene->name << "\n" << r.summary();
    print_outputs(r.plot_note, r.files, quiet_);
    return kOk;
  });
}

}  // namespace lagrangian::cli
