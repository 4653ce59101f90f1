#pragma once
/// \file plots.hpp
/// Plots of a finished run, drawn by gnuplot from the files the run wrote.
/// Target `lagrangian::scene`. For a model of your own, scene::run_and_write()
/// (scene/model_run.hpp) runs it and makes these plots, the CSV, the report
/// and the animation page in one call.
///
/// make_plots() reads `trajectory.csv` (header
/// `t,<coordinates...>,<coordinate>_dot...,energy[,total_energy][,lambda_…,Qc_…]`)
/// and, when it exists, `events.csv`
/// (`t,kind,bodies,impulse,approach_speed,separation_speed,ke_before,ke_after`),
/// finding columns by name; a field's " [unit]" (as CsvSink writes it) is
/// not part of the name. It writes a gnuplot script `<out_dir>/plots.gp` and runs it. The plots are
///  - `trajectory`:  particle scenes: each body's path projected on the plane
///                   of the two axes with the largest spread (equal aspect
///                   ratio), or position against time when the motion is along
///                   one axis only; models of particles (two bodies, the
///                   oblique impact, projectiles, Newton's cradle) likewise,
///                   every body; other generalized models: the configuration-space
///                   path q₀–q₁ (q₀ against t for one coordinate). Impacts are
///                   marked at the positions of the bodies involved, watched
///                   events (a projectile's apex and landing) by name, fixed
///                   planes (a floor, an incline) drawn as lines.
///  - `coordinates`: every coordinate against t, one panel per unit.
///  - `energy`:      the relative energy error (E(t) − E(t₀)) / energy_scale;
///                   titled as the energy lost at the impacts when impacts
///                   with e < 1 took energy (the steps are those losses).
///  - `phase`:       phase portraits q against q̇ for up to four coordinates.
/// each as PNG (1000×700) and SVG, as enabled. Impacts (events of kind
/// `impact`) are marked on every plot against time by dashed vertical lines
/// (by short ticks along the top when there are more than 50).
///
/// The script is kept: `cd <out_dir> && gnuplot plots.gp` draws the plots
/// again, and it is plain gnuplot to adapt. It reads the trajectory file
/// `every n` rows (about 5000 points per line), and only once per 13 columns
/// it uses, into in-memory data blocks that all plots share: runs with a
/// million samples or a thousand bodies plot in about a second. Particle
/// scenes with more than 40 bodies show the paths of the first 10; panels
/// show at most 10 coordinates (those that move first). Images are written
/// under a `.partial` name and renamed only when gnuplot succeeded, so a
/// failed plot never looks complete. Written for gnuplot 5.4 with the
/// pngcairo and svg terminals (Debian's gnuplot-nox).

#include <functional>
#include <string>
#include <vector>

#include "lagrangian/errors.hpp"

