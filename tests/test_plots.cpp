// Plots drawn by gnuplot from a run's CSV files, and the terminal progress bar.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "lagrangian/errors.hpp"
#include "lagrangian/scene/plots.hpp"
#include "lagrangian/scene/progress.hpp"

namespace fs = std::filesystem;
using lagrangian::OptionError;
using lagrangian::PlotResult;
using lagrangian::PlotSpec;
using lagrangian::SpeedPlotSpec;

namespace {

// A fresh directory (with a space in its name, as users' paths may have),
// removed at the end of the test unless LAGRANGIAN_KEEP_PLOTS is set.
struct TempDir {
  fs::path path;
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "lagrangian plots XXXXXX").string();
    if (!::mkdtemp(tmpl.data())) throw std::runtime_error("mkdtemp failed");
    path = tmpl;
  }
  ~TempDir() {
    if (!std::getenv("LAGRANGIAN_KEEP_PLOTS")) {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

std::string read_all(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

bool is_png(const std::string& path) {
  const std::string bytes = read_all(path);
  return bytes.size() > 100 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

bool is_svg(const std::string& path) {
  const std::string text = read_all(path);
  return text.size() > 100 && text.find("<svg") != std::string::npos;
}

std::vector<std::string> images_in(const fs::path& dir) {
  std::vector<std::string> found;
  if (!fs::exists(dir)) return found;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string ext = e.path().extension().string();
    if (ext == ".png" || ext == ".svg") found.push_back(e.path().filename().string());
  }
  return found;
}

constexpr double g = 9.81;

// Two balls thrown over a floor z = 0 (restitution e), in closed form: the
// flights are parabolas between impacts at the analytic times. Writes the
// trajectory and the events; returns the number of impacts.
int write_bouncing_balls(const std::string& trajectory, const std::string& events, double t_end, int rows) {
  struct Ball {
    const char* name;
    double x0, vx, z0, vz;
    std::vector<double> t_imp;  // impact times
  };
  const double e = 0.7;
  std::vector<Ball> balls = {{"ball", 0.0, 3.0, 1.0, 6.0, {}}, {"ball2", 0.5, 1.5, 2.0, 2.0, {}}};
  // Flight k starts at time s_k with height 0 (k ≥ 1) and upward speed w_k.
  for (Ball& b : balls) {
    double s = (b.vz + std::sqrt(b.vz * b.vz + 2 * g * b.z0)) / g;  // first landing
    double w = e * std::sqrt(b.vz * b.vz + 2 * g * b.z0);
    while (s < t_end) {
      b.t_imp.push_back(s);
      s += 2 * w / g;
      w *= e;
    }
  }
  auto state = [&](const Ball& b, double t, double& x, double& z, double& vz) {
    x = b.x0 + b.vx * t;
    double s = 0, z0 = b.z0, w = b.vz;
    double speed = std::sqrt(b.vz * b.vz + 2 * g * b.z0);
    for (double ti : b.t_imp) {
      if (t < ti) break;
      speed *= e;
      s = ti;
      z0 = 0;
      w = speed;
    }
    const double tau = t - s;
    z = z0 + w * tau - 0.5 * g * tau * tau;
    vz = w - g * tau;
  };
  std::FILE* f = std::fopen(trajectory.c_str(), "w");
  std::fprintf(f, "t,ball.x,ball.y,ball.z,ball2.x,ball2.y,ball2.z,ball.x_dot,ball.y_dot,ball.z_dot,"
                  "ball2.x_dot,ball2.y_dot,ball2.z_dot,energy,total_energy\n");
  for (int i = 0; i <= rows; ++i) {
    const double t = t_end * i / rows;
    double x[2], z[2], vz[2], E = 0;
    for (int k = 0; k < 2; ++k) {
      state(balls[static_cast<std::size_t>(k)], t, x[k], z[k], vz[k]);
      E += 0.5 * (balls[static_cast<std::size_t>(k)].vx * balls[static_cast<std::size_t>(k)].vx + vz[k] * vz[k]) +
           g * z[k];
    }
    E += 3e-9 * std::sin(3 * t) * t;  // an "integration error" to see
    std::fprintf(f, "%.17g,%.17g,0,%.17g,%.17g,0,%.17g,%.17g,0,%.17g,%.17g,0,%.17g,%.17g,%.17g\n", t, x[0], z[0],
                 x[1], z[1], balls[0].vx, vz[0], balls[1].vx, vz[1], E, E);
  }
  std::fclose(f);
  // Events in time order.
  std::vector<std::pair<double, std::string>> ev;
  for (const Ball& b : balls)
    for (double ti : b.t_imp) ev.emplace_back(ti, std::string(b.name) + "-floor");
  std::sort(ev.begin(), ev.end());
  f = std::fopen(events.c_str(), "w");
  std::fputs("t,kind,bodies,impulse,approach_speed,separation_speed,ke_before,ke_after\n", f);
  for (const auto& [t, name] : ev) std::fprintf(f, "%.17g,impact,%s,1,1,0.7,1,0.49\n", t, name.c_str());
  std::fclose(f);
  return static_cast<int>(ev.size());
}

PlotSpec bouncing_spec(const TempDir& dir) {
  PlotSpec spec;
  spec.title = "bouncing balls";
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.events_csv = dir / "events.csv";
  spec.out_dir = dir / "plots";
  spec.coordinates = {"ball.x", "ball.y", "ball.z", "ball2.x", "ball2.y", "ball2.z"};
  spec.units.assign(6, "m");
  spec.bodies = {{"ball", 0, 1, 2}, {"ball2", 3, 4, 5}};
  spec.energy_scale = 25;
  return spec;
}

// A cart (x, m) carrying a pendulum (theta, rad): small oscillations in
// closed form, a slowly drifting energy.
void write_cart_pendulum(const std::string& trajectory, int rows) {
  std::FILE* f = std::fopen(trajectory.c_str(), "w");
  std::fprintf(f, "t,x,theta,x_dot,theta_dot,energy\n");
  for (int i = 0; i <= rows; ++i) {
    const double t = 10.0 * i / rows;
    const double w1 = 2.2, w2 = 0.0;
    const double x = 0.3 * t - 0.05 * std::sin(w1 * t) + w2;
    const double th = 0.4 * std::sin(w1 * t);
    std::fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g\n", t, x, th, 0.3 - 0.05 * w1 * std::cos(w1 * t),
                 0.4 * w1 * std::cos(w1 * t), 3.5 + 1e-11 * t * t);
  }
  std::fclose(f);
}

void expect_images(const PlotResult& r, const std::string& out_dir) {
  EXPECT_TRUE(r.gnuplot_found);
  for (const char* name : {"trajectory", "coordinates", "energy", "phase"}) {
    const std::string png = out_dir + "/" + name + ".png", svg = out_dir + "/" + name + ".svg";
    EXPECT_TRUE(is_png(png)) << png;
    EXPECT_TRUE(is_svg(svg)) << svg;
    EXPECT_FALSE(fs::exists(out_dir + "/" + name + ".partial.png")) << name;
  }
  EXPECT_TRUE(fs::exists(out_dir + "/plots.gp"));
  EXPECT_EQ(r.files.size(), 9u);
}

// Keeps the files of a test (CSV files, script and images) in
// $LAGRANGIAN_PLOTS_SAMPLE/<name> when that variable is set, to look at.
void keep_sample(const TempDir& dir, const std::string& name) {
  const char* keep = std::getenv("LAGRANGIAN_PLOTS_SAMPLE");
  if (!keep) return;
  const fs::path dest = fs::path(keep) / name;
  fs::remove_all(dest);
  fs::create_directories(dest);
  fs::copy(dir.path, dest, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
}

// Sets PATH for the lifetime of the object.
struct ScopedPath {
  std::string saved;
  bool had;
  explicit ScopedPath(const std::string& value) {
    const char* p = std::getenv("PATH");
    had = p != nullptr;
    if (had) saved = p;
    ::setenv("PATH", value.c_str(), 1);
  }
  ~ScopedPath() {
    if (had) ::setenv("PATH", saved.c_str(), 1);
    else ::unsetenv("PATH");
  }
};

// A stand-in `gnuplot` first on PATH (a shell script) that answers
// --version and otherwise runs `body`: the checks of make_plots that come
// before gnuplot draws anything then run without a real gnuplot.
struct FakeGnuplot {
  TempDir bin;
  std::unique_ptr<ScopedPath> path;
  explicit FakeGnuplot(const std::string& body = "exit 0\n") {
    {
      std::ofstream f(bin / "gnuplot");
      f << "#!/bin/sh\n[ \"$1\" = --version ] && { echo 'gnuplot 0.0'; exit 0; }\n" << body;
    }
    fs::permissions(bin.path / "gnuplot", fs::perms::owner_all);
    path = std::make_unique<ScopedPath>(bin.path.string() + ":/usr/bin:/bin");
  }
};

#define REQUIRE_GNUPLOT() \
  if (!lagrangian::gnuplot_available()) GTEST_SKIP() << "gnuplot is not installed"

}  // namespace

TEST(Plots, ParticleSceneWithImpacts) {
  REQUIRE_GNUPLOT();
  TempDir dir;
  const int impacts = write_bouncing_balls(dir / "trajectory.csv", dir / "events.csv", 3.0, 3000);
  ASSERT_GE(impacts, 4);
  const PlotSpec spec = bouncing_spec(dir);
  const PlotResult r = lagrangian::make_plots(spec);
  expect_images(r, spec.out_dir);
  const std::string script = read_all(spec.out_dir + "/plots.gp");
  // The script names the trajectory relative to the plot directory, marks the
  // impacts and picks the x–z plane (y does not move).
  EXPECT_NE(script.find("data = '../trajectory.csv'"), std::string::npos) << script.substr(0, 600);
  EXPECT_NE(script.find("$impact_points"), std::string::npos);
  EXPECT_NE(script.find("x–z plane"), std::string::npos);
  EXPECT_NE(script.find("'x (m)'"), std::string::npos);
  EXPECT_NE(script.find("'z (m)'"), std::string::npos);
  // e < 1: the energy plot is titled for what its steps are, not as an error.
  EXPECT_NE(script.find("energy lost at the impacts (the steps), relative to |E0|"), std::string::npos);
  EXPECT_EQ(script.find("relative energy error"), std::string::npos);
  keep_sample(dir, "bouncing_balls");
}

TEST(Plots, ImpactsAreLocatedInThinnedFiles) {
  REQUIRE_GNUPLOT();
  TempDir dir;
  const int impacts = write_bouncing_balls(dir / "trajectory.csv", dir / "events.csv", 3.0, 60000);
  PlotSpec spec = bouncing_spec(dir);
  spec.svg = false;
  lagrangian::make_plots(spec);
  const std::string script = read_all(spec.out_dir + "/plots.gp");
  EXPECT_NE(script.find("n = 13 "), std::string::npos);
  // Every impact is on the floor: z interpolated between the rows around it.
  const std::string opening = "$impact_points << EOD\n# h v\n";
  const auto block = script.find(opening);
  ASSERT_NE(block, std::string::npos);
  std::istringstream in(script.substr(block + opening.size()));
  std::string row;
  int n = 0;
  while (std::getline(in, row) && row != "EOD") {
    const double z = std::stod(row.substr(row.find(' ') + 1));
    EXPECT_NEAR(z, 0.0, 1e-6) << row;
    ++n;
  }
  EXPECT_EQ(n, impacts);
}

TEST(Plots, GeneralizedModelWithoutEvents) {
  REQUIRE_GNUPLOT();
  TempDir dir;
  write_cart_pendulum(dir / "trajectory.csv", 2000);
  PlotSpec spec;
  spec.title = "cart pendulum";
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.events_csv = dir / "events.csv";  // absent
  spec.out_dir = dir / "out";
  spec.coordinates = {"x", "theta"};
  spec.units = {"m", "rad"};
  spec.energy_scale = 3.5;
  const PlotResult r = lagrangian::make_plots(spec);
  expect_images(r, spec.out_dir);
  const std::string script = read_all(spec.out_dir + "/plots.gp");
  EXPECT_NE(script.find("configuration space"), std::string::npos);
  EXPECT_NE(script.find("'theta_dot (rad/s)'"), std::string::npos);
  EXPECT_NE(script.find("'x_dot (m/s)'"), std::string::npos);
  EXPECT_EQ(script.find("$impacts"), std::string::npos);
  EXPECT_NE(script.find("relative energy error (of |E0|, E0 = 3.5 J)"), std::string::npos);
  keep_sample(dir, "cart_pendulum");
}

TEST(Plots, SingleCoordinateHeaderOnlyEventsAndInferredNames) {
  REQUIRE_GNUPLOT();
  TempDir dir;
  {
    std::ofstream f(dir / "trajectory.csv");
    f << "t,theta,theta_dot,energy\n";
    for (int i = 0; i <= 500; ++i) {
      const double t = 0.01 * i;
      f << t << "," << 0.3 * std::cos(3.13 * t) << "," << -0.3 * 3.13 * std::sin(3.13 * t) << ",0.5\n";
    }
    std::ofstream e(dir / "events.csv");
    e << "t,kind,bodies,impulse,approach_speed,separation_speed,ke_before,ke_after\n";
  }
  PlotSpec spec;
  spec.title = "pendulum";
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.events_csv = dir / "events.csv";
  spec.out_dir = dir / "plots";  // coordinates and units left empty: read from the header
  const PlotResult r = lagrangian::make_plots(spec);
  expect_images(r, spec.out_dir);
  const std::string script = read_all(spec.out_dir + "/plots.gp");
  EXPECT_NE(script.find("theta against time"), std::string::npos);
  keep_sample(dir, "pendulum");
}

TEST(Plots, AnEnergyConstantToRoundOffIsDrawnFlatAndSaidSo) {
  // E = −3.555 J with round-off of a few ulps: the plot is of (E − E0)/|E0| on an axis ±1e-10 wide, so
  // the round-off is not drawn at full height, and the title says how constant the energy was.
  REQUIRE_GNUPLOT();
  TempDir dir;
  double span = 0;
  {
    std::ofstream f(dir / "trajectory.csv");
    f.precision(17);
    f << "t,theta,theta_dot,energy\n";
    for (int i = 0; i <= 500; ++i) {
      const double t = 0.01 * i, E = -3.555 + (i % 7 - 3) * 4.440892098500626e-16;
      span = std::max(span, std::abs(E - (-3.555 + (0 % 7 - 3) * 4.440892098500626e-16)) / 3.555);
      f << t << "," << 0.3 * std::cos(3.13 * t) << "," << -0.3 * 3.13 * std::sin(3.13 * t) << "," << E << "\n";
    }
  }
  ASSERT_GT(span, 0.0);
  PlotSpec spec;
  spec.title = "link pendulum";
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.out_dir = dir / "plots";
  spec.energy_scale = 7.11;  // |T| + |V| at the bottom: not what the figure is relative to
  const PlotResult r = lagrangian::make_plots(spec);
  expect_images(r, spec.out_dir);
  const std::string script = read_all(spec.out_dir + "/plots.gp");
  EXPECT_NE(script.find("energy constant to "), std::string::npos) << script;
  EXPECT_NE(script.find("of |E0|, E0 = -3.555 J"), std::string::npos) << script;
  EXPECT_NE(script.find("set yrange [-1e-10:1e-10]"), std::string::npos) << script;
  EXPECT_EQ(script.find("relative energy error"), std::string::npos);
}

TEST(Plots, LargeFilesAreThinned) {
  REQUIRE_GNUPLOT();
  TempDir dir;
  write_cart_pendulum(dir / "trajectory.csv", 200000);
  PlotSpec spec;
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.out_dir = dir.path.string();  // the trajectory's own directory
  spec.coordinates = {"x", "theta"};
  spec.units = {"m", "rad"};
  spec.svg = false;
  const auto start = std::chrono::steady_clock::now();
  const PlotResult r = lagrangian::make_plots(spec);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_EQ(r.files.size(), 5u);  // 4 PNG and the script
  for (const char* name : {"trajectory", "coordinates", "energy", "phase"}) {
    EXPECT_TRUE(is_png(dir / (std::string(name) + ".png"))) << name;
    EXPECT_FALSE(fs::exists(dir / (std::string(name) + ".svg"))) << name;
  }
  const std::string script = read_all(dir / "plots.gp");
  EXPECT_NE(script.find("data = 'trajectory.csv'"), std::string::npos);
  EXPECT_NE(script.find("n = 41 "), std::string::npos);  // 200001 rows / 5000 per line
  // The file is read once, every n-th row, into a data block the plots use.
  EXPECT_NE(script.find("plot data every n::1 using (g(column(1))):(g(column(2)))"), std::string::npos);
  EXPECT_NE(script.find("$rows1 using 1:2 with lines"), std::string::npos);
  EXPECT_LT(seconds, 30.0);
}

TEST(Plots, ManyBodiesAreReadable) {
  REQUIRE_GNUPLOT();
  TempDir dir;
  // 15 bodies on circles in the x–y plane, z still.
  const int nb = 15;
  PlotSpec spec;
  spec.title = "ring";
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.out_dir = dir / "plots";
  std::ofstream f(spec.trajectory_csv);
  f << "t";
  for (int b = 0; b < nb; ++b)
    for (const char* a : {"x", "y", "z"}) {
      const std::string name = "m" + std::to_string(b + 1) + "." + a;
      spec.coordinates.push_back(name);
      f << "," << name;
    }
  for (const auto& name : spec.coordinates) f << "," << name << "_dot";
  f << ",energy\n";
  for (int b = 0; b < nb; ++b) spec.bodies.push_back({"m" + std::to_string(b + 1), 3 * b, 3 * b + 1, 3 * b + 2});
  spec.units.assign(spec.coordinates.size(), "m");
  for (int i = 0; i <= 400; ++i) {
    const double t = 0.01 * i;
    f << t;
    for (int b = 0; b < nb; ++b) {
      const double r = 1 + 0.2 * b, w = 1 / r;
      f << "," << r * std::cos(w * t + b) << "," << r * std::sin(w * t + b) << ",0";
    }
    for (int b = 0; b < nb; ++b) {
      const double r = 1 + 0.2 * b, w = 1 / r;
      f << "," << -r * w * std::sin(w * t + b) << "," << r * w * std::cos(w * t + b) << ",0";
    }
    f << ",-7\n";
  }
  f.close();
  // Many impacts: an even selection of them is marked.
  spec.events_csv = dir / "events.csv";
  {
    std::ofstream e(spec.events_csv);
    e << "t,kind,bodies,impulse,approach_speed,separation_speed,ke_before,ke_after\n";
    for (int i = 0; i < 5000; ++i) e << 4.0 * i / 5000 << ",impact,m" << i % nb + 1 << "-m" << (i + 1) % nb + 1 << ",1,1,1,2,2\n";
  }
  const PlotResult r = lagrangian::make_plots(spec);
  expect_images(r, spec.out_dir);
  const std::string script = read_all(spec.out_dir + "/plots.gp");
  EXPECT_NE(script.find("2000 of 5000, evenly chosen"), std::string::npos);
  EXPECT_NE(script.find("(15 bodies)"), std::string::npos);
  EXPECT_NE(script.find("title '10 of 45'"), std::string::npos);  // the moving ones first
  keep_sample(dir, "ring");
}

TEST(Plots, BodiesOnALineGivePositionAgainstTime) {
  REQUIRE_GNUPLOT();
  TempDir dir;
  // Three equal spheres (radius 0.1 m) on the x axis, elastic impacts: the
  // first one's velocity passes to the second at t1 = 1 s, then to the third at t2 = 2 s.
  PlotSpec spec;
  spec.title = "three spheres";
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.events_csv = dir / "events.csv";
  spec.out_dir = dir / "plots";
  const double v = 0.8, t1 = 1.0, t2 = 2.0;
  const double x0[3] = {0.0, v * t1 + 0.2, v * t1 + 0.2 + v * (t2 - t1) + 0.2};
  {
    std::ofstream f(spec.trajectory_csv);
    f << "t";
    std::vector<std::string> names;
    for (int b = 1; b <= 3; ++b)
      for (const char* a : {"x", "y", "z"}) names.push_back("s" + std::to_string(b) + "." + a);
    for (const auto& n : names) f << "," << n;
    for (const auto& n : names) f << "," << n << "_dot";
    f << ",energy\n";
    for (int i = 0; i <= 300; ++i) {
      const double t = 0.01 * i;
      const double vel[3] = {t < t1 ? v : 0, t1 <= t && t < t2 ? v : 0, t >= t2 ? v : 0};
      const double x[3] = {x0[0] + v * std::min(t, t1), x0[1] + v * std::clamp(t - t1, 0.0, t2 - t1),
                           x0[2] + v * std::max(t - t2, 0.0)};
      f << t;
      for (int b = 0; b < 3; ++b) f << "," << x[b] << ",0,0.1";
      for (int b = 0; b < 3; ++b) f << "," << vel[b] << ",0,0";
      f << "," << 0.5 * v * v << "\n";
    }
    std::ofstream e(spec.events_csv);
    e << "t,kind,bodies,impulse,approach_speed,separation_speed,ke_before,ke_after\n"
      << "1,impact,s1-s2,0.8,0.8,0.8,0.32,0.32\n"
      << "2,impact,s2-s3,0.8,0.8,0.8,0.32,0.32\n";
    spec.coordinates = names;
  }
  spec.units.assign(9, "m");
  spec.bodies = {{"s1", 0, 1, 2}, {"s2", 3, 4, 5}, {"s3", 6, 7, 8}};
  const PlotResult r = lagrangian::make_plots(spec);
  expect_images(r, spec.out_dir);
  const std::string script = read_all(spec.out_dir + "/plots.gp");
  EXPECT_NE(script.find("position along x against time"), std::string::npos);
  // Each impact is marked on both bodies, at the contact positions.
  const auto block = script.find("$impact_points << EOD\n# h v\n");
  ASSERT_NE(block, std::string::npos);
  EXPECT_NE(script.find("1 0.8\n1 1\n2 1.8\n2 2\n", block), std::string::npos)
      << script.substr(block, 200);
  EXPECT_EQ(script.find("energy lost at the impacts"), std::string::npos);  // elastic
  keep_sample(dir, "three_spheres");
}

// Speeds drawn from Maxwell–Boltzmann (three normal components of
// variance kT/m, a seeded generator): the histogram the script holds is a
// probability density (its area is 1) close to f(v) bin by bin.
TEST(Plots, SpeedHistogramIsADensityAgainstMaxwellBoltzmann) {
  REQUIRE_GNUPLOT();
  TempDir dir;
  SpeedPlotSpec spec;
  spec.title = "gas";
  spec.out_dir = dir / "out";
  spec.mass = 2.0;
  spec.kT = 3.0;
  const double a = std::sqrt(spec.kT / spec.mass);
  std::uint64_t state = 12345;
  auto uniform = [&] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (static_cast<double>(state >> 11) + 0.5) / 9007199254740992.0;
  };
  auto normal = [&] { return std::sqrt(-2 * std::log(uniform())) * std::cos(2 * M_PI * uniform()); };
  for (int i = 0; i < 40000; ++i) {
    const double vx = a * normal(), vy = a * normal(), vz = a * normal();
    spec.speeds.push_back(std::sqrt(vx * vx + vy * vy + vz * vz));
  }
  const PlotResult r = lagrangian::make_speed_plot(spec);
  EXPECT_TRUE(r.gnuplot_found);
  EXPECT_TRUE(is_png(spec.out_dir + "/speeds.png"));
  EXPECT_TRUE(is_svg(spec.out_dir + "/speeds.svg"));
  EXPECT_EQ(r.files.size(), 3u);  // the two images, then the script
  const std::string script = read_all(spec.out_dir + "/speeds.gp");
  const auto from = script.find("$speeds << EOD\n");
  ASSERT_NE(from, std::string::npos);
  std::istringstream rows(script.substr(script.find('\n', script.find("# bin centre")) + 1));
  std::string line;
  std::getline(rows, line);  // "$speeds << EOD"
  double area = 0, prev = -1, worst = 0;
  int bins = 0;
  while (std::getline(rows, line) && line != "EOD") {
    std::istringstream in(line);
    double centre = 0, density = 0, count = 0;
    in >> centre >> density >> count;
    const double width = prev < 0 ? 2 * centre : centre - prev;
    prev = centre;
    area += density * width;
    const double x = centre / a;  // f(v) = √(2/π) x² e^{−x²/2} / a
    const double f = std::sqrt(2 / M_PI) * x * x * std::exp(-0.5 * x * x) / a;
    worst = std::max(worst, std::abs(density - f) * a);
    ++bins;
  }
  EXPECT_EQ(bins, 60);  // √40000 = 200, at most 60
  EXPECT_NEAR(area, 1.0, 1e-12);
  EXPECT_LT(worst, 0.03);  // peak density × a is 0.83; bins hold ~700 speeds each
  EXPECT_NE(script.find("maxwell(v) = 4*pi*v**2*(m/(2*pi*kT))**1.5*exp(-m*v**2/(2*kT))"), std::string::npos);
  EXPECT_THROW(lagrangian::make_speed_plot([&] { auto b = spec; b.kT = 0; return b; }()), lagrangian::OptionError);
  EXPECT_THROW(lagrangian::make_speed_plot([&] { auto b = spec; b.speeds[3] = -1; return b; }()),
               lagrangian::OptionError);
}

// A projectile over an incline at beta = 0.3 rad, launched at 20 m/s and 45°
// from the origin: x = v t, y = v t − g t²/2 (v = 20/√2). Its watched
// events are marked by name where the path is at their times (the apex at
// t = v/g, interpolated between rows), and the incline is drawn as a line
// through the origin along (cos beta, sin beta), clipped to the plot.
TEST(Plots, WatchedEventsAndAnInclineOnAProjectilesPath) {
  REQUIRE_GNUPLOT();
  TempDir dir;
  const double v = 20 / std::sqrt(2.0), g = 9.81, beta = 0.3;
  const double t_apex = v / g, t_land = 2 * v * (1 - std::tan(beta)) / g;  // y = x tan(beta)
  {
    std::ofstream f(dir / "trajectory.csv");
    f << "t,x,y,x_dot,y_dot,energy\n";
    f.precision(17);
    for (int k = 0; k <= 173; ++k) {
      const double t = t_land * k / 173;
      f << t << "," << v * t << "," << v * t - 0.5 * g * t * t << "," << v << "," << v - g * t << ",200\n";
    }
    std::ofstream e(dir / "events.csv");
    e.precision(17);
    e << "t,kind,bodies,impulse,approach_speed,separation_speed,ke_before,ke_after\n"
      << t_apex << ",event,apex,0,0,0,0,0\n" << t_land << ",event,landing,0,0,0,0,0\n"
      << t_land << ",stop,landing,0,0,0,0,0\n";
  }
  PlotSpec spec;
  spec.title = "projectile";
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.events_csv = dir / "events.csv";
  spec.out_dir = dir / "out";
  spec.coordinates = {"x", "y"};
  spec.units = {"m", "m"};
  spec.energy_scale = 200;
  spec.bodies = {{"projectile", 0, 1, -1}};
  PlotSpec::Plane ground;
  ground.name = "ground";
  ground.normal[0] = -std::sin(beta);
  ground.normal[1] = std::cos(beta);
  ground.normal[2] = 0;
  spec.planes = {ground};
  const PlotResult r = lagrangian::make_plots(spec);
  expect_images(r, spec.out_dir);
  const std::string script = read_all(spec.out_dir + "/plots.gp");
  const auto block = script.find("$marks << EOD\n# h v name\n");
  ASSERT_NE(block, std::string::npos) << script.substr(0, 800);
  std::istringstream rows(script.substr(block + std::string("$marks << EOD\n# h v name\n").size()));
  double h = 0, vv = 0;
  std::string name;
  rows >> h >> vv >> name;
  EXPECT_EQ(name, "\"apex\"");
  EXPECT_NEAR(h, v * t_apex, 1e-6);
  EXPECT_NEAR(vv, v * v / (2 * g), 1e-3);  // between rows: the rates carry the rows to t_apex
  rows >> h >> vv >> name;
  EXPECT_EQ(name, "\"landing\"");
  EXPECT_NEAR(vv, h * std::tan(beta), 1e-3);  // on the incline to O(dt²), as impacts are placed
  EXPECT_EQ(script.find("\"landing\"", script.find("\"landing\"") + 1), std::string::npos);  // the stop is not a second mark
  // The incline: both ends on y = x tan(beta).
  const auto arrow = script.find("set arrow 1 from ");
  ASSERT_NE(arrow, std::string::npos);
  double h0 = 0, v0 = 0, h1 = 0, v1 = 0;
  char comma = 0;
  std::istringstream line(script.substr(arrow + 17));
  std::string to;
  line >> h0 >> comma >> v0 >> to >> h1 >> comma >> v1;
  EXPECT_EQ(to, "to");
  EXPECT_NEAR(v0, h0 * std::tan(beta), 1e-9 * (1 + std::abs(v0)));
  EXPECT_NEAR(v1, h1 * std::tan(beta), 1e-9 * (1 + std::abs(v1)));
  EXPECT_GT(std::abs(h1 - h0), 20.0);  // across the plot, which spans the 25 m of the path
  EXPECT_NE(script.find("'ground'"), std::string::npos);
  keep_sample(dir, "projectile_incline");
}

TEST(Plots, MissingGnuplotSkipsWithoutImages) {
  TempDir dir;
  write_cart_pendulum(dir / "trajectory.csv", 100);
  fs::create_directories(dir.path / "empty-bin");
  PlotSpec spec;
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.out_dir = dir / "plots";
  spec.coordinates = {"x", "theta"};
  spec.units = {"m", "rad"};
  ScopedPath path(dir / "empty-bin");
  EXPECT_FALSE(lagrangian::gnuplot_available());
  PlotResult r;
  ASSERT_NO_THROW(r = lagrangian::make_plots(spec));
  EXPECT_FALSE(r.gnuplot_found);
  EXPECT_TRUE(r.files.empty());
  EXPECT_EQ(r.message, "gnuplot not found; install it with: apt-get install gnuplot-nox (plots skipped)");
  EXPECT_TRUE(images_in(spec.out_dir).empty());
}

TEST(Plots, UnreadableTrajectoryNamesThePath) {
  FakeGnuplot gnuplot;
  TempDir dir;
  PlotSpec spec;
  spec.trajectory_csv = dir / "no such run/trajectory.csv";
  spec.out_dir = dir / "plots";
  try {
    lagrangian::make_plots(spec);
    FAIL() << "no exception";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find(spec.trajectory_csv), std::string::npos) << e.what();
  }
  EXPECT_TRUE(images_in(spec.out_dir).empty());

  // A directory is not a CSV file either; a file with a foreign header is refused.
  spec.trajectory_csv = dir.path.string();
  EXPECT_THROW(lagrangian::make_plots(spec), OptionError);
  {
    std::ofstream f(dir / "other.csv");
    f << "a,b\n1,2\n";
  }
  spec.trajectory_csv = dir / "other.csv";
  try {
    lagrangian::make_plots(spec);
    FAIL() << "no exception";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("other.csv"), std::string::npos) << e.what();
  }
}

