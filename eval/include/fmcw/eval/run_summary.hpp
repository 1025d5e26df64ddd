#pragma once
// Per-run figures of one method over all frames, and the accuracy targets they are held to.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "fmcw/eval/frame_evaluation.hpp"
#include "fmcw/eval/tail_metrics.hpp"
#include "fmcw/eval/tracking_metrics.hpp"

namespace fmcw::eval {

struct SummaryParams {
  /// Objects with at least this many valid pixels form the "large object" median (the paper's
  /// Fig. 8: errors within 0.1 m/s above 200 points) [pixels].
  int large_object_pixels = 200;
  /// An actor counts in blind_zone.recall_tracked from the frame after one in which at least
  /// this many of its truly moving pixels were outside the blind band (visibly moving) [pixels].
  int blind_visible_pixels = 20;
  /// Objects turning faster than this count as turning [rad/s] (about 3 deg/s).
  double turning_yaw_rate_rps = 0.05;
  /// Tracks match objects when their point IoU is at least this (MotParams).
  double mot_iou_threshold = 0.5;
  /// Directions whose reported sigma exceeds this count as unobservable (TailParams) [m/s].
  double unobservable_sigma_mps = 1e3;
  /// Object-frames in the first this many frames of their actor count as young [frames].
  int young_updates = 5;

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
  int objects_large_turning = 0;                   ///< large pairs whose actor turns
  double median_reference_error_mps_ge200_turning = 0.0;  ///< median |estimate - reference| over those

  int yaw_frames = 0;               ///< frames with a yaw-rate estimate
  double yaw_rate_rmse_dps = 0.0;   ///< RMSE of the ego yaw rate [deg/s]; NaN when never estimated

  InstanceCounts instances;         ///< pooled over frames
  double instance_precision = 0.0;  ///< clusters_matched / clusters (NaN without clusters)
  double instance_recall = 0.0;     ///< actors_matched / actors (NaN without evaluated actors)

  /// Blind band: pixels of actors visibly moving in an earlier frame that lie inside the band.
  int blind_actor_frames = 0;
  std::uint64_t blind_band_pixels = 0;
  std::uint64_t blind_band_detected = 0;
  double blind_recall_tracked = 0.0;  ///< detected / band pixels (NaN when there are none)
  /// Pixels of the same actors whose own motion is in the band while their body's is not
  /// (wheels, limbs: BlindBandActor::part_band_pixels), and how many were labelled moving.
  std::uint64_t blind_part_pixels = 0;
  std::uint64_t blind_part_detected = 0;
  double blind_part_recall = 0.0;

  /// Tails and calibration of the centre-velocity errors (tail_metrics.hpp).
  ObjectTails tails;
  /// CLEAR MOT and IDF1 (tracking_metrics.hpp).
  MotReport tracking;

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
  double max_yaw_rate_rmse_dps = 0.5;       ///< ego yaw rate [deg/s]
  double min_blind_recall = 0.9;            ///< blind_zone.recall_tracked (checked when there is a band)
  /// The tails (objects with >= 200 points, velocity at the centre).
  double max_p95_error_large_mps = 0.5;
  double max_share_over_1mps_large = 0.02;
  /// covariance_coverage_95 inside [min, max]: the reported uncertainty neither too small nor
  /// too large.
  double min_coverage_95 = 0.90;
  double max_coverage_95 = 0.98;
  double min_mota = 0.85;  ///< tracking.mota over all classes
  double min_idf1 = 0.85;  ///< tracking.idf1 over all classes
  double min_mota_vehicles = 0.9;  ///< tracking.vehicles.mota (held where vehicles are evaluated)
  double min_idf1_vehicles = 0.9;  ///< tracking.vehicles.idf1 (held where vehicles are evaluated)
};

struct TargetCheck {
  /// "accuracy", "ego_rmse_x", "ego_rmse_y", "ego_rmse_z", "yaw_rate_rmse", "object_median_ge200"
  /// (against the mean surface velocity of the cluster's points), "object_centre_median_ge200"
  /// (against the velocity of the actor's centre), "object_centre_p95_ge200",
  /// "object_centre_share_over_1mps_ge200", "covariance_coverage_95_min",
  /// "covariance_coverage_95_max", "tracking_mota", "tracking_idf1", "blind_zone_recall_tracked"
  /// (where the band holds pixels), "tracking_mota_vehicles", "tracking_idf1_vehicles" (where
  /// vehicles are evaluated).
  std::string key;
  std::string relation;  ///< ">=" or "<="
  double value = 0.0;
  double limit = 0.0;
  bool met = false;  ///< false also when the value is NaN (nothing to measure)
};

std::vector<TargetCheck> check_targets(const MethodSummary& summary, const Targets& targets = {});

}  // namespace fmcw::eval
