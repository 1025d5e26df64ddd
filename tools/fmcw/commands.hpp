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

/// Says once, on stderr, what the input's files hold that the run does not use.
inline void say_notices(const std::vector<std::string>& notices) {
  for (const auto& n : notices) std::cerr << "fmcw: note: " << n << "\n";
}

/// Runs the evaluation of a dataset and writes its report (metrics.json, tables, and figures
/// plus report.html unless no_figures), with progress on stderr. Shared by evaluate and run.
int evaluate_and_report(eval::FrameSource& source, const eval::EvaluationParams& params, const std::string& output,
                        bool no_figures);

}  // namespace fmcw::cli
