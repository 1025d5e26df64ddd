#include "fmcw/eval/scenario_manifest.hpp"

#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "fmcw/core/errors.hpp"

namespace fmcw::eval {

std::vector<std::vector<std::string>> parse_csv(const std::string& text, const std::string& name,
                                                std::vector<int>* lines) {
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> row;
  std::string cell;
  bool quoted = false;      // inside a quoted cell
  bool row_started = false;
  int line = 1, row_line = 1;
  const auto end_cell = [&] {
    row.push_back(cell);
    cell.clear();
  };
  const auto end_row = [&] {
    end_cell();
    // A blank line (one empty cell) is not a row.
    if (!(row.size() == 1 && row[0].empty())) {
      rows.push_back(std::move(row));
      if (lines != nullptr) lines->push_back(row_line);
    }
    row.clear();
    row_started = false;
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (!row_started) {
      row_started = true;
      row_line = line;
    }
    if (quoted) {
      if (c == '"') {
        if (i + 1 < text.size() && text[i + 1] == '"') {
          cell += '"';
          ++i;
        } else {
          quoted = false;
        }
      } else {
        if (c == '\n') ++line;
        cell += c;
      }
      continue;
    }
    if (c == '"' && cell.empty()) {
      quoted = true;
    } else if (c == ',') {
      end_cell();
    } else if (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n') {
      continue;
    } else if (c == '\n') {
      end_row();
      ++line;
    } else {
      cell += c;
    }
  }
  if (quoted) throw core::FileError(name + ":" + std::to_string(row_line) + ": unterminated quoted cell");
  if (row_started) end_row();
  return rows;
}

ScenarioManifest read_scenario_manifest(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::FileError(path + ": cannot read");
  std::ostringstream buf;
  buf << in.rdbuf();
  std::vector<int> lines;
  std::vector<std::vector<std::string>> rows = parse_csv(buf.str(), path, &lines);
  const auto fail = [&](int line, const std::string& what) {
    throw core::FileError(path + ":" + std::to_string(line) + ": " + what);
  };
  if (rows.empty()) fail(1, "empty: expected a header with a 'name' column");
  ScenarioManifest m;
  m.path = path;
  m.columns = rows.front();
  std::map<std::string, std::size_t> seen;
  for (std::size_t k = 0; k < m.columns.size(); ++k) {
    if (m.columns[k].empty()) fail(lines[0], "column " + std::to_string(k + 1) + " has no name");
    if (!seen.emplace(m.columns[k], k).second) fail(lines[0], "column '" + m.columns[k] + "' appears twice");
  }
  const auto it = seen.find("name");
  if (it == seen.end()) fail(lines[0], "no 'name' column (the scenario name that matches a dataset)");
  m.name_column = it->second;
  std::map<std::string, int> names;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    if (rows[r].size() != m.columns.size()) {
      fail(lines[r], std::to_string(rows[r].size()) + " cells, the header has " + std::to_string(m.columns.size()));
    }
    const std::string& name = rows[r][m.name_column];
    if (name.empty()) fail(lines[r], "empty 'name'");
    if (const auto [at, fresh] = names.emplace(name, lines[r]); !fresh) {
      fail(lines[r], "name '" + name + "' repeats line " + std::to_string(at->second));
    }
    m.rows.push_back(std::move(rows[r]));
  }
  return m;
}

const std::vector<std::string>* ScenarioManifest::find(const std::string& name) const {
  for (const auto& row : rows) {
    if (row[name_column] == name) return &row;
  }
  return nullptr;
}

int ScenarioManifest::column(const std::string& name) const {
  for (std::size_t k = 0; k < columns.size(); ++k) {
    if (columns[k] == name) return static_cast<int>(k);
  }
  return -1;
}

}  // namespace fmcw::eval
