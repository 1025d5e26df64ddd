#pragma once
// The manifest of a generated scenario set (manifest.csv beside the datasets): one row per
// scenario, keyed by the scenario's name, whose other columns (layout, speeds, density, ...)
// an aggregate evaluation carries into its per-scenario table and plots against.

#include <string>
#include <vector>

namespace fmcw::eval {

struct ScenarioManifest {
  std::string path;                              ///< the file read
  std::vector<std::string> columns;              ///< header, in file order; holds "name"
  std::vector<std::vector<std::string>> rows;    ///< cells per row, as many as columns
  std::size_t name_column = 0;                   ///< index of "name" in columns

  /// The row whose name is `name`, or nullptr.
  const std::vector<std::string>* find(const std::string& name) const;
  /// The index of a column, or -1.
  int column(const std::string& name) const;
};

/// Reads a CSV with a header (RFC 4180: cells may be quoted, "" is a quote inside quotes; CRLF
/// or LF). Throws core::FileError naming the file and line for: no header, no "name" column, a
/// repeated column, a row with another cell count than the header, an empty or a repeated
/// name, an unterminated quote, or a file that cannot be read.
ScenarioManifest read_scenario_manifest(const std::string& path);

/// Splits CSV text into rows of cells (as above); line numbers of each row's start in lines.
/// Throws std::invalid_argument("<what>", with line) for an unterminated quote, naming `name`.
std::vector<std::vector<std::string>> parse_csv(const std::string& text, const std::string& name,
                                                std::vector<int>* lines = nullptr);

}  // namespace fmcw::eval
