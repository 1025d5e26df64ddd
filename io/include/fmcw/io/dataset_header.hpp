#pragma once
// dataset.yaml: what a dataset folder holds and the exact scenario it came from. One writer and
// one reader, so that a resumed run, a shard and a merge of shards all write the same bytes as
// a single uninterrupted run.

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace fmcw::io {

/// Frames [first_frame, end_frame) of a dataset cut into count parts; this is part index.
struct ShardInfo {
  int index = 0;
  int count = 1;
  int first_frame = 0;
  int end_frame = 0;

  /// Part index of count over total frames: an even split, the first parts never larger.
  static ShardInfo of(int index, int count, int total_frames);
  int frames() const { return end_frame - first_frame; }
  bool operator==(const ShardInfo& o) const {
    return index == o.index && count == o.count && first_frame == o.first_frame && end_frame == o.end_frame;
  }
};

/// "000042.pcd": the name of frame k under DIR/frames/ (six digits, more past 999999). The one
/// place that formats a frame's file name: the writer, a merge, a resume and the reader use it.
std::string frame_file_name(long long k);

struct DatasetHeader {
  std::string tool_version;
  /// true once every frame of the dataset (or of the shard) and both truth tables are written.
  bool complete = false;
  /// Whole frames on disk, counted from the first frame of the dataset (or of the shard).
  int frames_written = 0;
  bool motion_distortion = false;  ///< frames carry the per-pixel time field t
  std::optional<ShardInfo> shard;  ///< absent for a whole dataset
  /// The class table of the field `class`: (id, name) pairs. Empty in datasets written before
  /// classes were.
  std::vector<std::pair<std::uint16_t, std::string>> classes;
  /// The resolved scenario as YAML (scenario_to_yaml), kept verbatim.
  std::string scenario_yaml;
  /// What an evaluation reports of the scenario: read() takes them from the scenario block;
  /// to_yaml() writes scenario_yaml alone, which holds them.
  struct ScenarioKeys {
    std::string name;
    double rate_hz = 0.0;    ///< frame rate [Hz], > 0
    std::uint64_t seed = 0;  ///< simulation noise seed
  } scenario;

  std::string to_yaml() const;
  /// Reads DIR/dataset.yaml, the one reader of it (the writer's resume, a merge and the
  /// evaluation all use it). It is lenient about keys a newer writer may add, strict about what
  /// it reads: core::FileError naming file, line and key when it is not a dataset header this
  /// tool wrote.
  static DatasetHeader read(const std::string& file);
};

}  // namespace fmcw::io
