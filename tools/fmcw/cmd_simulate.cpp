// fmcw simulate SCENARIO.yaml -o DIR: a synthetic FMCW dataset with ground truth.

#include <csignal>
#include <iostream>

#include "commands.hpp"
#include "fmcw/sim/dataset_writer.hpp"
#include "progress.hpp"

namespace fmcw::cli {

namespace {

struct SimulateOptions {
  std::string scenario;
  sim::DatasetOptions dataset;
  std::uint64_t seed = 0;
  std::string shard;
};

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void request_stop(int signal) { g_stop_signal = signal; }

// SIGINT and SIGTERM ask the writer to stop after the frame in flight. The handler resets
// itself, so a second Ctrl-C kills at once (whole frames are still all that is on disk).
void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND | SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

// "i/n" -> (i, n); std::invalid_argument naming the option otherwise.
std::pair<int, int> parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  int i = -1, n = 0;
  try {
    std::size_t used_i = 0, used_n = 0;
    if (slash != std::string::npos) {
      i = std::stoi(text.substr(0, slash), &used_i);
      n = std::stoi(text.substr(slash + 1), &used_n);
    }
    if (used_i != slash || used_n != text.size() - slash - 1) n = 0;
  } catch (const std::exception&) {
    n = 0;
  }
  if (n < 1 || i < 0 || i >= n) {
    throw std::invalid_argument("--shard '" + text + "': expected I/N with 0 <= I < N, e.g. 0/4 for the first of four");
  }
  return {i, n};
}

}  // namespace

Action add_simulate_command(CLI::App& app) {
  auto opt = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand("simulate", "Simulate a scenario into a dataset (PCD frames + ground truth)");
  cmd->add_option("scenario", opt->scenario, "Scenario YAML file")->required();
  cmd->add_option("-o,--output", opt->dataset.output_dir, "Output dataset folder")->required();
  cmd->add_option("--frames", opt->dataset.frames, "Frames to simulate (default: the scenario's)")->check(CLI::PositiveNumber);
  CLI::Option* seed = cmd->add_option("--seed", opt->seed, "Noise seed (default: the scenario's)");
  cmd->add_option("--threads", opt->dataset.num_threads, "Ray-casting threads (0 = all cores)")->check(CLI::NonNegativeNumber);
  CLI::Option* overwrite = cmd->add_flag("--overwrite", opt->dataset.overwrite, "Write into a non-empty output folder");
  cmd->add_flag("--resume", opt->dataset.resume,
                "Continue a stopped run in the output folder (same arguments); the result is byte-identical to an "
                "uninterrupted run")
      ->excludes(overwrite);
  cmd->add_option("--shard", opt->shard,
                  "Write only part I of N of the dataset (frames I*F/N to (I+1)*F/N); join the parts with fmcw merge");
  return [opt, seed] {
    opt->dataset.override_seed = seed->count() > 0;
    opt->dataset.seed = opt->seed;
    opt->dataset.tool_version = FMCW_VERSION;
    if (!opt->shard.empty()) std::tie(opt->dataset.shard_index, opt->dataset.shard_count) = parse_shard(opt->shard);
    const sim::LoadedScenario loaded = sim::load_scenario(opt->scenario);
    say_notices(loaded.notices);
    install_stop_handlers();
    opt->dataset.stop_requested = [] { return g_stop_signal != 0; };
    Progress progress("simulate " + loaded.scenario.name);
    const sim::DatasetSummary summary =
        sim::write_dataset(loaded, opt->dataset, [&](int done, int total) { progress.update(done, total); });
    const std::string& dir = opt->dataset.output_dir;
    if (summary.interrupted) {
      std::cerr << "fmcw: interrupted by " << (g_stop_signal == SIGTERM ? "SIGTERM" : "SIGINT") << ": " << dir << " holds "
                << summary.frames_written << " of " << summary.frames_total
                << " frames, all whole (dataset.yaml says so); continue with the same command and --resume\n";
      return 128 + static_cast<int>(g_stop_signal);
    }
    if (summary.frames_total > 0 && summary.frames_resumed == summary.frames_total) {
      std::cerr << dir << " is complete already (" << summary.frames_total << " frames)\n";
      return 0;
    }
    std::cerr << "wrote " << summary.frames_written - summary.frames_resumed << " frames to " << dir;
    if (summary.frames_resumed > 0) std::cerr << " after the " << summary.frames_resumed << " found there";
    std::cerr << " in " << summary.seconds << " s (" << summary.returns << " returns)\n";
    return 0;
  };
}

}  // namespace fmcw::cli
