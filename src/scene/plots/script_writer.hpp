#pragma once
// Internal: ScriptWriter, which writes the gnuplot script of make_plots()
// (trajectory, coordinates, energy error, phase portraits) for a read trajectory.

#include <cstddef>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "csv_inputs.hpp"
#include "lagrangian/scene/plots.hpp"

namespace lagrangian::plots_detail {

inline constexpr std::size_t kMaxImpactLines = 50;    // beyond, impact times are ticks, not lines across
inline constexpr std::size_t kMaxImpactCircles = 50;  // beyond, impact positions are small translucent dots
inline constexpr std::size_t kMaxLinesPerPanel = 10;  // coordinates drawn per unit panel (one colour each)
inline constexpr int kMaxPhasePanels = 4;

// Height / width of the plot area of a 1000×700 page with a title and axis
// labels, with and without a legend on the right.
inline constexpr double kAspectWithKey = 0.74;
inline constexpr double kAspectNoKey = 0.64;

constexpr std::size_t kLegendBodies = 10;      // at most this many bodies get a legend entry
constexpr std::size_t kMaxBodiesUnlabelled = 40;  // up to this many bodies are drawn without legend

struct Columns {
  std::vector<std::size_t> q, qd;  // column of each coordinate and its rate
  std::size_t energy = 0;
  std::size_t total_energy = 0;  // 0: absent
};

class ScriptWriter {
 public:
  // `impacts`: all impacts of the run; `times`: those marked on the plots
  // against time; `positions`: those marked on the trajectory (rows filled);
  // `marks`: watched events marked by name on the trajectory (rows filled).
  ScriptWriter(const PlotSpec& spec, const Trajectory& tr, const Columns& cols, const std::vector<Impact>& impacts,
               const std::vector<Impact>& times, const std::vector<Impact>& positions,
               const std::vector<Impact>& marks, std::vector<std::string> coords, std::vector<std::string> units,
               std::string data_path);

  std::string write();

 private:
  // ---- the data the plots read
  //
  // gnuplot reads the whole file for every line it draws, and twice (PNG and
  // SVG): with millions of rows or thousands of columns that is slow. So the
  // script first copies what the plots use — every n-th row, only the
  // columns needed — into data blocks $rows1, $rows2, … (at most
  // kBlockColumns columns each: t, then the quantities), reading the file
  // once per block; the plots then read the blocks from memory.
  static constexpr std::size_t kBlockColumns = 14;  // the most `with table` writes

  struct Quantity {
    std::string expr;   // gnuplot expression on the file's columns
    std::string label;  // for the comment
  };
  Quantity column_q(std::size_t col) const;

  // "$rowsB using a:b" for quantities placed together in one block (with
  // with_t, "$rowsB using 1:a" for one quantity against t).
  std::string source(const std::vector<Quantity>& qs, bool with_t = false);

  void write_blocks(std::ostringstream& os) const;
  double t0() const;
  double t1() const;
  std::pair<double, double> time_range() const;
  std::pair<double, double> col_range(const std::vector<std::size_t>& cols) const;
  double spread(std::size_t col) const;
  // Does coordinate i (or its rate) vary, beyond rounding, compared with the
  // others of its unit? (A body at rest may jitter by 1e-17 m.)
  bool varies(std::size_t i, bool rate) const;

  void preamble(std::ostringstream& os) const;

  std::string formats() const;

  // Opens the loop over formats for one plot; close with end_plot().
  void begin_plot(const char* name);
  void end_plot();

  // Style of coordinate i drawn as the k-th line of a panel: in particle
  // scenes the colour of its body (as on the trajectory plot) and a dash
  // pattern for its axis (x solid, y dashed, z dash-dotted); else the k-th colour.
  static constexpr const char* kAxisDash[3] = {" dt 1", " dt 2", " dt 4"};
  std::string line_style(std::size_t i, std::size_t k, bool dashes = true) const;

  // Dashed vertical lines at the impact times (needs `set y2range [0:1]`).
  // Many impacts: a short tick each along the top edge instead (a rug).
  std::string impact_lines(bool with_title) const;
  // Open circles, or small translucent dots when there are many.
  static std::string impact_point_style(std::size_t marks);
  void impact_axis();

  // 1. Particle paths, or the path in configuration space.
  void trajectory();
  void particle_trajectory();
  std::pair<int, int> particle_axes() const;
  std::size_t start_and_impact_points(const std::vector<std::size_t>& drawable, const std::vector<std::size_t>& hcols,
                                      const std::vector<std::size_t>& vcols, bool in_plane);
  void generalized_trajectory();
  // Inside a plot of axis `ah` (0–2; −1: t) against axis `av`, in the ranges
  // hr × vr: the planes that stand across it as lines (set arrow), named.
  void plane_lines(int ah, int av, std::pair<double, double> hr, std::pair<double, double> vr);
  // The watched events at (h, v) columns (hcol = npos: t) as a data block
  // $marks; returns the plot clauses for it ("" when there are none).
  std::string mark_block(std::size_t hcol, std::size_t vcol);

  void coordinates();
  void energy();
  void phase();

  const PlotSpec& spec_;
  const Trajectory& tr_;
  const Columns& cols_;
  const std::vector<Impact>& impacts_;    // marked against time
  const std::vector<Impact>& positions_;  // marked on the trajectory
  const std::vector<Impact>& marks_;      // watched events, marked by name on the trajectory
  std::size_t impacts_total_;
  std::vector<std::string> coords_, units_;
  std::string data_path_;
  std::size_t every_ = 1;
  bool impacts_lose_energy_ = false;
  std::vector<std::vector<Quantity>> blocks_;  // what each data block $rows<k> holds after t
  std::ostringstream os_;
};

}  // namespace lagrangian::plots_detail
