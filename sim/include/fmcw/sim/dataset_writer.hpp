#pragma once
// Writes a simulated dataset: dataset.yaml, frames/NNNNNN.pcd, ego.csv, objects.csv.

#include <cstdint>
#include <functional>
#include <string>

#include "fmcw/sim/scenario.hpp"

namespace fmcw::sim {

struct DatasetOptions {
  std::string output_dir;
  int frames = 0;              ///< 0: the scenario's count
  bool override_seed = false;
  std::uint64_t seed = 0;
  int num_threads = 0;
  bool overwrite = false;      ///< allow a non-empty output folder
  std::string tool_version = "unknown";
};

struct DatasetSummary {
  int frames_written = 0;
  double seconds = 0.0;
  std::size_t returns = 0;  ///< valid pixels over all frames
};

/// Simulates every frame and writes the dataset. Each frame file is written under a temporary
/// name and renamed; ego.csv, objects.csv and dataset.yaml are written last, so a dataset.yaml
/// that says complete: true means every file is there. progress(done, total) is called after
/// each frame. Throws std::invalid_argument for bad input, std::runtime_error for I/O failures.
DatasetSummary write_dataset(const LoadedScenario& loaded, const DatasetOptions& options,
                             const std::function<void(int, int)>& progress = {});

}  // namespace fmcw::sim
