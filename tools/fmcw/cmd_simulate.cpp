// fmcw simulate SCENARIO.yaml -o DIR: a synthetic FMCW dataset with ground truth.

#include <csignal>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "commands.hpp"
#include "fmcw/core/errors.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/sim/dataset_writer.hpp"
#include "fmcw/sim/scenario_generator.hpp"
#include <sstream>
#include "progress.hpp"

namespace fmcw::cli {

namespace {

struct SimulateOptions {
  std::string scenario;
  sim::DatasetOptions dataset;
  std::uint64_t seed = 0;
  std::string shard;
  std::string task;
  std::uint64_t max_memory_mb = 0;
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
std::pair<int, int> parse_shard(const std::string& text, const std::string& option) {
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
    throw core::InputError(option + " '" + text + "': expected I/N with 0 <= I < N, e.g. 0/4 for the first of four");
  }
  return {i, n};
}

// Simulates one scenario into opt.dataset.output_dir; the exit status.
int simulate_one(const std::string& scenario, sim::DatasetOptions options, std::uint64_t max_memory_mb) {
  const sim::LoadedScenario loaded = sim::load_scenario(scenario, max_memory_mb << 20);
  say_notices(loaded.notices);
  options.stop_requested = [] { return g_stop_signal != 0; };
  Progress progress("simulate " + loaded.scenario.name);
  const sim::DatasetSummary summary =
      sim::write_dataset(loaded, options, [&](int done, int total) { progress.update(done, total); });
  const std::string& dir = options.output_dir;
  if (!summary.resume_note.empty()) say_notices({summary.resume_note});
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
}

// A set written by fmcw generate: every scenario of the manifest (or of task I of N: those whose
// row number is I modulo N) into OUTPUT/<name>/, and the manifest beside them.
int simulate_set(const SimulateOptions& opt) {
  const std::filesystem::path set(opt.scenario);
  const std::vector<sim::SetEntry> scenarios = sim::read_set_manifest((set / "manifest.csv").string());
  int task = 0, tasks = 1;
  if (!opt.task.empty()) std::tie(task, tasks) = parse_shard(opt.task, "--task");
  {
    // The manifest beside the datasets, for fmcw evaluate over the folder; every task writes
    // the same bytes, atomically.
    std::ifstream in(set / "manifest.csv", std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    io::ensure_writable_directory(opt.dataset.output_dir);
    io::write_file_atomically(opt.dataset.output_dir + "/manifest.csv", [&](std::ostream& os) { os << text.str(); });
  }
  int done = 0;
  for (std::size_t k = 0; k < scenarios.size(); ++k) {
    if (static_cast<int>(k % static_cast<std::size_t>(tasks)) != task) continue;
    sim::DatasetOptions options = opt.dataset;
    options.output_dir = opt.dataset.output_dir + "/" + scenarios[k].name;
    const int status = simulate_one((set / scenarios[k].file).string(), options, opt.max_memory_mb);
    if (status != 0) return status;
    ++done;
  }
  std::cerr << "simulated " << done << " of the set's " << scenarios.size() << " scenarios into " << opt.dataset.output_dir
            << (tasks > 1 ? " (task " + std::to_string(task) + " of " + std::to_string(tasks) + ")" : std::string()) << "\n";
  return 0;
}

}  // namespace

Action add_simulate_command(CLI::App& app) {
  auto opt = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand("simulate", "Simulate a scenario into a dataset (PCD frames + ground truth)");
  cmd->add_option("scenario", opt->scenario, "Scenario YAML file, or a set folder written by fmcw generate")->required();
  cmd->add_option("-o,--output", opt->dataset.output_dir, "Output dataset folder")->required();
  cmd->add_option("--frames", opt->dataset.frames, "Frames to simulate (default: the scenario's)")->check(CLI::PositiveNumber);
  CLI::Option* seed = cmd->add_option("--seed", opt->seed, "Noise seed (default: the scenario's)")->check(seed_validator());
  cmd->add_option("--threads", opt->dataset.num_threads, "Ray-casting threads (0 = all cores)")->check(CLI::NonNegativeNumber);
  CLI::Option* overwrite = cmd->add_flag("--overwrite", opt->dataset.overwrite, "Write into a non-empty output folder");
  cmd->add_flag("--resume", opt->dataset.resume,
                "Continue a stopped run in the output folder (same arguments); the result is byte-identical to an "
                "uninterrupted run")
      ->excludes(overwrite);
  cmd->add_option("--max-memory", opt->max_memory_mb,
                  "Memory budget [MB] for the scenario's estimate (rig pixels, placed triangles); default: half of "
                  "this machine's memory")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 30));
  cmd->add_option("--shard", opt->shard,
                  "Write only part I of N of the dataset (frames I*F/N to (I+1)*F/N); join the parts with fmcw merge");
  cmd->add_option("--task", opt->task,
                  "With a set: simulate only the scenarios of task I of N (row number modulo N), e.g. "
                  "$SLURM_ARRAY_TASK_ID/N");
  return [opt, seed] {
    opt->dataset.override_seed = seed->count() > 0;
    opt->dataset.seed = opt->seed;
    opt->dataset.tool_version = FMCW_VERSION;
    if (!opt->shard.empty()) std::tie(opt->dataset.shard_index, opt->dataset.shard_count) = parse_shard(opt->shard, "--shard");
    install_stop_handlers();
    if (std::filesystem::is_directory(opt->scenario)) {
      if (!opt->shard.empty()) throw core::InputError("--shard is for one scenario; a set is split with --task I/N");
      return simulate_set(*opt);
    }
    if (!opt->task.empty()) throw core::InputError("--task is for a set folder written by fmcw generate");
    return simulate_one(opt->scenario, opt->dataset, opt->max_memory_mb);
  };
}

}  // namespace fmcw::cli
