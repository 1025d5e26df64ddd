#pragma once
// CSV tables built in memory and written atomically (a reader never sees half a table).

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

namespace fmcw::eval {

/// Rows of comma-separated cells under a fixed header. Numbers are written with 9 significant
/// digits; NaN as "nan", infinities as "inf"/"-inf" (numpy and pandas read both).
class CsvTable {
 public:
  explicit CsvTable(const std::vector<std::string>& columns);

  CsvTable& add(const std::string& text);  ///< must not hold commas, quotes or newlines
  /// Text from outside (folder names, manifest cells): quoted as RFC 4180 says when it holds
  /// a comma, quote or newline (a quote doubled), else written as is.
  CsvTable& add_quoted(const std::string& text);
  CsvTable& add(double value);
  CsvTable& add(std::int64_t value);
  CsvTable& add(int value) { return add(static_cast<std::int64_t>(value)); }
  CsvTable& add(std::uint64_t value) { return add(static_cast<std::int64_t>(value)); }
  CsvTable& add(unsigned value) { return add(static_cast<std::int64_t>(value)); }
  CsvTable& add(const char* text) { return add(std::string(text)); }
  CsvTable& add(bool value) { return add(static_cast<std::int64_t>(value ? 1 : 0)); }
  CsvTable& add(const Eigen::Vector3d& v);  ///< three cells
  /// Ends the row; throws std::logic_error when its cell count differs from the header's.
  void end_row();

  std::size_t rows() const { return rows_; }
  const std::string& text() const { return text_; }
  /// io::write_file_atomically(path, text()).
  void write(const std::string& path) const;

 private:
  void cell(const std::string& s);
  std::size_t columns_ = 0;
  std::size_t cells_in_row_ = 0;
  std::size_t rows_ = 0;
  std::string text_;
};

/// "nan", "inf", "-inf" or the number with 9 significant digits.
std::string format_number(double value);

/// Writes text to path atomically (temporary name, then rename); std::runtime_error on failure.
void write_text_atomically(const std::string& path, const std::string& text);

}  // namespace fmcw::eval
