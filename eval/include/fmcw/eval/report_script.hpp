#pragma once
// The figures and report.html are drawn by a Python script (matplotlib) from the tables the C++
// side writes; this runs it.

#include <string>

namespace fmcw::eval {

struct ReportScriptParams {
  std::string python = "/usr/bin/python3";  ///< an interpreter with numpy and matplotlib
  std::string script;                       ///< tools/report/fmcw_report.py

  /// FMCW_PYTHON and FMCW_REPORT_SCRIPT in the environment override the defaults given.
  static ReportScriptParams from_environment(const std::string& default_script);
};

/// Runs `python script dir`. The script reads dir/metrics.json (its "kind" says which report)
/// and the tables beside it, and writes the PNG figures and report.html, each atomically.
/// std::runtime_error when the script is missing or exits non-zero.
void run_report_script(const ReportScriptParams& params, const std::string& dir);

}  // namespace fmcw::eval
