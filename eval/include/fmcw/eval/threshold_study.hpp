#pragma once
// `fmcw study threshold`: the Doppler threshold v_th of Algorithm 1 swept on a dataset or a
// scenario: the precision/recall trade-off, and what v_th does to the velocities downstream.

#include <functional>
#include <string>
#include <vector>

#include "fmcw/eval/frame_source.hpp"
#include "fmcw/eval/run_summary.hpp"

namespace fmcw::eval {

struct ThresholdStudyParams {
  /// v_th values [m/s]; the paper's 0.17 and Eq. 14's bound lie among the defaults.
  std::vector<double> thresholds_mps = {0.03, 0.05, 0.08, 0.1, 0.12, 0.15, 0.17, 0.2, 0.25, 0.3, 0.4, 0.5, 0.75, 1.0};
  std::string method = "fast";  ///< preset whose v_th is swept (regions are the same for every preset)
  int stride = 1;               ///< use every stride-th frame of the source
  std::uint64_t seed = 0;
  int num_threads = 0;
  ObjectMatchParams objects;
  SummaryParams summary;

  void validate() const;
};

struct ThresholdPoint {
  double threshold_mps = 0.0;
  MethodSummary summary;
  double mean_clusters = 0.0;  ///< moving clusters per frame
};

struct ThresholdStudyResult {
  ThresholdStudyParams params;
  SourceInfo source;
  int frames_used = 0;
  double eq14_bound_mps = 0.0;  ///< Eq. 14 for 0.2 deg pixels and 25 m/s object and ego speeds
  std::vector<ThresholdPoint> points;
  double seconds = 0.0;
};

/// Frame by frame: each frame is read (or simulated) once and segmented at every threshold.
ThresholdStudyResult run_threshold_study(FrameSource& source, const ThresholdStudyParams& params,
                                         const std::function<void(std::size_t, std::size_t)>& progress = {});

/// threshold_sweep.csv, then metrics.json (kind "threshold").
void write_threshold_report(const std::string& dir, const ThresholdStudyResult& result, const std::string& tool_version);

}  // namespace fmcw::eval
