#pragma once
// Where evaluated frames come from: a dataset on disk (written by `fmcw simulate`) here, or a
// scenario simulated in memory (ScenarioSource, in fmcw::eval_sim: fmcw/eval/scenario_source.hpp).
// Either way frames are produced one at a time, never all at once. Reading a dataset needs no
// simulator: fmcw::eval links neither Embree nor assimp.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/io/frame_layout.hpp"

namespace fmcw::eval {

/// What a report says about where its frames came from.
struct SourceInfo {
  std::string scenario;        ///< scenario name
  std::string path;            ///< dataset folder or scenario file
  double rate_hz = 10.0;       ///< frame rate [Hz]
  std::uint64_t seed = 0;      ///< simulation noise seed
  std::string config_yaml;     ///< the resolved scenario as YAML (the exact config of the run)
  std::vector<std::string> notices;  ///< what the scenario's files hold that is not used, for the caller to say once
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  virtual std::size_t size() const = 0;
  /// Frame k with per-pixel truth (Frame::truth) and frame truth (Frame::frame_truth).
  virtual core::Frame frame(std::size_t k) = 0;
  /// Names frame k in error messages (its file, or "scenario.yaml frame k").
  virtual std::string describe(std::size_t k) const = 0;
  virtual const SourceInfo& info() const = 0;
};

/// A dataset folder: DIR/dataset.yaml (complete: true), DIR/frames/NNNNNN.pcd for frames
/// 0..n-1, DIR/ego.csv and DIR/objects.csv with n frames. The constructor checks all of that
/// and throws core::FileError naming the file at fault; frame(k) reads one PCD and
/// throws naming it when it is truncated, lacks ground truth, or has another shape or other
/// heads than frame 0. max_frames > 0 keeps the first max_frames frames.
class DatasetSource : public FrameSource {
 public:
  explicit DatasetSource(const std::string& dir, int max_frames = 0);
  std::size_t size() const override { return files_.size(); }
  core::Frame frame(std::size_t k) override;
  std::string describe(std::size_t k) const override { return files_.at(k); }
  const SourceInfo& info() const override { return info_; }

 private:
  SourceInfo info_;
  std::vector<std::string> files_;
  std::vector<core::FrameTruth> truth_;
  io::FrameLayoutCheck layout_;  ///< frame 0's shape and heads, which every frame must have
};

}  // namespace fmcw::eval
