#include "fmcw/sim/dataset_writer.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "fmcw/io/atomic_file.hpp"
#include "fmcw/io/pcd.hpp"
#include "fmcw/io/truth_tables.hpp"

namespace fmcw::sim {

namespace fs = std::filesystem;

namespace {
std::string frame_name(int k) {
  char name[32];
  std::snprintf(name, sizeof name, "%06d.pcd", k);
  return name;
}
}  // namespace

DatasetSummary write_dataset(const LoadedScenario& loaded_in, const DatasetOptions& options,
                             const std::function<void(int, int)>& progress) {
  LoadedScenario loaded = loaded_in;
  Scenario& s = loaded.scenario;
  if (options.frames > 0) s.frames = options.frames;
  if (options.override_seed) s.seed = options.seed;
  const fs::path dir(options.output_dir);
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_empty(dir, ec) && !options.overwrite) {
    throw std::invalid_argument("output folder '" + options.output_dir +
                                "' exists and is not empty (choose another folder or pass --overwrite)");
  }
  io::ensure_writable_directory((dir / "frames").string());

  const auto t0 = std::chrono::steady_clock::now();
  SimulationSetup setup = build_simulation(loaded, options.num_threads);
  LidarSimulator simulator(setup.scene, setup.ego, setup.params);
  std::string ego_rows = io::kEgoCsvHeader;
  std::string object_rows = io::kObjectsCsvHeader;
  DatasetSummary summary;
  core::Frame frame;
  for (int k = 0; k < s.frames; ++k) {
    simulator.simulate(static_cast<std::uint64_t>(k), s.frame_time_s(static_cast<std::uint64_t>(k)), frame);
    io::write_frame((dir / "frames" / frame_name(k)).string(), frame);
    ego_rows += io::ego_csv_row(static_cast<std::size_t>(k), *frame.frame_truth);
    object_rows += io::objects_csv_rows(static_cast<std::size_t>(k), *frame.frame_truth);
    summary.returns += frame.scan.num_valid();
    summary.frames_written = k + 1;
    if (progress) progress(k + 1, s.frames);
  }
  const auto write_text = [&](const char* name, const std::string& text) {
    io::write_file_atomically((dir / name).string(), [&](std::ostream& out) { out << text; });
  };
  write_text("ego.csv", ego_rows);
  write_text("objects.csv", object_rows);
  std::ostringstream yaml;
  yaml << "# FMCW LiDAR dataset written by fmcw simulate\n"
       << "format: fmcw-dataset\nformat_version: 1\n"
       << "tool_version: " << options.tool_version << "\n"
       << "complete: true\n"
       << "frames_written: " << summary.frames_written << "\n"
       << "frame_files: frames/%06d.pcd\n"
       << "fields: [x, y, z, range, v, intensity" << (s.motion_distortion ? ", t" : "")
       << ", gt_range, gt_v, gt_vx, gt_vy, gt_vz, instance, moving]\n"
       << "scenario:\n";
  std::istringstream resolved(scenario_to_yaml(s));
  for (std::string line; std::getline(resolved, line);) yaml << "  " << line << "\n";
  write_text("dataset.yaml", yaml.str());
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return summary;
}

}  // namespace fmcw::sim
