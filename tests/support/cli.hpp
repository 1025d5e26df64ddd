#pragma once
// Running the fmcw CLI as a user does, and reading what it wrote. FMCW_CLI_PATH is set by CMake.

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace fmcw::test {

/// The CLI's exit codes by the kind of error (README, "Exit codes").
constexpr int kExitOther = 1;  ///< anything else (an output not written, a frame not estimable)
constexpr int kExitUsage = 2;  ///< usage or bad input: command line, option values, output folder
constexpr int kExitFile = 3;   ///< a file that is missing, unreadable or malformed
constexpr int kExitLimit = 4;  ///< a resource limit: memory budget, sizes, thread counts

struct CliResult {
  int code = -1;       ///< exit code, or 128 + signal
  std::string output;  ///< stdout and stderr
};

/// Runs a shell command and collects its output (stdout and stderr) and exit code.
inline CliResult run_shell(const std::string& command) {
  CliResult r;
  const std::string cmd = "(" + command + ") 2>&1";
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) r.output.append(buf, n);
  const int status = ::pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return r;
}

/// Runs `fmcw ARGS` through the shell and collects its output and exit code.
inline CliResult run_cli(const std::string& args) { return run_shell(std::string(FMCW_CLI_PATH) + " " + args); }

/// A whole file as bytes.
inline std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// The lines of a command's output that mention "error".
inline std::vector<std::string> error_lines(const std::string& output) {
  std::vector<std::string> lines;
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);) {
    if (line.find("error") != std::string::npos) lines.push_back(line);
  }
  return lines;
}

/// The comma-separated cells of data row k (0 = the first after the header) of a CSV file;
/// empty when the file has no such row.
inline std::vector<std::string> csv_row(const std::filesystem::path& p, std::size_t k = 0) {
  std::istringstream in(slurp(p));
  std::string row;
  for (std::size_t i = 0; i <= k + 1; ++i) {
    if (!std::getline(in, row)) return {};
  }
  std::vector<std::string> cells;
  std::stringstream rs(row);
  for (std::string c; std::getline(rs, c, ',');) cells.push_back(c);
  return cells;
}

}  // namespace fmcw::test
