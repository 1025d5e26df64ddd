#pragma once
// Subcommands of the fmcw CLI. Each registers its options on the app and returns the action
// to run once the command line is parsed.

#include <CLI/CLI.hpp>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

#include "fmcw/eval/evaluation_report.hpp"

namespace fmcw::cli {

using Action = std::function<int()>;

Action add_process_command(CLI::App& app);
Action add_synth_command(CLI::App& app);
Action add_bench_command(CLI::App& app);
Action add_simulate_command(CLI::App& app);
Action add_merge_command(CLI::App& app);
Action add_evaluate_command(CLI::App& app);
Action add_run_command(CLI::App& app);
Action add_study_command(CLI::App& app);
Action add_export_command(CLI::App& app);
Action add_generate_command(CLI::App& app);

/// A seed option's check: decimal digits only, at most 2^64 - 1 (CLI11 alone would take -1,
/// 2^64 or 1e23 and wrap them silently).
inline const CLI::Validator& seed_validator() {
  static const CLI::Validator v(
      [](std::string& text) -> std::string {
        const std::string max = "18446744073709551615";
        const bool digits = !text.empty() && text.find_first_not_of("0123456789") == std::string::npos;
        std::string trimmed = text.substr(std::min(text.find_first_not_of('0'), text.empty() ? 0 : text.size() - 1));
        if (digits && (trimmed.size() < max.size() || (trimmed.size() == max.size() && trimmed <= max))) return "";
        return "'" + text.substr(0, 40) + "' is not a seed: expected a whole number from 0 to " + max;
      },
      "SEED");
  return v;
}

/// Says once, on stderr, what the input's files hold that the run does not use.
inline void say_notices(const std::vector<std::string>& notices) {
  for (const auto& n : notices) std::cerr << "fmcw: note: " << n << "\n";
}

/// Runs the evaluation of a dataset and writes its report (metrics.json, tables, and figures
/// plus report.html unless no_figures), with progress on stderr. Shared by evaluate and run.
int evaluate_and_report(eval::FrameSource& source, const eval::EvaluationParams& params, const std::string& output,
                        bool no_figures);

}  // namespace fmcw::cli
