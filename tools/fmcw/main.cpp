// fmcw: simulate, process and evaluate FMCW LiDAR scans.

#include <iostream>
#include <map>

#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"fmcw: FMCW LiDAR motion perception (Doppler clustering and velocity estimation)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("fmcw ") + FMCW_VERSION);
  std::map<CLI::App*, fmcw::cli::Action> actions;
  const auto reg = [&](fmcw::cli::Action (*add)(CLI::App&)) {
    const std::size_t before = app.get_subcommands({}).size();
    fmcw::cli::Action action = add(app);
    actions[app.get_subcommands({}).at(before)] = std::move(action);
  };
  reg(fmcw::cli::add_generate_command);
  reg(fmcw::cli::add_simulate_command);
  reg(fmcw::cli::add_merge_command);
  reg(fmcw::cli::add_process_command);
  reg(fmcw::cli::add_synth_command);
  reg(fmcw::cli::add_bench_command);
  reg(fmcw::cli::add_evaluate_command);
  reg(fmcw::cli::add_run_command);
  reg(fmcw::cli::add_study_command);
  reg(fmcw::cli::add_export_command);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  try {
    for (auto& [sub, action] : actions) {
      if (sub->parsed()) return action();
    }
  } catch (const std::exception& e) {
    std::cerr << "fmcw: error: " << e.what() << std::endl;
    return 1;
  }
  return 1;
}
