#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <string_view>
#include <utility>

#include "lagrangian/detail/csv_header.hpp"
#include "lagrangian/errors.hpp"
#include "lagrangian/integrate/observers.hpp"

namespace lagrangian {

CsvSink::CsvSink(std::string path) : path_(std::move(path)) {
  const std::string partial = path_ + ".partial";
  file_ = std::fopen(partial.c_str(), "w");
  if (!file_) throw OptionError("cannot write output file '" + partial + "': " + std::strerror(errno));
}

CsvSink::CsvSink(CsvSink&& other) noexcept
    : path_(std::move(other.path_)),
      file_(std::exchange(other.file_, nullptr)),
      total_energy_(other.total_energy_),
      finished_(other.finished_) {}

CsvSink::~CsvSink() {
  if (file_) {
    std::fclose(file_);
    if (!finished_) std::remove((path_ + ".partial").c_str());
  }
}

void CsvSink::begin(const Columns& columns) {
  total_energy_ = columns.total_energy;
  const auto unit_of = [](const std::vector<std::string>& units, std::size_t i) {
    return i < units.size() ? std::string_view(units[i]) : std::string_view();
  };
  std::string header = detail::csv_field("t", "s");
  const auto add = [&](const std::string& name, std::string_view unit) {
    header += ',';
    header += detail::csv_field(name, unit);
  };
  const std::vector<std::string>& q = columns.coordinates;
  for (std::size_t i = 0; i < q.size(); ++i) add(q[i], unit_of(columns.units, i));
  for (std::size_t i = 0; i < q.size(); ++i) add(q[i] + "_dot", detail::csv_rate_unit(unit_of(columns.units, i)));
  add("energy", "J");
  if (total_energy_) add("total_energy", "J");
  if (!columns.constraints.empty()) {
    for (std::size_t k = 0; k < columns.constraints.size(); ++k)
      add("lambda_" + columns.constraints[k], unit_of(columns.constraint_units, k));
    for (std::size_t i = 0; i < q.size(); ++i) add("Qc_" + q[i], detail::csv_force_unit(unit_of(columns.units, i)));
  }
  header += '\n';
  std::fputs(header.c_str(), file_);
}

void CsvSink::write_row(double t, const double* q, const double* qd, int n, double energy, double total_energy) {
  std::fprintf(file_, "%.17g", t);
  for (int i = 0; i < n; ++i) std::fprintf(file_, ",%.17g", q[i]);
  for (int i = 0; i < n; ++i) std::fprintf(file_, ",%.17g", qd[i]);
  std::fprintf(file_, ",%.17g", energy);
  if (total_energy_) std::fprintf(file_, ",%.17g", total_energy);
}

void CsvSink::write_extra(const Eigen::VectorXd& multipliers, const Eigen::VectorXd& forces) {
  for (Eigen::Index i = 0; i < multipliers.size(); ++i) std::fprintf(file_, ",%.17g", multipliers[i]);
  for (Eigen::Index i = 0; i < forces.size(); ++i) std::fprintf(file_, ",%.17g", forces[i]);
  std::fputc('\n', file_);
}

void CsvSink::finish() {
  if (!file_ || finished_) return;
  const bool write_failed = std::ferror(file_) != 0;
  const bool close_failed = std::fclose(file_) != 0;
  file_ = nullptr;
  const std::string partial = path_ + ".partial";
  if (write_failed || close_failed) {
    std::remove(partial.c_str());
    throw OptionError("writing output file '" + partial + "' failed");
  }
  if (std::rename(partial.c_str(), path_.c_str()) != 0)
    throw OptionError("cannot rename '" + partial + "' to '" + path_ + "': " + std::strerror(errno));
  finished_ = true;
}

}  // namespace lagrangian
