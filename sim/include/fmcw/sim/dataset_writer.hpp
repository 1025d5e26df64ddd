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
  /// Continue the dataset in output_dir where it stopped (same scenario, options and tool
  /// version); a missing or empty folder starts from the beginning.
  bool resume = false;
  int shard_index = 0;         ///< write part shard_index of shard_count (frames by io::ShardInfo::of)
  int shard_count = 1;
  std::string tool_version = "unknown";
  /// Asked before each frame; true stops the run after the last whole frame (SIGINT, SIGTERM).
  std::function<bool()> stop_requested;
};

struct DatasetSummary {
  int frames_written = 0;   ///< whole frames on disk, of this dataset or shard
  int frames_total = 0;     ///< frames the dataset or shard will have when complete
  int frames_resumed = 0;   ///< frames found complete on disk when the run started
  bool interrupted = false; ///< stop_requested said so before the last frame
  double seconds = 0.0;
  std::size_t returns = 0;  ///< valid pixels over the frames simulated in this run
  /// With resume: the first counted frame that was missing, cut short or another frame's, and
  /// that it was simulated again from there ("" when every counted frame was whole).
  std::string resume_note;
};

/// Simulates the frames and writes the dataset. Each frame file is written under a temporary
/// name and renamed; after it, its rows are appended to ego.csv and objects.csv and
/// dataset.yaml is rewritten (atomically) with the count of whole frames. So at any instant,
/// even after SIGKILL, dataset.yaml counts frames that are whole on disk, and `complete: true`
/// means every file is there. A resumed, sharded or interrupted run writes the same bytes per
/// frame as one uninterrupted run: frame k's noise depends on the seed and k alone.
/// progress(done, total) is called after each frame. Throws core::InputError for options the
/// folder does not allow (not empty, another run's dataset), core::FileError for a dataset to
/// resume whose files are broken, core::LimitError beyond the memory budget, and
/// std::runtime_error for I/O failures (the message says how many frames are whole).
DatasetSummary write_dataset(const LoadedScenario& loaded, const DatasetOptions& options,
                             const std::function<void(int, int)>& progress = {});

}  // namespace fmcw::sim
