#include "lagrangian/plots.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "lagrangian/errors.hpp"

namespace lagrangian {

namespace {

namespace fs = std::filesystem;

constexpr std::size_t kPointsPerLine = 5000;  // rows are thinned to about this many per line
constexpr std::size_t kMaxImpactMarks = 2000;  // more impacts are thinned evenly
constexpr std::size_t kMaxImpactLines = 50;    // beyond, impact times are ticks, not lines across
constexpr std::size_t kMaxImpactCircles = 50;  // beyond, impact positions are small translucent dots
constexpr std::size_t kLegendBodies = 10;      // at most this many bodies get a legend entry
constexpr std::size_t kMaxBodiesUnlabelled = 40;  // up to this many bodies are drawn without legend
constexpr std::size_t kMaxLinesPerPanel = 10;  // coordinates drawn per unit panel (one colour each)
constexpr int kMaxPhasePanels = 4;
constexpr const char* kNotFound = "gnuplot not found; install it with: apt-get install gnuplot-nox (plots skipped)";
constexpr const char* kPlotNames[] = {"trajectory", "coordinates", "energy", "phase"};

// ---------------------------------------------------------------- helpers

// A gnuplot single-quoted string: no escapes inside, a quote is doubled; a
// line break (which would end the command) becomes a space.
std::string gp_str(std::string_view s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += "''";
    else if (c == '\n' || c == '\r') out += ' ';
    else out += c;
  }
  return out + "'";
}

// The shortest text that reads back as exactly v; NaN for a non-finite value.
std::string num(double v) {
  if (!std::isfinite(v)) return "NaN";
  char buf[40];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  return ec == std::errc() ? std::string(buf, end) : "NaN";
}

std::string short_num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

std::string with_unit(const std::string& what, const std::string& unit) {
  return unit.empty() ? what : what + " (" + unit + ")";
}

std::string rate_unit(const std::string& unit) { return unit.empty() ? "1/s" : unit + "/s"; }

std::string join(const std::vector<std::string>& parts, const std::string& sep) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? sep : "") + parts[i];
  return out;
}

std::string titled(const std::string& scene, const std::string& what) {
  return scene.empty() ? what : scene + ": " + what;
}

// A padded axis range around [lo, hi] (finite values only).
std::pair<double, double> padded(double lo, double hi, double pad = 0.05) {
  if (!(lo <= hi)) return {-1, 1};  // no finite value at all
  const double span = hi - lo;
  if (span > 0) return {lo - pad * span, hi + pad * span};
  const double half = std::max(1e-3, 0.1 * std::abs(lo));
  return {lo - half, hi + half};
}

// Height / width of the plot area of a 1000×700 page with a title and axis
// labels, with and without a legend on the right.
constexpr double kAspectWithKey = 0.74;
constexpr double kAspectNoKey = 0.64;

// Widens h or v (about its centre) so that their spans have the ratio `aspect`.
void fill_aspect(std::pair<double, double>& h, std::pair<double, double>& v, double aspect) {
  const double hs = h.second - h.first, vs = v.second - v.first;
  if (!(hs > 0) || !(vs > 0)) return;
  if (vs < aspect * hs) {
    const double grow = (aspect * hs - vs) / 2;
    v = {v.first - grow, v.second + grow};
  } else {
    const double grow = (vs / aspect - hs) / 2;
    h = {h.first - grow, h.second + grow};
  }
}

std::string range(std::pair<double, double> r) { return "[" + num(r.first) + ":" + num(r.second) + "]"; }

std::vector<std::string> split_csv_line(const std::string& line) {
  // Fields separated by commas; a field may be double-quoted with "" for a quote.
  std::vector<std::string> fields;
  std::string field;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        field += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        field += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.push_back(std::move(field));
      field.clear();
    } else {
      field += c;
    }
  }
  fields.push_back(std::move(field));
  return fields;
}

// Reads lines with POSIX getline (fast on large files).
class LineReader {
 public:
  explicit LineReader(const std::string& path) : file_(std::fopen(path.c_str(), "r")) {}
  ~LineReader() {
    std::free(buf_);
    if (file_) std::fclose(file_);
  }
  LineReader(const LineReader&) = delete;
  LineReader& operator=(const LineReader&) = delete;
  bool ok() const { return file_ != nullptr; }
  bool failed() const { return file_ && std::ferror(file_); }
  // The next line without its end of line, or nullopt-like false at the end.
  bool next(std::string_view& line) {
    const ssize_t n = ::getline(&buf_, &cap_, file_);
    if (n < 0) return false;
    std::size_t len = static_cast<std::size_t>(n);
    while (len > 0 && (buf_[len - 1] == '\n' || buf_[len - 1] == '\r')) --len;
    line = std::string_view(buf_, len);
    return true;
  }

 private:
  std::FILE* file_;
  char* buf_ = nullptr;
  std::size_t cap_ = 0;
};

bool parse_double(std::string_view s, double& v) {
  while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
  while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return false;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return ec == std::errc() && ptr == s.data() + s.size();
}

// ---------------------------------------------------------------- inputs

struct Impact {
  double t = 0;
  std::string bodies;
  double ke_before = 0, ke_after = 0;  // kinetic energy just before and after (J), 0 when not given
  std::vector<double> row;  // the columns Trajectory::slot names, at time t (interpolated)
};

struct Trajectory {
  std::vector<std::string> header;
  std::size_t rows = 0;
  std::size_t every = 1;            // rows are drawn every `every` (about kPointsPerLine per line)
  std::vector<double> first, last;  // first and last rows
  std::vector<double> lo, hi;       // finite minimum and maximum of every column
  std::vector<std::size_t> slot;    // per column: its index in Impact::row, or npos
  bool kept(std::size_t col) const { return slot.at(col) != std::string::npos; }
  // Column `col` of the trajectory at an impact.
  double at(const Impact& imp, std::size_t col) const { return imp.row.at(slot.at(col)); }
};

