// fmcw run SCENARIO.yaml -o DIR: simulate the scenario into DIR/dataset, evaluate every method
// on it and write the report into DIR, in one go.

#include <filesystem>
#include <iostream>

#include "commands.hpp"
#include "fmcw/core/errors.hpp"
#include "fmcw/eval/evaluation_report.hpp"
#include "fmcw/sim/dataset_writer.hpp"
#include "progress.hpp"

namespace fmcw::cli {

namespace fs = std::filesystem;

namespace {
struct RunOptions {
  std::string scenario;
  std::string output;
  int frames = 0;
  std::uint64_t seed = 0;
  std::vector<std::string> methods;
  int threads = 0;
  bool overwrite = false;
  bool no_figures = false;
};

// With --overwrite, an earlier run's dataset is removed first, so that stale frames of a longer
// run cannot mix with the new ones. Only a folder that is a dataset (it holds dataset.yaml or
// frames/) is removed.
void clear_previous_dataset(const fs::path& dir, bool overwrite) {
  std::error_code ec;
  if (!fs::exists(dir, ec) || fs::is_empty(dir, ec)) return;
  if (!overwrite) {
    throw core::InputError("dataset folder '" + dir.string() +
                           "' exists and is not empty (choose another output folder or pass --overwrite)");
  }
  if (!fs::exists(dir / "dataset.yaml", ec) && !fs::is_directory(dir / "frames", ec)) {
    throw core::InputError("'" + dir.string() + "' is not a dataset folder; not removing it");
  }
  fs::remove_all(dir, ec);
  if (ec) throw std::runtime_error("cannot remove the previous dataset '" + dir.string() + "': " + ec.message());
}
}  // namespace

Action add_run_command(CLI::App& app) {
  auto opt = std::make_shared<RunOptions>();
  CLI::App* cmd = app.add_subcommand("run", "Simulate a scenario, evaluate every method on it and write the report");
  cmd->add_option("scenario", opt->scenario, "Scenario YAML file")->required();
  cmd->add_option("-o,--output", opt->output, "Output folder (the dataset goes to DIR/dataset)")->required();
  cmd->add_option("--frames", opt->frames, "Frames to simulate (default: the scenario's)")->check(CLI::PositiveNumber);
  CLI::Option* seed = cmd->add_option("--seed", opt->seed, "Noise seed (default: the scenario's)")->check(seed_validator());
  cmd->add_option("--methods", opt->methods, "Methods to run, comma-separated (default: all; paper is always included)")
      ->delimiter(',')
      ->check(CLI::IsMember(core::MotionPipelineParams::preset_names()));
  cmd->add_option("--threads", opt->threads, "Threads (0 = all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--overwrite", opt->overwrite, "Replace the dataset of an earlier run in DIR/dataset");
  cmd->add_flag("--no-figures", opt->no_figures, "Write metrics.json and the tables only (no Python report)");
  return [opt, seed] {
    eval::EvaluationParams params;
    params.methods = opt->methods;
    params.num_threads = opt->threads;
    params.validate();
    const sim::LoadedScenario loaded = sim::load_scenario(opt->scenario);
    say_notices(loaded.notices);
    const fs::path dataset_dir = fs::path(opt->output) / "dataset";
    clear_previous_dataset(dataset_dir, opt->overwrite);

    sim::DatasetOptions ds;
    ds.output_dir = dataset_dir.string();
    ds.frames = opt->frames;
    ds.override_seed = seed->count() > 0;
    ds.seed = opt->seed;
    ds.num_threads = opt->threads;
    ds.tool_version = FMCW_VERSION;
    Progress sim_progress("simulate " + loaded.scenario.name);
    const sim::DatasetSummary summary =
        sim::write_dataset(loaded, ds, [&](int done, int total) { sim_progress.update(done, total); });
    std::cerr << "wrote " << summary.frames_written << " frames to " << ds.output_dir << " in " << summary.seconds
              << " s\n";

    eval::DatasetSource source(ds.output_dir);
    return evaluate_and_report(source, params, opt->output, opt->no_figures);
  };
}

}  // namespace fmcw::cli
