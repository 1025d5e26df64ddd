#pragma once
// Subcommands of the fmcw CLI. Each registers its options on the app and returns the action
// to run once the command line is parsed.

#include <CLI/CLI.hpp>
#include <functional>

namespace fmcw::cli {

using Action = std::function<int()>;

Action add_process_command(CLI::App& app);
Action add_synth_command(CLI::App& app);
Action add_bench_command(CLI::App& app);
Action add_simulate_command(CLI::App& app);
Action add_evaluate_command(CLI::App& app);
Action add_run_command(CLI::App& app);
Action add_study_command(CLI::App& app);

}  // namespace fmcw::cli