namespace lagrangian {

/// What to plot and where.
struct PlotSpec {
  std::string title;                      ///< shown in the plot titles (e.g. the scene name)
  std::string trajectory_csv;             ///< path of the run's trajectory CSV
  std::string events_csv;                 ///< path of its events CSV; may be empty or not exist
  std::string out_dir;                    ///< directory for the script and images (created if missing)
  std::vector<std::string> coordinates;   ///< coordinate names in the CSV's order; empty: read from the header
  std::vector<std::string> units;         ///< unit of each coordinate ("m", "rad", …); empty: unitless
  /// A particle of a particle scene: 0-based indices into `coordinates` of
  /// its Cartesian x, y, z (−1 when absent).
  struct Body {
    std::string name;
    int x = -1, y = -1, z = -1;
  };
  std::vector<Body> bodies;               ///< particle scenes and models of particles; empty: configuration space
  /// A fixed plane (a floor, an incline, a wall): drawn as a line on the
  /// trajectory plot when it stands across the plotted plane (its normal in
  /// that plane), or as a level on a position-against-time plot.
  struct Plane {
    std::string name;
    double point[3] = {0, 0, 0};   ///< a point on it (m)
    double normal[3] = {0, 0, 1};  ///< its normal
  };
  std::vector<Plane> planes;
  double energy_scale = 1;                ///< J, > 0; the energy error is plotted as (E − E₀)/energy_scale
  bool png = true;                        ///< write `<name>.png` (pngcairo, 1000×700)
  bool svg = true;                        ///< write `<name>.svg`
};

/// What make_plots() did.
struct PlotResult {
  bool gnuplot_found = false;       ///< false: nothing was written, see message
  std::vector<std::string> files;   ///< the images written (paths under out_dir), then the script
  std::string message;              ///< one line for the user (and any warnings gnuplot printed)
};

/// True when a program `gnuplot` is on PATH and runs (`gnuplot --version`
/// exits with status 0).
bool gnuplot_available();

/// Writes `<out_dir>/plots.gp` and runs gnuplot on it to draw the plots
/// described in this file's documentation.
///
/// Without gnuplot on PATH nothing is written and nothing is thrown: the
/// result has gnuplot_found = false and the message
/// "gnuplot not found; install it with: apt-get install gnuplot-nox (plots skipped)".
///
/// Throws OptionError naming the path when the trajectory CSV cannot be read
/// or is malformed (missing columns, no data rows), when the events CSV exists
/// but cannot be read, when out_dir cannot be created or written, and when
/// gnuplot exits with a non-zero status (the message then holds its stderr);
/// in that case no image of this call is left behind.
PlotResult make_plots(const PlotSpec& spec);

/// One line of a work-precision diagram: the runs of one stepper, from the
/// loosest tolerance (or largest step) to the tightest.
struct WorkPrecisionSeries {
  std::string name;                    ///< the stepper, shown in the legend
  std::vector<double> wall_time_s;     ///< wall time of each run (s), > 0
  std::vector<double> rhs_evaluations; ///< right-hand-side evaluations of each run
  std::vector<double> error;           ///< the error measure of each run; non-positive values are not drawn
  std::vector<double> energy_drift;    ///< relative energy drift of each run; NaN: not measured
};

/// What make_work_precision_plots() draws and where.
struct WorkPrecisionPlotSpec {
  std::string title;                   ///< e.g. the scene's name
  std::string error_label;             ///< y-axis label: what the error is
  std::string note;                    ///< one line under the plot (how the error was measured, the machine)
  std::string out_dir;                 ///< directory for `bench.gp` and the images (created if missing)
  double reference_accuracy = 0;       ///< > 0: drawn as a dashed line (errors below it are not resolved)
  std::vector<WorkPrecisionSeries> series;
  bool png = true;                     ///< write `<name>.png` (pngcairo, 800×560)
  bool svg = true;                     ///< write `<name>.svg`
};

/// Writes `<out_dir>/bench.gp` and runs gnuplot on it to draw, log–log, one
/// line per series:
///  - `work_precision_time`:   error against wall time;
///  - `work_precision_rhs`:    error against right-hand-side evaluations;
///  - `work_precision_energy`: relative energy drift against wall time (only
///    when some series has a measured drift).
/// Without gnuplot nothing is written and the result says so, as for
/// make_plots(); images are written under `.partial` names and renamed only
/// when gnuplot succeeded. Throws OptionError when out_dir cannot be written
/// or gnuplot fails, leaving no image of this call behind.
PlotResult make_work_precision_plots(const WorkPrecisionPlotSpec& spec);

/// Calls `make` (a call of one of the make_*plots functions) for a command
/// whose plots must not fail it: appends the images and script to `files`;
/// sets `note` to the message when gnuplot is missing and to "plots failed:
/// <why>" when `make` throws an Error.
void collect_plots(const std::function<PlotResult()>& make, std::vector<std::string>& files, std::string& note);

/// What make_speed_plot() draws: the speeds of a gas's molecules against
/// the Maxwell–Boltzmann distribution at its temperature.
struct SpeedPlotSpec {
  std::string title;            ///< e.g. the scene's name
  std::string out_dir;          ///< directory for `speeds.gp` and the images (created if missing)
  std::vector<double> speeds;   ///< m/s, finite and ≥ 0, at least 2
  double mass = 1;              ///< m (kg), > 0
  double kT = 1;                ///< J, > 0
  std::string note;             ///< one line under the plot (e.g. the Kolmogorov–Smirnov distance)
  bool png = true;              ///< write `speeds.png` (800×560)
  bool svg = true;              ///< write `speeds.svg`
};

/// Writes `<out_dir>/speeds.gp` and draws `speeds`: the histogram of the
/// speeds as a probability density (√N bins, at least 10 and at most 60,
/// from 0 to the largest speed) and the Maxwell–Boltzmann density
/// f(v) = 4π v² (m / 2πkT)^{3/2} exp(−m v² / 2kT) (s/m). Without gnuplot
/// nothing is written, as for make_plots(); throws OptionError for speeds,
/// mass or kT outside their ranges, or when gnuplot fails.
PlotResult make_speed_plot(const SpeedPlotSpec& spec);

/// What make_sweep_plots() draws: the results of a sweep along one key (a
/// curve per series) or two keys (a heat map per series).
struct SweepPlotSpec {
  std::string title;                   ///< e.g. the scene's name
  std::string out_dir;                 ///< directory for `sweep.gp` and the images (created if missing)
  std::vector<std::string> axes;       ///< the varied keys (1 or 2), axis labels
  std::vector<std::string> axis_units; ///< the keys' units ("" or absent: none shown)
  std::vector<int> axis_counts;        ///< grid points along each axis; the points run with the first axis slowest
  std::vector<bool> log_axes;          ///< logarithmic grid along the axis
  /// One plotted column: x[i] holds point i's values along the axes, y[i]
  /// the column's value (NaN: a failed run or no value; not drawn).
  struct Series {
    std::string name;
    std::string unit;  ///< shown with the name on its axis; "" for none
    std::vector<std::vector<double>> x;
    std::vector<double> y;
  };
  std::vector<Series> series;
  bool png = true;                     ///< write `sweep_<name>.png` (pngcairo, 800×560)
  bool svg = false;                    ///< write `sweep_<name>.svg`
};

/// Writes `<out_dir>/sweep.gp` and runs gnuplot on it: for a sweep along one
/// key, `sweep_<name>` is the series against the key (lines and points);
/// along two keys, a heat map (`with image`) over the grid. Names are made
/// file-safe (characters other than letters, digits, '_' and '-' become
/// '_'). Without gnuplot nothing is written and the result says so, as for
/// make_plots(); images go through `.partial` names. Throws OptionError when
/// out_dir cannot be written or gnuplot fails, leaving no image behind.
PlotResult make_sweep_plots(const SweepPlotSpec& spec);

}  // namespace lagrangian
