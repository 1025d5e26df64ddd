#include "fmcw/eval/report_script.hpp"

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace fmcw::eval {

namespace {
// Single-quoted for /bin/sh: ' becomes '\''.
std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}
}  // namespace

ReportScriptParams ReportScriptParams::from_environment(const std::string& default_script) {
  ReportScriptParams p;
  p.script = default_script;
  if (const char* py = std::getenv("FMCW_PYTHON"); py != nullptr && *py != '\0') p.python = py;
  if (const char* s = std::getenv("FMCW_REPORT_SCRIPT"); s != nullptr && *s != '\0') p.script = s;
  return p;
}

void run_report_script(const ReportScriptParams& params, const std::string& dir) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(params.script, ec)) {
    throw std::runtime_error("report script '" + params.script + "' not found (set FMCW_REPORT_SCRIPT)");
  }
  const std::string cmd = shell_quote(params.python) + " " + shell_quote(params.script) + " " + shell_quote(dir);
  const int status = std::system(cmd.c_str());
  if (status == -1) throw std::runtime_error("cannot start '" + params.python + "' for the report");
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    throw std::runtime_error("report script " + params.script + " failed on '" + dir + "' (exit " +
                             std::to_string(code) + "; its message is above)");
  }
}

}  // namespace fmcw::eval
