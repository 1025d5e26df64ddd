// fmcw merge SHARD_DIR... -o DIR: joins the parts written by fmcw simulate --shard I/N.

#include <iostream>

#include "commands.hpp"
#include "fmcw/sim/dataset_merge.hpp"

namespace fmcw::cli {

namespace {
struct MergeOptions {
  std::vector<std::string> shards;
  std::string output;
  bool overwrite = false;
};
}  // namespace

Action add_merge_command(CLI::App& app) {
  auto opt = std::make_shared<MergeOptions>();
  CLI::App* cmd = app.add_subcommand(
      "merge", "Join the shards of a dataset (fmcw simulate --shard I/N) into the dataset one run would have written");
  cmd->add_option("shards", opt->shards, "Shard folders, all N of them, in any order")->required();
  cmd->add_option("-o,--output", opt->output, "Output dataset folder")->required();
  cmd->add_flag("--overwrite", opt->overwrite, "Write into a non-empty output folder");
  return [opt] {
    const sim::MergeSummary s = sim::merge_shards(opt->shards, opt->output, opt->overwrite);
    std::cerr << "merged " << s.shards << " shards into " << opt->output << ": " << s.frames << " frames ("
              << s.frames_linked << " hard-linked, " << s.frames - s.frames_linked << " copied)\n";
    return 0;
  };
}

}  // namespace fmcw::cli