TEST(Plots, MalformedTrajectoryAndMissingColumns) {
  FakeGnuplot gnuplot;
  TempDir dir;
  {
    std::ofstream f(dir / "trajectory.csv");
    f << "t,x,x_dot,energy\n0,1,2,3\n0.1,1,2\n";
  }
  PlotSpec spec;
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.out_dir = dir / "plots";
  try {
    lagrangian::make_plots(spec);
    FAIL() << "no exception";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("line 3"), std::string::npos) << e.what();
  }
  {
    std::ofstream f(dir / "trajectory.csv");
    f << "t,x,x_dot,energy\n0,1,2,3\n";
  }
  spec.coordinates = {"y"};
  spec.units = {"m"};
  try {
    lagrangian::make_plots(spec);
    FAIL() << "no exception";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("'y'"), std::string::npos) << e.what();
  }
}

TEST(Plots, UnwritableOutputDirectoryNamesThePath) {
  FakeGnuplot gnuplot;
  TempDir dir;
  write_cart_pendulum(dir / "trajectory.csv", 100);
  PlotSpec spec;
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.out_dir = dir / "trajectory.csv/plots";  // under a regular file
  try {
    lagrangian::make_plots(spec);
    FAIL() << "no exception";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find(spec.out_dir), std::string::npos) << e.what();
  }
}

