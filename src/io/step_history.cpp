#include "io/step_history.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <stdexcept>

#include "io/file_space.hpp"
#include "io/hdf5_file.hpp"

namespace hs {

namespace {

std::string column_name(const std::string& name) {
  std::string column = name;
  for (char& c : column) {
    const bool plain = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                       c == '_' || c == '-' || c == '.';
    if (!plain) c = '_';
  }
  return column;
}

// Appends `text` to the file (replacing it when `fresh`). A write that fails (a full disk)
// takes the file back to its length before, so that it never ends in half a row.
void append_text(const std::string& path, const std::string& text, bool fresh) {
  const int fd =
      open(path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | (fresh ? O_TRUNC : O_APPEND), 0644);
  if (fd < 0) throw std::runtime_error(path + ": cannot write: " + system_reason());
  struct stat st;
  const off_t before = fstat(fd, &st) == 0 ? st.st_size : -1;
  std::string error;
  for (size_t done = 0; done < text.size() && error.empty();) {
    const ssize_t n = write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) error = system_reason();
    if (n > 0) done += static_cast<size_t>(n);
  }
  if (!error.empty() && before >= 0 && ftruncate(fd, before) != 0) {
    // The reason of the write is the one to report.
  }
  if (close(fd) != 0 && error.empty()) error = system_reason();
  if (!error.empty()) throw std::runtime_error(path + ": cannot write: " + error);
}

}  // namespace

void HistoryRow::add(const std::string& name, double value) {
  cells.push_back({column_name(name), value, false});
}

void HistoryRow::add_count(const std::string& name, int64_t value) {
  cells.push_back({column_name(name), static_cast<double>(value), true});
}

void StepHistory::append(const HistoryRow& row, const std::string& csv_path) {
  const bool first = values_.empty();
  if (first) {
    for (const auto& cell : row.cells) {
      columns_.push_back(cell.column);
      integer_.push_back(cell.integer);
    }
  } else {
    bool same = row.cells.size() == columns_.size();
    for (size_t c = 0; same && c < columns_.size(); ++c) same = row.cells[c].column == columns_[c];
    if (!same) throw std::logic_error("StepHistory::append: a row with other columns");
  }
  std::vector<double> values;
  for (const auto& cell : row.cells) values.push_back(cell.value);
  values_.push_back(values);
  if (csv_path.empty()) return;
  std::string text;
  if (first) {
    for (size_t c = 0; c < columns_.size(); ++c) text += (c ? "," : "") + columns_[c];
    text += "\n";
  }
  char number[32];
  for (size_t c = 0; c < values.size(); ++c) {
    // %.17g: the CSV holds the same doubles as the .h5 and summary.json.
    std::snprintf(number, sizeof number, "%.17g", values[c]);
    text += (c ? "," : "") + std::string(number);
  }
  text += "\n";
  append_text(csv_path, text, first);
}

std::vector<double> StepHistory::column(size_t c) const {
  std::vector<double> out;
  for (const auto& row : values_) out.push_back(row[c]);
  return out;
}

nlohmann::json StepHistory::last_row() const {
  if (values_.empty()) return nullptr;
  nlohmann::json j = nlohmann::json::object();
  for (size_t c = 0; c < columns_.size(); ++c) {
    const double v = values_.back()[c];
    if (integer_[c])
      j[columns_[c]] = static_cast<int64_t>(v);
    else
      j[columns_[c]] = v;
  }
  return j;
}

// A column's unit, from the suffix its name ends with (docs/output.md, "History").
static std::string column_units(const std::string& column) {
  auto ends_with = [&](const std::string& suffix) {
    return column.size() >= suffix.size() &&
           column.compare(column.size() - suffix.size(), suffix.size(), suffix) == 0;
  };
  for (const char* unit : {"Pa", "m3", "N", "m", "s"})
    if (ends_with(std::string("_") + unit)) return std::string(unit) == "m3" ? "m^3" : unit;
  return "1";
}

void StepHistory::write_h5(const std::string& h5_path, MPI_Comm comm) const {
  if (columns_.empty()) return;
  int rank = 0;
  if (comm != MPI_COMM_NULL) MPI_Comm_rank(comm, &rank);
  const int64_t objects = 1 + 2 * static_cast<int64_t>(columns_.size());  // datasets, units
  const int64_t bytes = 8 * static_cast<int64_t>(rows() * columns_.size()) +
                        Hdf5File::metadata_allowance(objects, static_cast<int64_t>(rows()));
  Hdf5File h5(h5_path, Hdf5File::Mode::Append, comm, bytes);
  h5.create_group("/history");
  for (size_t c = 0; c < columns_.size(); ++c) {
    const std::string name = "/history/" + columns_[c];
    std::vector<double> values = rank == 0 ? column(c) : std::vector<double>();
    if (integer_[c])
      h5.write_rows(name, std::vector<int64_t>(values.begin(), values.end()), rows(), 0, 0);
    else
      h5.write_rows(name, values, rows(), 0, 0);
    h5.set_attribute(name, "units", column_units(columns_[c]));
  }
  h5.close();
}

}  // namespace hs
