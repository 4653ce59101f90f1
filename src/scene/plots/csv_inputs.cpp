// Reading a run's CSV files for the plots: CSV fields and numbers, the impacts
// of the events file, one pass over the trajectory file (ranges, impact rows).
#include "csv_inputs.hpp"

#include <sys/types.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <string_view>
#include <system_error>
#include <unordered_map>
#include <utility>
#include <vector>

#include "lagrangian/detail/csv_header.hpp"
#include "lagrangian/errors.hpp"

namespace lagrangian::plots_detail {

namespace fs = std::filesystem;

namespace {

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

}  // namespace

std::vector<Impact> read_impacts(const std::string& path, bool watched) {
  std::vector<Impact> impacts;
  if (path.empty()) return impacts;
  std::error_code ec;
  if (!fs::exists(path, ec)) return impacts;
  if (fs::is_directory(path, ec)) throw OptionError("cannot read events file '" + path + "': it is a directory");
  LineReader in(path);
  if (!in.ok()) throw OptionError("cannot read events file '" + path + "': " + std::strerror(errno));
  std::string_view line;
  if (!in.next(line)) return impacts;  // empty file: no events
  std::vector<std::string> header = split_csv_line(std::string(line));
  for (std::string& h : header) h = std::string(lagrangian::detail::csv_field_name(h));  // "t [s]" is t
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
    if (line.empty() || line.front() == '#') continue;  // a note, such as the truncation line
    const std::vector<std::string> f = split_csv_line(std::string(line));
    if (f.size() <= std::max({ct, ck, cb}))
      throw OptionError("events file '" + path + "', line " + std::to_string(lineno) + ": too few fields");
    if (f[ck] != (watched ? "event" : "impact")) continue;
    Impact imp;
    imp.watched = watched;
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

std::vector<Impact> thinned(const std::vector<Impact>& impacts) {
  if (impacts.size() <= kMaxImpactMarks) return impacts;
  std::vector<Impact> kept;
  const double step = static_cast<double>(impacts.size() - 1) / static_cast<double>(kMaxImpactMarks - 1);
  for (std::size_t k = 0; k < kMaxImpactMarks; ++k)
    kept.push_back(impacts[static_cast<std::size_t>(std::llround(static_cast<double>(k) * step))]);
  return kept;
}

namespace {

/// The rate column of each column ("x" → "x_dot"), npos where there is
/// none, for impact positions.
std::vector<std::size_t> rate_columns(const std::vector<std::string>& header) {
  std::vector<std::size_t> rate(header.size(), std::string::npos);
  std::unordered_map<std::string, std::size_t> index;
  for (std::size_t k = 0; k < header.size(); ++k) index.emplace(header[k], k);
  for (std::size_t k = 1; k < header.size(); ++k)
    if (const auto it = index.find(header[k] + "_dot"); it != index.end()) rate[k] = it->second;
  return rate;
}

/// The columns kept at the impacts (t and those named in at_impacts, all
/// when it is empty), their slots written to tr.slot.
std::vector<std::size_t> kept_columns(Trajectory& tr, const std::vector<std::string>& at_impacts) {
  tr.slot.assign(tr.header.size(), std::string::npos);
  std::vector<std::size_t> kept = {0};
  tr.slot[0] = 0;
  for (std::size_t k = 1; k < tr.header.size(); ++k)
    if (at_impacts.empty() || std::find(at_impacts.begin(), at_impacts.end(), tr.header[k]) != at_impacts.end()) {
      tr.slot[k] = kept.size();
      kept.push_back(k);
    }
  return kept;
}

/// The kept columns at an impact at ti between the rows `prev` (at t_prev)
/// and `cur` (at t). Positions have a kink at an impact: each side's own
/// rate carries it to the impact time (error O(dt²)); the mean of both is
/// taken. Other columns are interpolated linearly.
std::vector<double> row_at_impact(double ti, const std::vector<std::size_t>& kept, const std::vector<std::size_t>& rate,
                                  const std::vector<double>& prev, double t_prev, const std::vector<double>& cur,
                                  double t) {
  const double w = (ti - t_prev) / (t - t_prev);
  std::vector<double> row;
  for (std::size_t k : kept) {
    if (rate[k] != std::string::npos) {
      const double from_before = prev[k] + prev[rate[k]] * (ti - t_prev);
      const double from_after = cur[k] - cur[rate[k]] * (t - ti);
      row.push_back(0.5 * (from_before + from_after));
    } else {
      row.push_back(prev[k] + w * (cur[k] - prev[k]));
    }
  }
  return row;
}

}  // namespace

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
  for (std::string& h : tr.header) h = std::string(lagrangian::detail::csv_field_name(h));  // "x [m]" is x
  if (tr.header.empty() || tr.header[0] != "t")
    throw OptionError("trajectory file '" + path + "' does not start with the header 't,...' (found '" +
                      std::string(line.substr(0, 80)) + "')");
  const std::size_t total_rows = count_data_lines(path);
  if (total_rows == 0) throw OptionError("trajectory file '" + path + "' has no data rows");
  tr.every = std::max<std::size_t>(1, (total_rows + kPointsPerLine - 1) / kPointsPerLine);

  const std::size_t ncol = tr.header.size();
  const std::vector<std::size_t> rate = rate_columns(tr.header);
  const std::vector<std::size_t> kept = kept_columns(tr, at_impacts);
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
          imp.row = row_at_impact(imp.t, kept, rate, prev, t_prev, cur, t);
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

}  // namespace lagrangian::plots_detail