TEST(Plots, FailingGnuplotLeavesNoImages) {
  TempDir dir;
  write_cart_pendulum(dir / "trajectory.csv", 100);
  // A gnuplot that writes one image and then fails.
  FakeGnuplot gnuplot(
      "echo x > trajectory.partial.png\n"
      "echo 'line 12: undefined variable: boom' >&2\n"
      "exit 1\n");
  PlotSpec spec;
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.out_dir = dir / "plots";
  {
    fs::create_directories(spec.out_dir);
    std::ofstream stale(spec.out_dir + "/energy.png");  // from an earlier run
    stale << "old";
  }
  try {
    lagrangian::make_plots(spec);
    FAIL() << "no exception";
  } catch (const OptionError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("undefined variable: boom"), std::string::npos) << what;
    EXPECT_NE(what.find("plots.gp"), std::string::npos) << what;
  }
  EXPECT_TRUE(images_in(spec.out_dir).empty());
  EXPECT_TRUE(fs::exists(spec.out_dir + "/plots.gp"));  // kept, to debug
}

TEST(Plots, GnuplotThatWritesNothingIsAnError) {
  TempDir dir;
  write_cart_pendulum(dir / "trajectory.csv", 100);
  FakeGnuplot gnuplot("exit 0\n");
  PlotSpec spec;
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.out_dir = dir / "plots";
  try {
    lagrangian::make_plots(spec);
    FAIL() << "no exception";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find("trajectory.partial.png"), std::string::npos) << e.what();
  }
  EXPECT_TRUE(images_in(spec.out_dir).empty());
}

