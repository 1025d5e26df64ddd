// fmcw: simulate, process and evaluate FMCW LiDAR scans.

#include <iostream>
#include <map>
#include <string>

#include "commands.hpp"
#include "fmcw/core/errors.hpp"

namespace {

// Exit codes by the kind of error (README, "Exit codes"); 128 + N after signal N.
constexpr int kExitOther = 1;  // anything else: an output that cannot be written, a failed estimate
constexpr int kExitUsage = 2;  // a command line or a value the program refuses (core::InputError)
constexpr int kExitFile = 3;   // a file that is missing, unreadable or malformed (core::FileError)
constexpr int kExitLimit = 4;  // a resource limit: memory budget, sizes, threads (core::LimitError)

const char* const kExitCodesHelp =
    "Exit codes: 0 success; 1 any other failure (an output that cannot be written, a frame the "
    "method cannot estimate); 2 usage or bad input (command line, option values, an output folder "
    "that may not be used); 3 a file that is missing, unreadable or malformed; 4 a resource limit "
    "(memory budget, sizes, thread counts); 128+N after signal N.";

// One line, however many the message has.
std::string one_line(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return text;
}

int fail(const std::string& what, int code) {
  std::cerr << "fmcw: error: " << one_line(what) << std::endl;
  return code;
}

// The subcommand a command line named, for the hint after a parse error ("" when none).
std::string named_subcommand(const CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands({})) {
    if (sub->parsed()) return sub->get_name() + " ";
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fmcw: FMCW LiDAR motion perception (Doppler clustering and velocity estimation)"};
  app.footer(kExitCodesHelp);
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
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);  // --help, --version
    return fail(e.what() + std::string(" (see fmcw ") + named_subcommand(app) + "--help)", kExitUsage);
  }
  try {
    for (auto& [sub, action] : actions) {
      if (sub->parsed()) return action();
    }
  } catch (const fmcw::core::LimitError& e) {
    return fail(e.what(), kExitLimit);
  } catch (const fmcw::core::FileError& e) {
    return fail(e.what(), kExitFile);
  } catch (const std::invalid_argument& e) {  // core::InputError, or bad input the core names untyped
    return fail(e.what(), kExitUsage);
  } catch (const std::exception& e) {
    return fail(e.what(), kExitOther);
  }
  return kExitOther;
}