// All impacts of the events file, in time order (none if it does not exist).
std::vector<Impact> read_impacts(const std::string& path) {
  std::vector<Impact> impacts;
  if (path.empty()) return impacts;
  std::error_code ec;
  if (!fs::exists(path, ec)) return impacts;
  if (fs::is_directory(path, ec)) throw OptionError("cannot read events file '" + path + "': it is a directory");
  LineReader in(path);
  if (!in.ok()) throw OptionError("cannot read events file '" + path + "': " + std::strerror(errno));
  std::string_view line;
  if (!in.next(line)) return impacts;  // empty file: no events
  const std::vector<std::string> header = split_csv_line(std::string(line));
  auto col = [&](const char* name) {
    const auto it = std::find(header.begin(), header.end(), name);
    if (it == header.end())
      throw OptionError("events file '" + path + "' has no column '" + name + "' (header: " + std::string(line) + ")");
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t ct = col("t"), ck = col("kind"), cb = col("bodies");
  const auto optional_col = [&](const char* name) {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? std::string::npos : static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t ckb = optional_col("ke_before"), cka = optional_col("ke_after");
  std::size_t lineno = 1;
  while (in.next(line)) {
    ++lineno;
    if (line.empty()) continue;
    const std::vector<std::string> f = split_csv_line(std::string(line));
    if (f.size() <= std::max({ct, ck, cb}))
      throw OptionError("events file '" + path + "', line " + std::to_string(lineno) + ": too few fields");
    if (f[ck] != "impact") continue;
    Impact imp;
    if (!parse_double(f[ct], imp.t))
      throw OptionError("events file '" + path + "', line " + std::to_string(lineno) + ": bad time '" + f[ct] + "'");
    imp.bodies = f[cb];
    if (ckb < f.size() && cka < f.size() && !(parse_double(f[ckb], imp.ke_before) && parse_double(f[cka], imp.ke_after)))
      imp.ke_before = imp.ke_after = 0;
    impacts.push_back(std::move(imp));
  }
  if (in.failed()) throw OptionError("reading events file '" + path + "' failed");
  std::stable_sort(impacts.begin(), impacts.end(), [](const Impact& a, const Impact& b) { return a.t < b.t; });
  return impacts;
}

// At most kMaxImpactMarks of `impacts`, evenly chosen (the first and the last kept).
std::vector<Impact> thinned(const std::vector<Impact>& impacts) {
  if (impacts.size() <= kMaxImpactMarks) return impacts;
  std::vector<Impact> kept;
  const double step = static_cast<double>(impacts.size() - 1) / static_cast<double>(kMaxImpactMarks - 1);
  for (std::size_t k = 0; k < kMaxImpactMarks; ++k)
    kept.push_back(impacts[static_cast<std::size_t>(std::llround(static_cast<double>(k) * step))]);
  return kept;
}

// Number of data lines (non-empty lines after the header) of a file.
std::size_t count_data_lines(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw OptionError("cannot read trajectory file '" + path + "': " + std::strerror(errno));
  std::vector<char> buf(1 << 20);
  std::size_t lines = 0;
  char prev = '\n';      // the character before the current one
  bool header = true;    // still in the first line
  while (true) {
    const std::size_t got = std::fread(buf.data(), 1, buf.size(), f);
    if (got == 0) break;
    const char* p = buf.data();
    const char* end = p + got;
    while (p < end) {
      const char* nl = static_cast<const char*>(std::memchr(p, '\n', static_cast<std::size_t>(end - p)));
      if (!nl) {
        prev = end[-1];
        break;
      }
      // A line ends at nl: it is a data line unless it is the header or empty.
      const char before = nl > p ? nl[-1] : prev;
      if (header) {
        header = false;
      } else if (before != '\n' && !(before == '\r' && (nl - 1 > p ? nl[-2] : prev) == '\n')) {
        ++lines;
      }
      prev = '\n';
      p = nl + 1;
    }
  }
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw OptionError("reading trajectory file '" + path + "' failed");
  if (!header && prev != '\n' && prev != '\r') ++lines;  // a last line without end of line
  return lines;
}

// Reads the trajectory: header, row count, and — over the rows gnuplot will
// draw (every `every`-th, and the last) — the column ranges; the first and
// last rows; at the impact times (from the rows around each), t and the
// columns named in at_impacts (all columns when it is empty). Other rows are only checked for their field count and
// time, so that files of millions of rows read quickly.
Trajectory read_trajectory(const std::string& path, std::vector<Impact>& impacts,
                           const std::vector<std::string>& at_impacts) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw OptionError("cannot read trajectory file '" + path + "': it is a directory");
  LineReader in(path);
  if (!in.ok()) throw OptionError("cannot read trajectory file '" + path + "': " + std::strerror(errno));
  Trajectory tr;
  std::string_view line;
  if (!in.next(line)) throw OptionError("trajectory file '" + path + "' is empty (expected a header t,...)");
  tr.header = split_csv_line(std::string(line));
  if (tr.header.empty() || tr.header[0] != "t")
    throw OptionError("trajectory file '" + path + "' does not start with the header 't,...' (found '" +
                      std::string(line.substr(0, 80)) + "')");
  const std::size_t total_rows = count_data_lines(path);
  if (total_rows == 0) throw OptionError("trajectory file '" + path + "' has no data rows");
  tr.every = std::max<std::size_t>(1, (total_rows + kPointsPerLine - 1) / kPointsPerLine);

  const std::size_t ncol = tr.header.size();
  // The rate column of each column ("x" → "x_dot"), for impact positions.
  std::vector<std::size_t> rate(ncol, std::string::npos);
  {
    std::unordered_map<std::string, std::size_t> index;
    for (std::size_t k = 0; k < ncol; ++k) index.emplace(tr.header[k], k);
    for (std::size_t k = 1; k < ncol; ++k)
      if (const auto it = index.find(tr.header[k] + "_dot"); it != index.end()) rate[k] = it->second;
  }
  // The columns kept at the impacts (t and those named in at_impacts).
  tr.slot.assign(ncol, std::string::npos);
  std::vector<std::size_t> kept = {0};
  tr.slot[0] = 0;
  for (std::size_t k = 1; k < ncol; ++k)
    if (at_impacts.empty() || std::find(at_impacts.begin(), at_impacts.end(), tr.header[k]) != at_impacts.end()) {
      tr.slot[k] = kept.size();
      kept.push_back(k);
    }
  auto keep = [&](const std::vector<double>& full) {
    std::vector<double> r;
    for (std::size_t k : kept) r.push_back(full[k]);
    return r;
  };
  tr.lo.assign(ncol, std::numeric_limits<double>::infinity());
  tr.hi.assign(ncol, -std::numeric_limits<double>::infinity());
  std::vector<double> cur(ncol), prev(ncol);
  std::string prev_line;
  std::size_t lineno = 1;
  auto fail = [&](const std::string& what) {
    throw OptionError("trajectory file '" + path + "', line " + std::to_string(lineno) + ": " + what);
  };
  auto parse_row = [&](std::string_view text, std::vector<double>& row) {
    std::size_t c = 0, pos = 0;
    while (true) {
      const std::size_t comma = text.find(',', pos);
      const std::string_view field = text.substr(pos, comma == std::string_view::npos ? text.npos : comma - pos);
      if (!parse_double(field, row[c]))
        fail("bad number '" + std::string(field.substr(0, 40)) + "' in column '" + tr.header[c] + "'");
      ++c;
      if (comma == std::string_view::npos) break;
      pos = comma + 1;
    }
  };
  std::size_t next_impact = 0;
  double t_prev = 0;
  while (in.next(line)) {
    ++lineno;
    if (line.empty()) continue;
    const auto fields = static_cast<std::size_t>(std::count(line.begin(), line.end(), ',')) + 1;
    if (fields != ncol)
      fail(std::to_string(fields) + " fields, the header has " + std::to_string(ncol));
    const std::size_t row = tr.rows++;
    const bool drawn = row % tr.every == 0 || row + 1 == total_rows;
    bool parsed = false;
    double t = 0;
    if (drawn) {
      parse_row(line, cur);
      parsed = true;
      t = cur[0];
      for (std::size_t k = 0; k < ncol; ++k) {
        const double v = cur[k];
        if (std::isfinite(v)) {
          tr.lo[k] = std::min(tr.lo[k], v);
          tr.hi[k] = std::max(tr.hi[k], v);
        }
      }
      if (row == 0) tr.first = cur;
      if (row + 1 == total_rows) tr.last = cur;
    } else {
      const std::string_view field = line.substr(0, line.find(','));
      if (!parse_double(field, t)) fail("bad time '" + std::string(field.substr(0, 40)) + "'");
    }
    if (next_impact < impacts.size() && impacts[next_impact].t <= t) {
      if (!parsed) parse_row(line, cur);
      if (row > 0) parse_row(prev_line, prev);  // the previous row, in full
      while (next_impact < impacts.size() && impacts[next_impact].t <= t) {
        Impact& imp = impacts[next_impact++];
        if (row > 0 && t > t_prev && imp.t >= t_prev) {
          // Positions have a kink at an impact: each side's own rate carries
          // it to the impact time (error O(dt²)); the mean of both is taken.
          // Other columns are interpolated linearly.
          const double w = (imp.t - t_prev) / (t - t_prev);
          imp.row.clear();
          for (std::size_t k : kept) {
            if (rate[k] != std::string::npos) {
              const double from_before = prev[k] + prev[rate[k]] * (imp.t - t_prev);
              const double from_after = cur[k] - cur[rate[k]] * (t - imp.t);
              imp.row.push_back(0.5 * (from_before + from_after));
            } else {
              imp.row.push_back(prev[k] + w * (cur[k] - prev[k]));
            }
          }
        } else {
          imp.row = keep(cur);
        }
      }
    }
    t_prev = t;
    if (next_impact < impacts.size()) prev_line.assign(line.data(), line.size());
  }
  if (in.failed()) throw OptionError("reading trajectory file '" + path + "' failed");
  if (tr.rows != total_rows || tr.last.empty())
    throw OptionError("trajectory file '" + path + "' changed while it was read");
  for (std::size_t k = next_impact; k < impacts.size(); ++k) impacts[k].row = keep(tr.last);
  return tr;
}

// Does an event's `bodies` field ("ball-floor", "s1-s2") name this body?
bool names_body(const std::string& bodies, const std::string& body) {
  if (body.empty()) return false;
  if (bodies == body) return true;
  const std::string left = body + "-", right = "-" + body;
  if (bodies.size() > body.size() && bodies.compare(0, left.size(), left) == 0) return true;
  if (bodies.size() > body.size() && bodies.compare(bodies.size() - right.size(), right.size(), right) == 0)
    return true;
  return bodies.find("-" + body + "-") != std::string::npos;
}

// ---------------------------------------------------------------- processes

std::string find_on_path(const std::string& program) {
  const char* path_env = std::getenv("PATH");
  const std::string path = path_env ? path_env : "/usr/local/bin:/usr/bin:/bin";
  std::size_t start = 0;
  while (start <= path.size()) {
    std::size_t end = path.find(':', start);
    if (end == std::string::npos) end = path.size();
    std::string dir = path.substr(start, end - start);
    if (dir.empty()) dir = ".";
    const std::string candidate = dir + "/" + program;
    struct stat st {};
    if (::stat(candidate.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
    start = end + 1;
  }
  return {};
}

struct ProcessResult {
  int status = -1;  // exit status, or -1 when it did not exit normally
  std::string err;  // what it wrote on stderr
};

// Runs `exe args...` in directory `cwd` (if not empty) with stdin and stdout
// on /dev/null; collects stderr. No shell is involved, so paths need no quoting.
ProcessResult run_process(const std::string& exe, const std::vector<std::string>& args, const std::string& cwd) {
  std::vector<std::string> argv_store;
  argv_store.push_back(exe);
  argv_store.insert(argv_store.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : argv_store) argv.push_back(a.data());
  argv.push_back(nullptr);

  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) throw OptionError(std::string("cannot create a pipe: ") + std::strerror(errno));
  const int devnull = ::open("/dev/null", O_RDWR | O_CLOEXEC);
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int e = errno;
    ::close(fds[0]);
    ::close(fds[1]);
    if (devnull >= 0) ::close(devnull);
    throw OptionError("cannot start '" + exe + "': " + std::strerror(e));
  }
  if (pid == 0) {  // child: only async-signal-safe calls
    if (devnull >= 0) {
      ::dup2(devnull, STDIN_FILENO);
      ::dup2(devnull, STDOUT_FILENO);
    }
    ::dup2(fds[1], STDERR_FILENO);
    if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) ::_exit(126);
    ::execv(exe.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  if (devnull >= 0) ::close(devnull);
  ProcessResult r;
  char buf[4096];
  while (true) {
    const ssize_t n = ::read(fds[0], buf, sizeof buf);
    if (n > 0) {
      if (r.err.size() < (1u << 20)) r.err.append(buf, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(fds[0]);
  int wstatus = 0;
  while (::waitpid(pid, &wstatus, 0) < 0 && errno == EINTR) {
  }
  r.status = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
  return r;
}

std::string trim(std::string s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  std::size_t i = 0;
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  return s.substr(i);
}

// Colours (the Tableau 10 palette), the settings every plot starts from
// (`setup`) and the two terminals (`png_terminal`, `svg_terminal`) at
// width × height pixels.
void write_styles(std::ostream& os, int width, int height) {
  os << "# Colours (the Tableau 10 palette) and the settings every plot starts from.\n";
  static const char* palette[] = {"#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd",
                                  "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};
  for (int i = 0; i < 10; ++i) os << "set linetype " << i + 1 << " lc rgb '" << palette[i] << "' lw 1.5 pt 7 ps 0.8\n";
  const std::string size = std::to_string(width) + "," + std::to_string(height);
  os << "set linetype cycle 10\n"
     << "setup = \"set encoding utf8; "
        "set grid lc rgb '#d9d9d9' lw 1 dt 1; set key noautotitle spacing 1.2; set tics front\"\n"
     << "png_terminal = \"set terminal pngcairo size " << size
     << " noenhanced font 'Sans,11' linewidth 1 background rgb 'white'\"\n"
     << "svg_terminal = \"set terminal svg size " << size
     << " noenhanced dynamic font 'Sans,12' linewidth 1 background rgb 'white'\"\n\n";
}

// ---------------------------------------------------------------- the script

struct Columns {
  std::vector<std::size_t> q, qd;  // column of each coordinate and its rate
  std::size_t energy = 0;
  std::size_t total_energy = 0;  // 0: absent
};

class ScriptWriter {
 public:
  // `impacts`: all impacts of the run; `times`: those marked on the plots
  // against time; `positions`: those marked on the trajectory (rows filled).
  ScriptWriter(const PlotSpec& spec, const Trajectory& tr, const Columns& cols, const std::vector<Impact>& impacts,
               const std::vector<Impact>& times, const std::vector<Impact>& positions,
               std::vector<std::string> coords, std::vector<std::string> units, std::string data_path)
      : spec_(spec),
        tr_(tr),
        cols_(cols),
        impacts_(times),
        positions_(positions),
        impacts_total_(impacts.size()),
        coords_(std::move(coords)),
        units_(std::move(units)),
        data_path_(std::move(data_path)) {
    every_ = tr_.every;
    for (const Impact& imp : impacts)
      if (imp.ke_before - imp.ke_after > 1e-9 * std::abs(imp.ke_before)) impacts_lose_energy_ = true;
  }

  std::string write() {
    trajectory();
    coordinates();
    energy();
    phase();
    std::ostringstream head;
    preamble(head);
    write_blocks(head);
    return head.str() + os_.str();
  }

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
  Quantity column_q(std::size_t col) const { return {"column(" + std::to_string(col + 1) + ")", tr_.header[col]}; }

  // "$rowsB using a:b" for quantities placed together in one block (with
  // with_t, "$rowsB using 1:a" for one quantity against t).
  std::string source(const std::vector<Quantity>& qs, bool with_t = false) {
    auto find_in = [&](std::size_t b, const Quantity& q) -> int {
      for (std::size_t k = 0; k < blocks_[b].size(); ++k)
        if (blocks_[b][k].expr == q.expr) return static_cast<int>(k) + 2;  // column 1 is t
      return 0;
    };
    std::size_t block = blocks_.size();
    for (std::size_t b = 0; b < blocks_.size() && block == blocks_.size(); ++b) {
      bool all = true;
      for (const Quantity& q : qs) all = all && find_in(b, q);
      if (all) block = b;
    }
    if (block == blocks_.size()) {  // add the missing ones to the last block, or open a new one
      if (!blocks_.empty()) {
        std::size_t missing = 0;
        for (const Quantity& q : qs) missing += find_in(blocks_.size() - 1, q) ? 0 : 1;
        if (blocks_.back().size() + missing <= kBlockColumns - 1) block = blocks_.size() - 1;
      }
      if (block == blocks_.size()) blocks_.emplace_back();
      for (const Quantity& q : qs)
        if (!find_in(block, q)) blocks_[block].push_back(q);
    }
    std::string out = "$rows" + std::to_string(block + 1) + " using " + (with_t ? "1" : "");
    for (std::size_t k = 0; k < qs.size(); ++k)
      out += (with_t || k ? ":" : "") + std::to_string(find_in(block, qs[k]));
    return out;
  }

  void write_blocks(std::ostringstream& os) const {
    os << "# The data the plots use: every n-th row of the trajectory, only the columns\n"
       << "# needed, read once per block below into memory (column 1 of each block is t).\n"
       << "# Values are written with 12 significant digits.\n"
       << "g(x) = sprintf('%.12g', x)\n"
       << "set datafile separator comma\n";
    for (std::size_t b = 0; b < blocks_.size(); ++b) {
      os << "set table $rows" << b + 1 << "    # t";
      for (const Quantity& q : blocks_[b]) os << ", " << q.label;
      os << "\nplot data every n::1 using (g(column(1)))";  // point 0 of the file is its header
      for (const Quantity& q : blocks_[b]) os << ":(g(" << q.expr << "))";
      os << " with table\nunset table\n";
    }
    os << "set datafile separator whitespace\n\n";
  }
  double t0() const { return tr_.first[0]; }
  double t1() const { return tr_.last[0]; }
  std::pair<double, double> time_range() const {
    return t1() > t0() ? std::pair{t0(), t1()} : padded(t0(), t1());
  }
  std::pair<double, double> col_range(const std::vector<std::size_t>& cols) const {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t k : cols) {
      lo = std::min(lo, tr_.lo[k]);
      hi = std::max(hi, tr_.hi[k]);
    }
    return padded(lo, hi);
  }
  double spread(std::size_t col) const { return tr_.hi[col] >= tr_.lo[col] ? tr_.hi[col] - tr_.lo[col] : 0.0; }
  // Does coordinate i (or its rate) vary, beyond rounding, compared with the
  // others of its unit? (A body at rest may jitter by 1e-17 m.)
  bool varies(std::size_t i, bool rate) const {
    const auto& cols = rate ? cols_.qd : cols_.q;
    double largest = 0;
    for (std::size_t j = 0; j < coords_.size(); ++j)
      if (units_[j] == units_[i]) largest = std::max(largest, spread(cols[j]));
    return spread(cols[i]) > 1e-9 * largest;
  }

  void preamble(std::ostringstream& os) const {
    os << "# Plots of the run" << (spec_.title.empty() ? "" : " " + gp_str(spec_.title))
        << ", written by lagrangian::make_plots.\n"
        << "# Draw them again with:   cd <this directory> && gnuplot plots.gp\n"
        << "# Set before the script with -e: formats (default below), suffix (added to each\n"
        << "# image name before the extension; make_plots uses '.partial' and renames).\n"
        << "if (!exists(\"formats\")) formats = " << gp_str(formats()) << "\n"
        << "if (!exists(\"suffix\")) suffix = ''\n\n"
        << "data = " << gp_str(data_path_) << "\n"
        << "n = " << every_ << "    # plot every n-th row: " << tr_.rows << " rows, about " << kPointsPerLine
        << " points per line\n"
        << "E0 = " << num(tr_.first[cols_.energy]) << "    # energy at t0 (J)\n";
    if (cols_.total_energy)
      os << "Etot0 = " << num(tr_.first[cols_.total_energy]) << "    # T + V at t0 (J)\n";
    os << "Escale = " << num(spec_.energy_scale) << "    # energy scale (J)\n\n";

    write_styles(os, 1000, 700);

    // Impact times and, per plot, the impact points: inline data blocks.
    if (!impacts_.empty()) {
      os << "# Impacts (events of kind 'impact')";
      if (impacts_total_ > impacts_.size())
        os << ": " << impacts_.size() << " of " << impacts_total_ << ", evenly chosen";
      os << ".\n$impacts << EOD\n# t (s)\n";
      for (const Impact& imp : impacts_) os << num(imp.t) << "\n";
      os << "EOD\n\n";
    }
  }

  std::string formats() const {
    std::string f;
    if (spec_.png) f = "png";
    if (spec_.svg) f += f.empty() ? "svg" : " svg";
    return f;
  }

  // Opens the loop over formats for one plot; close with end_plot().
  void begin_plot(const char* name) {
    os_ << "do for [fmt in formats] {\n"
        << "  reset\n"
        << "  eval setup\n"
        << "  if (fmt eq 'png') { eval png_terminal } else { eval svg_terminal }\n"
        << "  set output '" << name << "'.suffix.'.'.fmt\n";
  }
  void end_plot() { os_ << "  set output\n}\n\n"; }

  // Style of coordinate i drawn as the k-th line of a panel: in particle
  // scenes the colour of its body (as on the trajectory plot) and a dash
  // pattern for its axis (x solid, y dashed, z dash-dotted); else the k-th colour.
  static constexpr const char* kAxisDash[3] = {" dt 1", " dt 2", " dt 4"};
  std::string line_style(std::size_t i, std::size_t k, bool dashes = true) const {
    const auto& bodies = spec_.bodies;
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      const int idx[3] = {bodies[b].x, bodies[b].y, bodies[b].z};
      for (int a = 0; a < 3; ++a)
        if (idx[a] == static_cast<int>(i))
          return "lt " + std::to_string(b % 10 + 1) + (dashes ? std::string(kAxisDash[a]) : std::string());
    }
    return "lt " + std::to_string(k % 10 + 1);
  }

  // Dashed vertical lines at the impact times (needs `set y2range [0:1]`).
  // Many impacts: a short tick each along the top edge instead (a rug).
  std::string impact_lines(bool with_title) const {
    if (impacts_.empty()) return {};
    const bool rug = impacts_.size() > kMaxImpactLines;
    const std::string title = rug ? "impact (ticks)" : "impact";
    return std::string(", \\\n       $impacts using 1:") + (rug ? "(0.965):(0):(0.035)" : "(0):(0):(1)") +
           " axes x1y2 with vectors nohead " + (rug ? "lw 1 lc rgb '#60000000' " : "dt 2 lw 1 lc rgb '#707070' ") +
           (with_title ? "title " + gp_str(title) : std::string("notitle"));
  }
  // Open circles, or small translucent dots when there are many.
  static std::string impact_point_style(std::size_t marks) {
    return marks <= kMaxImpactCircles ? "with points pt 6 ps 1.6 lw 1.5 lc rgb 'black' title 'impact'"
                                      : "with points pt 7 ps 0.5 lc rgb '#a0000000' title 'impact'";
  }
  void impact_axis() {
    if (!impacts_.empty()) os_ << "  set y2range [0:1]; unset y2tics\n";
  }

  // 1. Particle paths, or the path in configuration space.
  void trajectory() {
    os_ << "# 1. Trajectory\n";
    if (!spec_.bodies.empty()) {
      particle_trajectory();
    } else {
      generalized_trajectory();
    }
  }

  void particle_trajectory() {
    const auto& bodies = spec_.bodies;
    // Spread of each Cartesian axis over all bodies.
    double lo[3], hi[3];
    bool present[3] = {false, false, false};
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::numeric_limits<double>::infinity();
      hi[a] = -lo[a];
    }
    for (const auto& b : bodies) {
      const int idx[3] = {b.x, b.y, b.z};
      for (int a = 0; a < 3; ++a) {
        if (idx[a] < 0) continue;
        present[a] = true;
        const std::size_t col = cols_.q[static_cast<std::size_t>(idx[a])];
        lo[a] = std::min(lo[a], tr_.lo[col]);
        hi[a] = std::max(hi[a], tr_.hi[col]);
      }
    }
    std::vector<int> axes;
    for (int a = 0; a < 3; ++a)
      if (present[a]) axes.push_back(a);
    auto axis_spread = [&](int a) { return hi[a] >= lo[a] ? hi[a] - lo[a] : 0.0; };
    std::stable_sort(axes.begin(), axes.end(), [&](int a, int b) { return axis_spread(a) > axis_spread(b); });
    const bool planar = axes.size() >= 2 && axis_spread(axes[1]) > 1e-6 * axis_spread(axes[0]);
    const bool still = axes.size() >= 2 && axis_spread(axes[0]) == 0;  // nothing moves: show the positions
    int ah = axes.empty() ? 0 : axes[0], av = -1;
    if (planar || still) {
      ah = std::min(axes[0], axes[1]);
      av = std::max(axes[0], axes[1]);
    }
    static const char* axis_name[3] = {"x", "y", "z"};
    auto index_of = [](const PlotSpec::Body& b, int a) { return a == 0 ? b.x : a == 1 ? b.y : b.z; };

    // Bodies drawn: those with both axes; beyond kMaxBodiesUnlabelled only the first kLegendBodies.
    std::vector<std::size_t> drawable;
    for (std::size_t i = 0; i < bodies.size(); ++i)
      if (index_of(bodies[i], ah) >= 0 && (av < 0 || index_of(bodies[i], av) >= 0)) drawable.push_back(i);
    if (drawable.empty()) {  // no body has the axes: fall back to the configuration-space plot
      generalized_trajectory();
      return;
    }
    const std::size_t total = drawable.size();
    if (total > kMaxBodiesUnlabelled) drawable.resize(kLegendBodies);
    const bool legend = drawable.size() <= kLegendBodies;

    std::string unit_h, unit_v;
    std::vector<std::size_t> hcols, vcols;
    for (std::size_t i : drawable) {
      const auto ih = static_cast<std::size_t>(index_of(bodies[i], ah));
      hcols.push_back(cols_.q[ih]);
      if (unit_h.empty()) unit_h = units_[ih];
      if (av >= 0) {
        const auto iv = static_cast<std::size_t>(index_of(bodies[i], av));
        vcols.push_back(cols_.q[iv]);
        if (unit_v.empty()) unit_v = units_[iv];
      }
    }
    std::string what;
    if (av >= 0) {
      what = std::string("trajectory in the ") + axis_name[ah] + "–" + axis_name[av] + " plane";
    } else {
      what = std::string("position along ") + axis_name[ah] + " against time";
    }
    if (drawable.size() < total) {
      what += " (first " + std::to_string(drawable.size()) + " of " + std::to_string(total) + " bodies)";
    } else if (!legend) {
      what += " (" + std::to_string(total) + " bodies)";
    }

    // Start points and impact points.
    os_ << "$start << EOD\n# h v linetype\n";
    for (std::size_t k = 0; k < drawable.size(); ++k) {
      const double h = av >= 0 ? tr_.first[hcols[k]] : tr_.first[0];
      const double v = av >= 0 ? tr_.first[vcols[k]] : tr_.first[hcols[k]];
      os_ << num(h) << " " << num(v) << " " << (drawable[k] % 10) + 1 << "\n";
    }
    os_ << "EOD\n";
    std::size_t marks = 0;
    std::ostringstream pts;
    for (const Impact& imp : positions_) {
      for (std::size_t k = 0; k < drawable.size(); ++k) {
        if (!names_body(imp.bodies, bodies[drawable[k]].name) || !tr_.kept(hcols[k]) ||
            (av >= 0 && !tr_.kept(vcols[k])))
          continue;
        const double h = av >= 0 ? tr_.at(imp, hcols[k]) : imp.t;
        const double v = av >= 0 ? tr_.at(imp, vcols[k]) : tr_.at(imp, hcols[k]);
        pts << num(h) << " " << num(v) << "\n";
        ++marks;
      }
    }
    if (marks) os_ << "$impact_points << EOD\n# h v\n" << pts.str() << "EOD\n";

    std::pair<double, double> hr, vr;
    if (av >= 0) {
      hr = col_range(hcols);
      vr = col_range(vcols);
      // Equal scales: widen the shorter range (centred) so that the data
      // aspect matches the plot area and the picture fills the page.
      fill_aspect(hr, vr, legend ? kAspectWithKey : kAspectNoKey);
    } else {
      hr = time_range();
      vr = col_range(hcols);
    }

    begin_plot("trajectory");
    os_ << "  set title " << gp_str(titled(spec_.title, what)) << "\n";
    if (av >= 0) {
      os_ << "  set xlabel " << gp_str(with_unit(axis_name[ah], unit_h)) << "\n"
          << "  set ylabel " << gp_str(with_unit(axis_name[av], unit_v)) << "\n"
          << "  set size ratio -1    # equal scales on both axes\n";
    } else {
      os_ << "  set xlabel 't (s)'\n"
          << "  set ylabel " << gp_str(with_unit(axis_name[ah], unit_h)) << "\n";
    }
    os_ << "  set xrange " << range(hr) << "\n  set yrange " << range(vr) << "\n";
    os_ << (legend ? "  set key outside right top\n" : "  unset key\n");
    os_ << "  plot ";
    for (std::size_t k = 0; k < drawable.size(); ++k) {
      const std::string src =
          av >= 0 ? source({column_q(hcols[k]), column_q(vcols[k])}) : source({column_q(hcols[k])}, true);
      os_ << (k ? ", \\\n       " : "") << src << " with lines lt " << (drawable[k] % 10) + 1
          << " lw " << (legend ? "2" : "1") << " title " << gp_str(bodies[drawable[k]].name);
    }
    // Black under the coloured points: the legend shows a neutral "start".
    os_ << ", \\\n       $start using 1:2 with points pt 7 ps 1.2 lc rgb 'black' title 'start'"
        << ", \\\n       $start using 1:2:3 with points pt 7 ps 1.2 lc variable notitle";
    if (marks) os_ << ", \\\n       $impact_points using 1:2 " << impact_point_style(marks);
    os_ << "\n";
    end_plot();
  }

  void generalized_trajectory() {
    const std::size_t n = coords_.size();
    if (n == 0) return;
    const bool two = n >= 2;
    const std::size_t ch = two ? cols_.q[0] : 0, cv = two ? cols_.q[1] : cols_.q[0];
    const std::string uh = two ? units_[0] : "s", uv = two ? units_[1] : units_[0];
    os_ << "$start << EOD\n# h v\n" << num(tr_.first[ch]) << " " << num(tr_.first[cv]) << "\nEOD\n";
    if (!positions_.empty()) {
      os_ << "$impact_points << EOD\n# h v\n";
      for (const Impact& imp : positions_) os_ << num(tr_.at(imp, ch)) << " " << num(tr_.at(imp, cv)) << "\n";
      os_ << "EOD\n";
    }
    auto hr = two ? col_range({ch}) : time_range();
    auto vr = col_range({cv});
    // Equal scales when both axes have the same unit and comparable spreads.
    const double sh = hr.second - hr.first, sv = vr.second - vr.first;
    const bool equal = two && uh == uv && sh > 0 && sv > 0 && sh / sv < 20 && sv / sh < 20;
    if (equal) fill_aspect(hr, vr, kAspectWithKey);

    begin_plot("trajectory");
    if (two) {
      os_ << "  set title " << gp_str(titled(spec_.title, "path in configuration space")) << "\n"
          << "  set xlabel " << gp_str(with_unit(coords_[0], uh)) << "\n";
    } else {
      os_ << "  set title " << gp_str(titled(spec_.title, coords_[0] + " against time")) << "\n"
          << "  set xlabel 't (s)'\n";
    }
    os_ << "  set ylabel " << gp_str(with_unit(two ? coords_[1] : coords_[0], uv)) << "\n";
    if (equal) os_ << "  set size ratio -1    # equal scales on both axes\n";
    os_ << "  set xrange " << range(hr) << "\n  set yrange " << range(vr) << "\n"
        << "  set key outside right top\n"
        << "  plot " << (two ? source({column_q(ch), column_q(cv)}) : source({column_q(cv)}, true))
        << " with lines lt 1 lw 1.5 title "
        << gp_str(two ? "path" : coords_[0]) << ", \\\n"
        << "       $start using 1:2 with points pt 7 ps 1.2 lc rgb 'black' title 'start'";
    if (!positions_.empty())
      os_ << ", \\\n       $impact_points using 1:2 " << impact_point_style(positions_.size());
    os_ << "\n";
    end_plot();
  }

  void coordinates() {
    // Panels by unit, in order of first appearance.
    std::vector<std::string> unit_order;
    std::map<std::string, std::vector<std::size_t>> groups;
    for (std::size_t i = 0; i < coords_.size(); ++i) {
      if (!groups.count(units_[i])) unit_order.push_back(units_[i]);
      groups[units_[i]].push_back(i);
    }
    const std::size_t panels = unit_order.size();
    const double top = 0.90, bottom = 0.09;
    os_ << "# 2. Coordinates against time, one panel per unit\n";
    begin_plot("coordinates");
    os_ << "  set multiplot layout " << panels << ",1 margins 0.10,0.80," << bottom << "," << top
        << " spacing 0,0.035 title " << gp_str(titled(spec_.title, "coordinates against time")) << "\n"
        << "  set xrange " << range(time_range()) << "\n";
    impact_axis();
    for (std::size_t p = 0; p < panels; ++p) {
      const std::string& unit = unit_order[p];
      std::vector<std::size_t> members = groups[unit];
      const std::size_t total = members.size();
      std::string shown;  // legend title when not all are drawn
      if (members.size() > kMaxLinesPerPanel) {
        // Too many for one panel: those that move (a constant coordinate
        // says little), at most kMaxLinesPerPanel.
        std::vector<std::size_t> moving;
        for (std::size_t i : members)
          if (varies(i, false)) moving.push_back(i);
        if (!moving.empty()) members = moving;
        if (members.size() > kMaxLinesPerPanel) members.resize(kMaxLinesPerPanel);
        shown = std::to_string(members.size()) + " of " + std::to_string(total) +
                (moving.empty() || moving.size() > kMaxLinesPerPanel ? "" : " (moving)");
      }
      std::vector<std::string> names;
      std::vector<std::size_t> cols;
      for (std::size_t i : members) {
        names.push_back(coords_[i]);
        cols.push_back(cols_.q[i]);
      }
      std::string what = total <= 3 ? join(names, ", ") : "coordinates";
      if (unit.empty() && total > 3) what = "unitless coordinates";
      const bool last = p + 1 == panels;
      os_ << "  # " << (unit.empty() ? "no unit" : unit) << "\n"
          << "  set ylabel " << gp_str(with_unit(what, unit)) << "\n"
          << "  set yrange " << range(col_range(cols)) << "\n"
          << (last ? "  set xlabel 't (s)'; set format x '%g'\n" : "  unset xlabel; set format x ''\n");
      // A legend unless the panel has a single line (named by the y label).
      if (members.size() == 1 && !(p == 0 && !impacts_.empty())) {
        os_ << "  unset key\n";
      } else {
        os_ << "  set key outside right top title " << gp_str(shown) << "\n";
      }
      os_ << "  plot ";
      for (std::size_t k = 0; k < members.size(); ++k)
        os_ << (k ? ", \\\n       " : "") << source({column_q(cols[k])}, true) << " with lines "
            << line_style(members[k], k) << " title " << gp_str(names[k]);
      os_ << impact_lines(p == 0) << "\n";
    }
    os_ << "  unset multiplot\n";
    end_plot();
  }

  void energy() {
    const double s = spec_.energy_scale;
    std::vector<std::pair<double, double>> errs = {
        {(tr_.lo[cols_.energy] - tr_.first[cols_.energy]) / s, (tr_.hi[cols_.energy] - tr_.first[cols_.energy]) / s}};
    if (cols_.total_energy)
      errs.push_back({(tr_.lo[cols_.total_energy] - tr_.first[cols_.total_energy]) / s,
                      (tr_.hi[cols_.total_energy] - tr_.first[cols_.total_energy]) / s});
    double lo = 0, hi = 0;  // the range always shows 0
    for (auto [a, b] : errs) {
      if (std::isfinite(a)) lo = std::min(lo, a);
      if (std::isfinite(b)) hi = std::max(hi, b);
    }
    std::pair<double, double> yr;
    if (hi - lo > 0) {
      yr = padded(lo, hi);
    } else {
      yr = {-1e-16, 1e-16};  // exactly conserved (to the last digit)
    }
    os_ << "# 3. Relative energy error\n";
    begin_plot("energy");
    os_ << "  set title "
        << gp_str(titled(spec_.title, "relative energy error (E_scale = " + short_num(s) + " J)") +
                  (impacts_lose_energy_ ? "; the steps at impacts are energy they took" : "")) << "\n"
        << "  set xlabel 't (s)'\n"
        << "  set ylabel '(E − E(t0)) / E_scale'\n"
        << "  set format y " << (std::max(-yr.first, yr.second) < 1e-2 ? "'%.1e'" : "'%g'") << "\n"
        << "  set xrange " << range(time_range()) << "\n"
        << "  set yrange " << range(yr) << "\n"
        << "  set key outside right top\n";
    impact_axis();
    const std::string h_err = "(column(" + std::to_string(cols_.energy + 1) + ") - E0)/Escale";
    os_ << "  plot " << source({{h_err, "(energy - E0)/Escale"}}, true) << " with lines lt 1 title "
        << (cols_.total_energy ? "'h = p·q̇ − L'" : "'energy'");
    if (cols_.total_energy) {
      const std::string e_err = "(column(" + std::to_string(cols_.total_energy + 1) + ") - Etot0)/Escale";
      os_ << ", \\\n       " << source({{e_err, "(total_energy - Etot0)/Escale"}}, true)
          << " with lines lt 2 dt 2 title 'T + V'";
    }
    // With e < 1 the steps at the impacts are the energy they took, not error.
    os_ << impact_lines(true) << "\n";
    end_plot();
  }

  void phase() {
    // Up to four coordinates whose rate varies (the informative portraits),
    // else those that move at all, else the first ones.
    std::vector<std::size_t> chosen;
    for (std::size_t i = 0; i < coords_.size() && chosen.size() < kMaxPhasePanels; ++i)
      if (varies(i, true)) chosen.push_back(i);
    if (chosen.empty())
      for (std::size_t i = 0; i < coords_.size() && chosen.size() < kMaxPhasePanels; ++i)
        if (varies(i, false)) chosen.push_back(i);
    if (chosen.empty())
      for (std::size_t i = 0; i < std::min<std::size_t>(kMaxPhasePanels, coords_.size()); ++i) chosen.push_back(i);
    if (chosen.empty()) return;
    const std::size_t np = chosen.size();
    const std::size_t rows = np <= 2 ? 1 : 2, cols = np == 1 ? 1 : 2;
    std::string what = "phase portraits";
    if (np == 1) what = "phase portrait";
    if (coords_.size() > np) what += " (" + std::to_string(np) + " of " + std::to_string(coords_.size()) + " coordinates)";
    os_ << "# 4. Phase portraits\n";
    begin_plot("phase");
    os_ << "  set multiplot layout " << rows << "," << cols << " margins 0.09,0.97,0.09," << (rows == 1 ? 0.86 : 0.90)
        << " spacing 0.10,0.13 title " << gp_str(titled(spec_.title, what)) << "\n"
        << "  unset key\n";
    for (std::size_t k = 0; k < np; ++k) {
      const std::size_t i = chosen[k];
      os_ << "  set title " << gp_str(coords_[i]) << "\n"
          << "  set xlabel " << gp_str(with_unit(coords_[i], units_[i])) << "\n"
          << "  set ylabel " << gp_str(with_unit(coords_[i] + "_dot", rate_unit(units_[i]))) << "\n"
          << "  set xrange " << range(col_range({cols_.q[i]})) << "\n"
          << "  set yrange " << range(col_range({cols_.qd[i]})) << "\n"
          << "  plot " << source({column_q(cols_.q[i]), column_q(cols_.qd[i])}) << " with lines "
          << line_style(i, k, false) << "\n";
    }
    os_ << "  unset multiplot\n";
    end_plot();
  }

  const PlotSpec& spec_;
  const Trajectory& tr_;
  const Columns& cols_;
  const std::vector<Impact>& impacts_;    // marked against time
  const std::vector<Impact>& positions_;  // marked on the trajectory
  std::size_t impacts_total_;
  std::vector<std::string> coords_, units_;
  std::string data_path_;
  std::size_t every_ = 1;
  bool impacts_lose_energy_ = false;
  std::vector<std::vector<Quantity>> blocks_;  // what each data block $rows<k> holds after t
  std::ostringstream os_;
};

// The path of `file` as the script (run in `dir`) should name it: relative
// when it lies under dir or under its parent (a run directory holding its
// plot directory), so that the run can be moved; absolute otherwise.
std::string script_path(const std::string& file, const fs::path& dir) {
  const fs::path abs = fs::absolute(file).lexically_normal();
  const fs::path rel = abs.lexically_relative(dir);
  int up = 0;
  for (const fs::path& part : rel) up += part == "..";
  if (!rel.empty() && up <= 1) return rel.generic_string();
  return abs.string();
}

void write_file(const fs::path& path, const std::string& text) {
  const std::string partial = path.string() + ".partial";
  std::FILE* f = std::fopen(partial.c_str(), "w");
  if (!f) throw OptionError("cannot write plot script '" + partial + "': " + std::strerror(errno));
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (std::fclose(f) != 0 || !ok) {
    std::remove(partial.c_str());
    throw OptionError("writing plot script '" + partial + "' failed");
  }
  if (std::rename(partial.c_str(), path.c_str()) != 0)
    throw OptionError("cannot rename '" + partial + "' to '" + path.string() + "': " + std::strerror(errno));
}


// Runs gnuplot on `script` in `dir`; the script writes each image as
// <name>.partial.<ext> (its variable `suffix`), renamed here only when
// gnuplot succeeded. Fills result.files (images, then the script) and
// result.message; on failure removes every image of this call and throws.
void run_script(const std::string& exe, const fs::path& dir, const fs::path& script,
                const std::vector<std::string>& names, bool png, bool svg, PlotResult& result) {
  std::vector<std::string> exts;
  if (png) exts.push_back("png");
  if (svg) exts.push_back("svg");
  std::vector<std::pair<fs::path, fs::path>> outputs;  // partial, final
  for (const std::string& name : names)
    for (const std::string& ext : exts)
      outputs.emplace_back(dir / (name + ".partial." + ext), dir / (name + "." + ext));
  auto remove_outputs = [&] {
    for (const auto& [partial, final_path] : outputs) {
      std::error_code ignore;
      fs::remove(partial, ignore);
      fs::remove(final_path, ignore);
    }
  };
  remove_outputs();  // images of an earlier run would not match this one
  const ProcessResult run = run_process(exe, {"-e", "suffix = '.partial'", script.filename().string()}, dir.string());
  const std::string err = trim(run.err);
  if (run.status != 0) {
    remove_outputs();
    throw OptionError("gnuplot failed on '" + script.string() + "' (exit status " + std::to_string(run.status) +
                      ")" + (err.empty() ? "" : ":\n" + err));
  }
  for (const auto& [partial, final_path] : outputs) {
    std::error_code e1;
    const auto size = fs::file_size(partial, e1);
    if (e1 || size == 0) {
      remove_outputs();
      throw OptionError("gnuplot did not write '" + partial.string() + "' (script '" + script.string() + "')" +
                        (err.empty() ? "" : ":\n" + err));
    }
    fs::rename(partial, final_path, e1);
    if (e1) {
      remove_outputs();
      throw OptionError("cannot rename '" + partial.string() + "' to '" + final_path.string() + "': " + e1.message());
    }
    result.files.push_back(final_path.string());
  }
  result.files.push_back(script.string());
  result.message = "wrote " + std::to_string(outputs.size()) + " plots and the script " +
                   script.filename().string() + " to '" + dir.string() + "'";
  if (!err.empty()) result.message += "; gnuplot said: " + err;
}

/// gnuplot is on PATH and runs: its path, else "".
std::string working_gnuplot() {
  const std::string exe = find_on_path("gnuplot");
  if (exe.empty()) return {};
  try {
    return run_process(exe, {"--version"}, "").status == 0 ? exe : std::string();
  } catch (const OptionError&) {
    return {};
  }
}

/// gnuplot's path when it runs and an image format is enabled; otherwise ""
/// with result.message saying why nothing will be drawn.
std::string gnuplot_for(bool png, bool svg, PlotResult& result) {
  const std::string exe = working_gnuplot();
  if (exe.empty()) {
    result.message = kNotFound;
    return {};
  }
  result.gnuplot_found = true;
  if (!png && !svg) {
    result.message = "plots skipped: neither png nor svg is enabled";
    return {};
  }
  return exe;
}

/// Creates `out_dir` and returns it absolute.
fs::path plot_directory(const std::string& out_dir) {
  if (out_dir.empty()) throw OptionError("plots: out_dir is empty");
  if (out_dir.find_first_of("\n\r") != std::string::npos)
    throw OptionError("plots: a path contains a line break: '" + out_dir + "'");
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec || !fs::is_directory(out_dir))
    throw OptionError("cannot create plot directory '" + out_dir + "'" + (ec ? ": " + ec.message() : ""));
  return fs::absolute(out_dir).lexically_normal();
}

}  // namespace

bool gnuplot_available() { return !working_gnuplot().empty(); }

PlotResult make_plots(const PlotSpec& spec) {
  PlotResult result;
  const std::string exe = gnuplot_for(spec.png, spec.svg, result);
  if (exe.empty()) return result;

  // Check the spec.
  if (!(spec.energy_scale > 0) || !std::isfinite(spec.energy_scale))
    throw OptionError("plots: energy_scale must be a positive number of J, not " + num(spec.energy_scale));
  for (const std::string* p : {&spec.trajectory_csv, &spec.events_csv, &spec.out_dir})
    if (p->find_first_of("\n\r") != std::string::npos)
      throw OptionError("plots: a path contains a line break: '" + *p + "'");
  if (spec.out_dir.empty()) throw OptionError("plots: out_dir is empty");

  // Inputs.
  const std::vector<Impact> impacts = read_impacts(spec.events_csv);
  const std::vector<Impact> times = thinned(impacts);
  std::vector<Impact> positions;  // those the trajectory plot marks: of the bodies it draws
  if (spec.bodies.size() > kMaxBodiesUnlabelled) {
    for (const Impact& imp : impacts)
      for (std::size_t b = 0; b < kLegendBodies; ++b)
        if (names_body(imp.bodies, spec.bodies[b].name)) {
          positions.push_back(imp);
          break;
        }
    positions = thinned(positions);
  } else {
    positions = times;
  }
  // The coordinates the trajectory plot may need at the impacts.
  std::vector<std::string> at_impacts;
  if (!spec.coordinates.empty()) {
    const auto add = [&](int idx) {
      if (idx >= 0 && idx < static_cast<int>(spec.coordinates.size()))
        at_impacts.push_back(spec.coordinates[static_cast<std::size_t>(idx)]);
    };
    if (spec.bodies.empty()) {
      add(0);
      add(1);
    }
    const std::size_t drawn =
        spec.bodies.size() > kMaxBodiesUnlabelled ? kLegendBodies : spec.bodies.size();
    for (std::size_t b = 0; b < drawn; ++b) {
      add(spec.bodies[b].x);
      add(spec.bodies[b].y);
      add(spec.bodies[b].z);
    }
  }
  Trajectory tr = read_trajectory(spec.trajectory_csv, positions, at_impacts);

  std::unordered_map<std::string, std::size_t> index;
  for (std::size_t k = 0; k < tr.header.size(); ++k) index.emplace(tr.header[k], k);
  auto column = [&](const std::string& name) {
    const auto it = index.find(name);
    if (it == index.end())
      throw OptionError("trajectory file '" + spec.trajectory_csv + "' has no column '" + name + "'");
    return it->second;
  };
  std::vector<std::string> coords = spec.coordinates;
  if (coords.empty()) {  // the names between t and the first rate
    const auto rate = index.find(tr.header.size() > 1 ? tr.header[1] + "_dot" : std::string());
    if (rate == index.end())
      throw OptionError("trajectory file '" + spec.trajectory_csv + "': cannot tell the coordinates from the header");
    coords.assign(tr.header.begin() + 1, tr.header.begin() + static_cast<std::ptrdiff_t>(rate->second));
  }
  std::vector<std::string> units = spec.units;
  if (units.empty()) units.assign(coords.size(), "");
  if (units.size() != coords.size())
    throw OptionError("plots: " + std::to_string(units.size()) + " units for " + std::to_string(coords.size()) +
                      " coordinates");
  Columns cols;
  for (const std::string& name : coords) {
    cols.q.push_back(column(name));
    cols.qd.push_back(column(name + "_dot"));
  }
  cols.energy = column("energy");
  if (const auto it = index.find("total_energy"); it != index.end()) cols.total_energy = it->second;
  for (const auto& b : spec.bodies)
    for (int idx : {b.x, b.y, b.z})
      if (idx >= static_cast<int>(coords.size()))
        throw OptionError("plots: body '" + b.name + "' names coordinate " + std::to_string(idx) + " of only " +
                          std::to_string(coords.size()));

  // Output directory and script.
  const fs::path dir = plot_directory(spec.out_dir);
  ScriptWriter writer(spec, tr, cols, impacts, times, positions, coords, units,
                      script_path(spec.trajectory_csv, dir));
  const fs::path script = dir / "plots.gp";
  write_file(script, writer.write());

  std::vector<std::string> names(std::begin(kPlotNames), std::end(kPlotNames));
  run_script(exe, dir, script, names, spec.png, spec.svg, result);
  return result;
}


PlotResult make_work_precision_plots(const WorkPrecisionPlotSpec& spec) {
  PlotResult result;
  const std::string exe = gnuplot_for(spec.png, spec.svg, result);
  if (exe.empty()) return result;
  const fs::path dir = plot_directory(spec.out_dir);

  // One data block per series: wall time, RHS evaluations, error, energy
  // drift; rows whose value is not positive and finite hold NaN there, which
  // gnuplot leaves out (log axes).
  auto positive = [](double v) { return std::isfinite(v) && v > 0 ? num(v) : std::string("NaN"); };
  std::ostringstream os;
  os << "# Work-precision diagrams, written by lagrangian::make_work_precision_plots.\n"
     << "# Run with: gnuplot bench.gp   (images <name>.png / .svg; `suffix` goes between\n"
     << "# the image name and the extension; lagrangian uses '.partial' and renames).\n"
     << "if (!exists('suffix')) suffix = ''\n\n";
  write_styles(os, 800, 560);
  bool any_energy = false;
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const WorkPrecisionSeries& sr = spec.series[k];
    const std::size_t n = sr.error.size();
    if (sr.wall_time_s.size() != n || sr.rhs_evaluations.size() != n || sr.energy_drift.size() != n)
      throw OptionError("plots: series '" + sr.name + "' has columns of different lengths");
    os << "# " << sr.name << ": wall time (s), RHS evaluations, error, relative energy drift\n"
       << "$s" << k << " << EOD\n";
    for (std::size_t i = 0; i < n; ++i) {
      os << positive(sr.wall_time_s[i]) << " " << positive(sr.rhs_evaluations[i]) << " " << positive(sr.error[i])
         << " " << positive(sr.energy_drift[i]) << "\n";
      any_energy = any_energy || (std::isfinite(sr.energy_drift[i]) && sr.energy_drift[i] > 0);
    }
    os << "EOD\n";
  }
  std::string formats;
  if (spec.png) formats = "png";
  if (spec.svg) formats += formats.empty() ? "svg" : " svg";
  os << "\nformats = '" << formats << "'\n";

  struct Diagram {
    const char* name;
    const char* what;
    const char* xlabel;
    const char* ylabel;  // empty: spec.error_label
    int x, y;            // columns of the data blocks
  };
  std::vector<Diagram> diagrams{{"work_precision_time", "error against wall time", "wall time (s)", "", 1, 3},
                                {"work_precision_rhs", "error against right-hand-side evaluations",
                                 "right-hand-side evaluations", "", 2, 3}};
  if (any_energy)
    diagrams.push_back({"work_precision_energy", "relative energy drift against wall time", "wall time (s)",
                        "max |E(t) - E(t0)| / E scale", 1, 4});
  std::vector<std::string> names;
  for (const Diagram& d : diagrams) {
    names.emplace_back(d.name);
    os << "\n# " << d.what << "\n"
       << "do for [fmt in formats] {\n"
       << "  reset\n"
       << "  eval setup\n"
       << "  if (fmt eq 'png') { eval png_terminal } else { eval svg_terminal }\n"
       << "  set output '" << d.name << "'.suffix.'.'.fmt\n"
       << "  set logscale xy\n"
       << "  set format x '%.0e'; set format y '%.0e'\n"
       << "  set title " << gp_str(spec.title + ": " + d.what) << "\n"
       << "  set xlabel " << gp_str(d.xlabel) << "\n"
       << "  set ylabel " << gp_str(*d.ylabel ? std::string(d.ylabel) : spec.error_label) << "\n"
       << "  set key outside right top\n"
       << "  set bmargin 6\n";
    if (!spec.note.empty()) os << "  set label 1 " << gp_str(spec.note) << " at screen 0.01, 0.025 font ',9'\n";
    os << "  plot ";
    bool first = true;
    for (std::size_t k = 0; k < spec.series.size(); ++k) {
      os << (first ? "" : ", \\\n       ") << "$s" << k << " using " << d.x << ":" << d.y << " with linespoints lt "
         << k % 10 + 1 << " title " << gp_str(spec.series[k].name);
      first = false;
    }
    if (d.y == 3 && spec.reference_accuracy > 0)
      os << (first ? "" : ", \\\n       ") << num(spec.reference_accuracy)
         << " with lines dt 2 lc rgb '#707070' title 'reference accuracy'";
    os << "\n  set output\n}\n";
  }
  const fs::path script = dir / "bench.gp";
  write_file(script, os.str());
  run_script(exe, dir, script, names, spec.png, spec.svg, result);
  return result;
}