TEST(Plots, UnreadableEventsNameThePath) {
  FakeGnuplot gnuplot;
  TempDir dir;
  write_cart_pendulum(dir / "trajectory.csv", 100);
  fs::create_directories(dir.path / "events.csv");  // a directory
  PlotSpec spec;
  spec.trajectory_csv = dir / "trajectory.csv";
  spec.events_csv = dir / "events.csv";
  spec.out_dir = dir / "plots";
  try {
    lagrangian::make_plots(spec);
    FAIL() << "no exception";
  } catch (const OptionError& e) {
    EXPECT_NE(std::string(e.what()).find(spec.events_csv), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------- progress

namespace {

// Captures what is written on file descriptor 2 while `body` runs.
template <class F>
std::string capture_stderr(F body) {
  std::fflush(stderr);
  char path[] = "/tmp/lagrangian-stderr-XXXXXX";
  const int fd = ::mkstemp(path);
  const int saved = ::dup(STDERR_FILENO);
  ::dup2(fd, STDERR_FILENO);
  body();
  std::fflush(stderr);
  ::dup2(saved, STDERR_FILENO);
  ::close(saved);
  ::close(fd);
  const std::string text = read_all(path);
  ::unlink(path);
  return text;
}

}  // namespace

TEST(Progress, DisabledWritesNothing) {
  const std::string out = capture_stderr([] {
    lagrangian::Progress p(0, 10, false);
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    for (int i = 0; i <= 100000; ++i) p.update(1e-4 * i);
    p.finish();
  });
  EXPECT_EQ(out, "");
}

TEST(Progress, QuietInAPipe) {
  // stderr redirected to a file is not a terminal.
  const std::string out = capture_stderr([] {
    EXPECT_FALSE(lagrangian::Progress::stderr_is_terminal());
    lagrangian::Progress p(0, 1);
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    for (int i = 0; i <= 5000; ++i) p.update(2e-4 * i);
  });
  EXPECT_EQ(out, "");
}

TEST(Progress, ShortRunsDrawNothing) {
  const std::string out = capture_stderr([] {
    lagrangian::Progress p(0, 10, true);
    for (int i = 0; i <= 100000; ++i) p.update(1e-4 * i);
    p.finish();
  });
  EXPECT_EQ(out, "");
}

TEST(Progress, DrawsAfterOneSecondAndClears) {
  const std::string out = capture_stderr([] {
    lagrangian::Progress p(2, 12, true);
    std::this_thread::sleep_for(std::chrono::milliseconds(1100));
    // Enough calls for the adaptive stride to reach the clock.
    for (int i = 0; i < 3000; ++i) p.update(7);
    p.finish();
    p.update(8);  // after finish: nothing
  });
  EXPECT_NE(out.find("\r["), std::string::npos) << out;
  EXPECT_NE(out.find(" 50%"), std::string::npos) << out;
  EXPECT_NE(out.find("t = 7 s"), std::string::npos) << out;
  EXPECT_NE(out.find("ETA "), std::string::npos) << out;
  EXPECT_EQ(out.substr(out.size() - 4), "\r\x1b[K") << out;  // the line is cleared
  EXPECT_EQ(out.find("t = 8 s"), std::string::npos) << out;
}
