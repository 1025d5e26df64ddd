#pragma once
// Per-run figures of one method over all frames, and the accuracy targets they are held to.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "fmcw/eval/frame_evaluation.hpp"

namespace fmcw::eval {

struct SummaryParams {
  /// Objects with at least this many valid pixels form the "large object" median (the paper's
  /// Fig. 8: errors within 0.1 m/s above 200 points) [pixels].
  int large_object_pixels = 200;

  void validate() const;
};

struct MethodSummary {
  std::string method;
  int frames = 0;
  int frames_not_ok = 0;   ///< frames whose MotionStatus is not kOk
  MotionConfusion motion;  ///< pooled over all frames' valid pixels

  int ego_frames = 0;  ///< frames with a valid ego estimate (the others are left out of the errors)
  Eigen::Vector3d ego_rmse_mps = Eigen::Vector3d::Zero();     ///< per axis, vs the rig origin's velocity
  Eigen::Vector3d ego_max_abs_mps = Eigen::Vector3d::Zero();  ///< per axis
  Eigen::Vector3d ego_rmse_at_heads_mps = Eigen::Vector3d::Zero();  ///< vs the mean mount point's velocity

  int objects_evaluated = 0;  ///< (frame, actor) pairs with >= min_moving_pixels moving pixels
  int objects_detected = 0;   ///< of which detected
  int objects_estimated = 0;  ///< of which detected with a valid velocity estimate
  double detected_fraction = 0.0;  ///< detected / evaluated (NaN when none evaluated)
  int objects_large = 0;           ///< estimated pairs with pixels >= large_object_pixels
  double median_error_mps = 0.0;        ///< median |estimate - truth_mean| over estimated pairs
  double median_error_mps_ge200 = 0.0;  ///< the same over large pairs
  double p90_error_mps_ge200 = 0.0;     ///< 90th percentile over large pairs
  double median_reference_error_mps = 0.0;        ///< median |estimate - reference| over estimated pairs
  double median_reference_error_mps_ge200 = 0.0;  ///< the same over large pairs

  core::StageTiming mean_timing_ms;  ///< mean per frame
  core::StageTiming max_timing_ms;   ///< worst frame
};

/// Summarises one method's frames. Throws std::invalid_argument when frames mix methods.
MethodSummary summarize(const std::vector<FrameEvaluation>& frames, const SummaryParams& params = {});

/// The accuracy the paper reports (Section IV), held against every run.
struct Targets {
  double min_accuracy = 0.995;                                    ///< motion accuracy (Eq. 25)
  Eigen::Vector3d max_ego_rmse_mps = Eigen::Vector3d(0.01, 0.01, 0.03);  ///< per axis [m/s]
  double max_median_error_large_mps = 0.1;  ///< median object error, >= 200 pixels [m/s]
};

struct TargetCheck {
  std::string key;       ///< "accuracy", "ego_rmse_x", "ego_rmse_y", "ego_rmse_z", "object_median_ge200"
  std::string relation;  ///< ">=" or "<="
  double value = 0.0;
  double limit = 0.0;
  bool met = false;  ///< false also when the value is NaN (nothing to measure)
};

std::vector<TargetCheck> check_targets(const MethodSummary& summary, const Targets& targets = {});

}  // namespace fmcw::eval
