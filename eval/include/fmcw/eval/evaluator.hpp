#pragma once
// Runs every motion method on every frame of a source, frame by frame, and compares each with
// the ground truth: the heart of `fmcw evaluate`.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "fmcw/eval/frame_evaluation.hpp"
#include "fmcw/eval/frame_source.hpp"
#include "fmcw/eval/run_summary.hpp"

namespace fmcw::eval {

/// The methods to run: the given preset names (empty = every preset) with "paper", the
/// baseline, first. Throws std::invalid_argument for an unknown name, listing the known ones.
std::vector<std::string> methods_with_baseline(const std::vector<std::string>& wanted);

struct EvaluationParams {
  /// core::MotionPipelineParams preset names; empty = all presets. "paper" (the baseline) is
  /// always evaluated; it is added when missing and listed first.
  std::vector<std::string> methods;
  /// The core's default method (core::MotionPipelineParams::default_method()), named in reports.
  std::string default_method = core::MotionPipelineParams::default_method();
  std::uint64_t seed = 0;               ///< seeds the methods' random subsampling
  int num_threads = 0;                  ///< per-object estimation threads (0 = OpenMP default)
  ObjectMatchParams objects;
  /// Width of the Doppler blind band [m/s]: truly moving pixels with |e . v_true| below it are
  /// what a single scan cannot separate from the static world (the robust method's threshold
  /// is 4 sigma of the 0.031 m/s noise, about 0.124 m/s).
  double blind_band_mps = 0.15;
  SummaryParams summary;
  Targets targets;

  void validate() const;  ///< unknown method names throw std::invalid_argument listing the known
  std::vector<std::string> resolved_methods() const;
};

/// The dataset as the paper's Table II describes one.
struct DatasetStats {
  int frames = 0;                      ///< scans
  std::uint64_t valid_points = 0;      ///< returns over all frames
  std::uint64_t motion_points = 0;     ///< truly moving returns over all frames
  double duration_s = 0.0;             ///< frames / rate
  double max_ego_speed_mps = 0.0;
  double mean_ego_speed_mps = 0.0;
  bool ego_moving = false;             ///< the rig moves faster than 0.1 m/s in some frame
  int actors_seen = 0;                 ///< distinct actors with a valid pixel in some frame
};

/// One frame kept whole for the pictures (Fig. 1 and Fig. 4): the frame with the most actors
/// showing at least large_object_pixels moving pixels (ties: the most evaluated actors, then the
/// most truly moving pixels, then the earliest).
struct Snapshot {
  std::size_t frame_index = 0;
  core::Frame frame;
  std::vector<core::MotionEstimate> estimates;  ///< one per method, in EvaluationResult::methods order
};

struct EvaluationResult {
  SourceInfo source;
  EvaluationParams params;
  std::vector<std::string> methods;
  DatasetStats dataset;
  std::vector<std::vector<FrameEvaluation>> frames;  ///< [method][frame]
  std::vector<MethodSummary> summaries;              ///< [method]
  std::vector<std::vector<TargetCheck>> checks;      ///< [method]
  Snapshot snapshot;
};

/// progress(done, total) after each frame.
using ProgressFn = std::function<void(std::size_t, std::size_t)>;

/// Reads (or simulates) one frame at a time, runs every method on it, evaluates, and keeps only
/// the per-frame metrics and one snapshot frame. Errors while evaluating a frame are rethrown
/// as std::invalid_argument naming the frame's file.
EvaluationResult evaluate(FrameSource& source, const EvaluationParams& params, const ProgressFn& progress = {});

}  // namespace fmcw::eval
