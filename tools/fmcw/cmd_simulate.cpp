// fmcw simulate SCENARIO.yaml -o DIR: a synthetic FMCW dataset with ground truth.

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
};
}  // namespace

Action add_simulate_command(CLI::App& app) {
  auto opt = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand("simulate", "Simulate a scenario into a dataset (PCD frames + ground truth)");
  cmd->add_option("scenario", opt->scenario, "Scenario YAML file")->required();
  cmd->add_option("-o,--output", opt->dataset.output_dir, "Output dataset folder")->required();
  cmd->add_option("--frames", opt->dataset.frames, "Frames to simulate (default: the scenario's)")->check(CLI::PositiveNumber);
  CLI::Option* seed = cmd->add_option("--seed", opt->seed, "Noise seed (default: the scenario's)");
  cmd->add_option("--threads", opt->dataset.num_threads, "Ray-casting threads (0 = all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--overwrite", opt->dataset.overwrite, "Write into a non-empty output folder");
  return [opt, seed] {
    opt->dataset.override_seed = seed->count() > 0;
    opt->dataset.seed = opt->seed;
    opt->dataset.tool_version = FMCW_VERSION;
    const sim::LoadedScenario loaded = sim::load_scenario(opt->scenario);
    Progress progress("simulate " + loaded.scenario.name);
    const sim::DatasetSummary summary =
        sim::write_dataset(loaded, opt->dataset, [&](int done, int total) { progress.update(done, total); });
    std::cerr << "wrote " << summary.frames_written << " frames to " << opt->dataset.output_dir << " in "
              << summary.seconds << " s (" << summary.returns << " returns)\n";
    return 0;
  };
}

}  // namespace fmcw::cli
