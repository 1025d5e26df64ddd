#include "fmcw/eval/table_writer.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "fmcw/core/check.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/csv_cell.hpp"

namespace fmcw::eval {

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", value);
  return buf;
}

void write_text_atomically(const std::string& path, const std::string& text) {
  io::write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

CsvTable::CsvTable(const std::vector<std::string>& columns) : columns_(columns.size()) {
  FMCW_CHECK_ARG(!columns.empty(), "CsvTable: no columns");
  for (std::size_t k = 0; k < columns.size(); ++k) text_ += (k ? "," : "") + columns[k];
  text_ += '\n';
}

void CsvTable::cell(const std::string& s) {
  if (cells_in_row_ > 0) text_ += ',';
  text_ += s;
  ++cells_in_row_;
}

CsvTable& CsvTable::add(const std::string& text) {
  FMCW_CHECK_ARG(text.find_first_of(",\"\n\r") == std::string::npos, "CsvTable: cell '", text,
                 "' holds a comma, quote or newline");
  cell(text);
  return *this;
}

CsvTable& CsvTable::add_quoted(const std::string& text) {
  cell(io::csv_cell(text));
  return *this;
}

CsvTable& CsvTable::add(double value) {
  cell(format_number(value));
  return *this;
}

CsvTable& CsvTable::add(std::int64_t value) {
  cell(std::to_string(value));
  return *this;
}

CsvTable& CsvTable::add(const Eigen::Vector3d& v) { return add(v.x()).add(v.y()).add(v.z()); }

void CsvTable::end_row() {
  if (cells_in_row_ != columns_) {
    throw std::logic_error("CsvTable: row " + std::to_string(rows_ + 1) + " has " + std::to_string(cells_in_row_) +
                           " cells, header has " + std::to_string(columns_));
  }
  text_ += '\n';
  cells_in_row_ = 0;
  ++rows_;
}

void CsvTable::write(const std::string& path) const { write_text_atomically(path, text_); }

}  // namespace fmcw::eval