void collect_plots(const std::function<PlotResult()>& make, std::vector<std::string>& files, std::string& note) {
  try {
    const PlotResult pr = make();
    files.insert(files.end(), pr.files.begin(), pr.files.end());
    if (!pr.gnuplot_found) note = pr.message;
  } catch (const Error& e) {
    note = std::string("plots failed: ") + e.what();
  }
}

PlotResult make_sweep_plots(const SweepPlotSpec& spec) {
  PlotResult result;
  const std::size_t dims = spec.axes.size();
  if (dims < 1 || dims > 2 || spec.axis_counts.size() != dims)
    throw OptionError("plots: a sweep plot needs one or two axes, got " + std::to_string(dims));
  const std::string exe = gnuplot_for(spec.png, spec.svg, result);
  if (exe.empty()) return result;
  const fs::path dir = plot_directory(spec.out_dir);
  auto value = [](double v) { return std::isfinite(v) ? num(v) : std::string("NaN"); };
  auto file_name = [](const std::string& name) {
    std::string out = "sweep_";
    for (char c : name) out += std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' ? c : '_';
    return out;
  };
  std::ostringstream os;
  os << "# Sweep plots, written by lagrangian::make_sweep_plots.\n"
     << "# Run with: gnuplot sweep.gp   (images sweep_<column>.png / .svg; `suffix` goes between\n"
     << "# the image name and the extension; lagrangian uses '.partial' and renames).\n"
     << "if (!exists('suffix')) suffix = ''\n\n";
  write_styles(os, 800, 560);
  std::string formats;
  if (spec.png) formats = "png";
  if (spec.svg) formats += formats.empty() ? "svg" : " svg";
  os << "\nformats = '" << formats << "'\n";
  std::vector<std::string> names;
  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const SweepPlotSpec::Series& s = spec.series[k];
    if (s.x.size() != s.y.size()) throw OptionError("plots: series '" + s.name + "' has columns of different lengths");
    os << "\n$d" << k << " << EOD\n";
    for (std::size_t i = 0; i < s.y.size(); ++i) {
      if (s.x[i].size() != dims) throw OptionError("plots: series '" + s.name + "' has a point with the wrong axes");
      if (dims == 2 && i > 0 && spec.axis_counts[1] > 0 && i % static_cast<std::size_t>(spec.axis_counts[1]) == 0)
        os << "\n";  // a new row of the grid
      for (double x : s.x[i]) os << value(x) << " ";
      os << value(s.y[i]) << "\n";
    }
    os << "EOD\n";
    const std::string name = file_name(s.name);
    names.push_back(name);
    os << "do for [fmt in formats] {\n"
       << "  reset\n"
       << "  eval setup\n"
       << "  if (fmt eq 'png') { eval png_terminal } else { eval svg_terminal }\n"
       << "  set output '" << name << "'.suffix.'.'.fmt\n"
       << "  set title " << gp_str(spec.title + ": " + s.name) << "\n"
       << "  set xlabel " << gp_str(spec.axes[0]) << "\n";
    if (spec.log_axes.size() > 0 && spec.log_axes[0]) os << "  set logscale x\n";
    if (dims == 1) {
      os << "  set ylabel " << gp_str(s.name) << "\n"
         << "  plot $d" << k << " using 1:2 with linespoints lt 1 notitle\n";
    } else {
      if (spec.log_axes.size() > 1 && spec.log_axes[1]) os << "  set logscale y\n";
      os << "  set ylabel " << gp_str(spec.axes[1]) << "\n"
         << "  set cblabel " << gp_str(s.name) << "\n"
         << "  set palette rgbformulae 33,13,10\n"
         << "  set autoscale fix\n"
         << "  plot $d" << k << " using 1:2:3 with image notitle\n";
    }
    os << "  set output\n}\n";
  }
  const fs::path script = dir / "sweep.gp";
  write_file(script, os.str());
  run_script(exe, dir, script, names, spec.png, spec.svg, result);
  return result;
}

}  // namespace lagrangian

