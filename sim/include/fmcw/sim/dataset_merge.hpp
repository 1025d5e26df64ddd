#pragma once
// Joins the shards of a dataset (fmcw simulate --shard i/n) into one dataset, byte-identical to
// the dataset one uninterrupted run would have written.

#include <string>
#include <vector>

namespace fmcw::sim {

struct MergeSummary {
  int shards = 0;
  int frames = 0;
  int frames_linked = 0;  ///< hard-linked frame files (the rest were copied)
};

/// Checks that shard_dirs are the complete shards 0..n-1 of one dataset (same scenario, options
/// and tool version, frame ranges that tile the dataset), in any order, then writes
/// output_dir: frames hard-linked where the file system allows (copied otherwise), the truth
/// tables joined in frame order, dataset.yaml last. std::invalid_argument names the shard and
/// what is wrong; std::runtime_error for I/O failures. output_dir must be absent or empty
/// unless overwrite.
MergeSummary merge_shards(const std::vector<std::string>& shard_dirs, const std::string& output_dir, bool overwrite = false);

}  // namespace fmcw::sim
