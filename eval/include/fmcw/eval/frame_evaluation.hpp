#pragma once
// Everything measured on one frame for one method: classification, ego error, objects, time.

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/core/motion_pipeline.hpp"
#include "fmcw/eval/motion_confusion.hpp"
#include "fmcw/eval/object_matching.hpp"
#include "fmcw/eval/tracking_metrics.hpp"

namespace fmcw::eval {

struct FrameEvaluation {
  std::size_t frame = 0;
  double stamp_s = 0.0;
  std::string method;
  core::MotionStatus status = core::MotionStatus::kOk;
  MotionConfusion motion;  ///< over the frame's valid pixels
  int num_clusters = 0;    ///< moving clusters reported
  int static_pixels = 0;
  bool ego_valid = false;
  Eigen::Vector3d ego_estimate_mps = Eigen::Vector3d::Constant(core::VelocityEstimate::kNaN);
  Eigen::Vector3d ego_truth_mps = Eigen::Vector3d::Zero();  ///< FrameTruth::ego.velocity_mps (rig origin)
  /// Velocity of the mean head mount point, V + omega x r_mean: what one velocity shared by all
  /// beam origins can at best be when the rig turns (equals ego_truth_mps without rotation).
  Eigen::Vector3d ego_truth_at_heads_mps = Eigen::Vector3d::Zero();
  std::vector<ObjectMatch> objects;
  InstanceCounts instances;
  TrackingFrame tracking;  ///< objects, tracks and their overlaps, for the tracking metrics
  std::vector<BlindBandActor> blind_band;  ///< see blind_band_actors
  /// Yaw rate: valid when the method estimates it (and the ego velocity is valid).
  bool yaw_rate_valid = false;
  double yaw_rate_estimate_rps = core::VelocityEstimate::kNaN;
  double yaw_rate_truth_rps = 0.0;  ///< FrameTruth::ego.angular_velocity_rps.z()
  core::StageTiming timing;

  /// estimate - truth (rig origin) [m/s]; NaN when the ego estimate is invalid.
  Eigen::Vector3d ego_error_mps() const { return ego_estimate_mps - ego_truth_mps; }
  /// estimate - velocity of the mean mount point [m/s].
  Eigen::Vector3d ego_error_at_heads_mps() const { return ego_estimate_mps - ego_truth_at_heads_mps; }
};

/// Compares an estimate with the frame's truth. The frame must carry per-pixel truth; truth is
/// the frame's row of the truth tables. Throws std::invalid_argument when sizes disagree or
/// the per-pixel truth is missing.
/// blind_band_mps: width of the Doppler blind band for BlindBandActor counts [m/s].
FrameEvaluation evaluate_frame(std::size_t frame_index, const core::Frame& frame, const core::FrameTruth& truth,
                               const core::MotionEstimate& estimate, const ObjectMatchParams& objects = {},
                               double blind_band_mps = 0.15);

}  // namespace fmcw::eval
