// fmcw generate [CONFIG.yaml] --count N --seed S -o DIR: procedural scenarios and their manifest.

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "commands.hpp"
#include "fmcw/core/errors.hpp"
#include "fmcw/io/atomic_file.hpp"
#include "fmcw/sim/scenario_generator.hpp"

namespace fmcw::cli {

namespace fs = std::filesystem;

namespace {
struct GenerateOptions {
  std::string config;
  int count = 0;
  std::uint64_t seed = 1;
  std::string output;
  bool overwrite = false;
};

std::string default_config() { return std::string(FMCW_SOURCE_DIR) + "/configs/generator.yaml"; }
}  // namespace

Action add_generate_command(CLI::App& app) {
  auto opt = std::make_shared<GenerateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "generate", "Write N procedural scenarios (layouts, traffic, rigs, noise) and a manifest, from a generator config");
  cmd->add_option("config", opt->config, "Generator config (default: configs/generator.yaml)");
  cmd->add_option("--count", opt->count, "Scenarios to write")->required()->check(CLI::Range(1, 1000000));
  cmd->add_option("--seed", opt->seed, "Seed of the set: the same seed gives the same files")->check(seed_validator());
  cmd->add_option("-o,--output", opt->output, "Output folder (scenarios/, manifest.csv, generator.yaml)")->required();
  cmd->add_flag("--overwrite", opt->overwrite, "Replace a set that fmcw generate wrote there before");
  return [opt] {
    const auto t0 = std::chrono::steady_clock::now();
    const std::string config_path = opt->config.empty() ? default_config() : opt->config;
    const sim::GeneratorConfig config = sim::GeneratorConfig::load(config_path);
    const std::shared_ptr<const sim::GeneratorAssets> assets = sim::load_generator_assets(config);

    // The output: new, empty, or a set written by generate (it holds manifest.csv) with --overwrite.
    const fs::path out(opt->output);
    if (fs::exists(out)) {
      if (!fs::is_directory(out)) throw core::InputError(opt->output + ": exists and is not a folder");
      if (!fs::is_empty(out)) {
        if (!opt->overwrite) {
          throw core::InputError(opt->output + ": not empty (use --overwrite to replace a set fmcw generate wrote)");
        }
        if (!fs::exists(out / "manifest.csv") || !fs::exists(out / "scenarios")) {
          throw core::InputError(opt->output +
                                 ": --overwrite replaces only a folder that fmcw generate wrote (with manifest.csv "
                                 "and scenarios/); this one is not");
        }
        fs::remove_all(out / "scenarios");
        fs::remove(out / "manifest.csv");
        fs::remove(out / "generator.yaml");
      }
    }
    fs::create_directories(out / "scenarios");
    io::ensure_writable_directory((out / "scenarios").string());

    std::vector<sim::ManifestRow> rows;
    int not_clear = 0;
    double min_clearance = 1e300;
    for (int k = 0; k < opt->count; ++k) {
      const sim::GeneratedScenario g = sim::generate_scenario(config, *assets, opt->seed, k);
      io::write_file_atomically((out / g.row.file).string(), [&](std::ostream& os) { os << g.yaml; });
      rows.push_back(g.row);
      not_clear += g.row.clearance_ok ? 0 : 1;
      min_clearance = std::min(min_clearance, g.row.min_clearance_m);
    }
    {
      std::ifstream in(config_path, std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      io::write_file_atomically((out / "generator.yaml").string(), [&](std::ostream& os) {
        os << "# The generator config this set was made from (" << fs::absolute(config_path).lexically_normal().string()
           << "), with --seed " << opt->seed << " --count " << opt->count << ".\n"
           << text.str();
      });
    }
    // The manifest last: its presence says the set is whole.
    io::write_file_atomically((out / "manifest.csv").string(), [&](std::ostream& os) {
      os << sim::manifest_header() << "\n";
      for (const auto& r : rows) os << sim::manifest_line(r) << "\n";
    });
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::cerr << "wrote " << rows.size() << " scenarios and manifest.csv to " << opt->output << " in " << seconds
              << " s; smallest clearance " << min_clearance << " m (required " << config.clearance_m << " m)\n";
    if (not_clear > 0) {
      std::cerr << "fmcw: error: " << not_clear << " scenario(s) break the clearance: see clearance_ok in manifest.csv\n";
      return 1;
    }
    return 0;
  };
}

}  // namespace fmcw::cli
