#pragma once
// Matching ground-truth actors to estimated moving clusters, and their velocity errors.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/core/motion_pipeline.hpp"

namespace fmcw::eval {

struct ObjectMatchParams {
  /// An actor is "evaluated" in a frame when at least this many of its valid pixels are truly
  /// moving (ground truth `moving`) [pixels].
  int min_moving_pixels = 3;

  void validate() const;
};

/// One actor seen in one frame (at least one valid pixel), for one method.
///
/// The actor's cluster is the moving cluster (label >= 1) holding most of its valid pixels; it is
/// "detected" when that cluster holds more than half of them. Two truths are compared:
/// - truth_mean_mps: the mean ground-truth surface velocity (gt_vx, gt_vy, gt_vz) over the actor's
///   pixels inside its cluster. This is what a single-velocity model fitted to exactly those
///   points can recover; it differs from the actor's reference velocity where parts move on
///   their own (wheels, limbs) or the actor turns (omega x r).
/// - reference_mps: ActorTruth::velocity_rig_mps, the velocity of the actor's origin.
struct ObjectMatch {
  std::uint32_t actor_id = 0;
  std::string class_name;
  int pixels = 0;         ///< valid pixels of the actor
  int moving_pixels = 0;  ///< of which truly moving
  double distance_m = 0.0;  ///< |position_rig_m| [m]
  bool evaluated = false;   ///< moving_pixels >= min_moving_pixels
  std::int32_t cluster = 0;  ///< best moving cluster's label, 0 when none holds an actor pixel
  int pixels_in_cluster = 0;  ///< actor pixels in that cluster
  int cluster_pixels = 0;     ///< all pixels of that cluster
  bool detected = false;      ///< 2 * pixels_in_cluster > pixels
  bool estimate_valid = false;  ///< detected and the cluster's velocity estimate is valid
  Eigen::Vector3d estimate_mps = Eigen::Vector3d::Constant(core::VelocityEstimate::kNaN);    ///< cluster velocity, rig axes
  Eigen::Vector3d truth_mean_mps = Eigen::Vector3d::Constant(core::VelocityEstimate::kNaN);  ///< see above
  Eigen::Vector3d reference_mps = Eigen::Vector3d::Zero();          ///< see above
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  ///< ActorTruth::position_rig_m
  double yaw_rate_rps = 0.0;  ///< the actor's true yaw rate (ActorTruth, z) [rad/s]
  /// From a tracking method (NaN otherwise): the track's box centre and yaw rate.
  Eigen::Vector3d estimate_centre_m = Eigen::Vector3d::Constant(core::VelocityEstimate::kNaN);
  double estimate_yaw_rate_rps = core::VelocityEstimate::kNaN;
  std::int32_t estimate_track_id = 0;  ///< the cluster's track (0: untracked)
  /// The estimate's reported covariance (VelocityEstimate::covariance; NaN when none) [m^2/s^2].
  Eigen::Matrix3d estimate_covariance = Eigen::Matrix3d::Constant(core::VelocityEstimate::kNaN);

  /// estimate - truth_mean (NaN unless estimate_valid) [m/s]
  Eigen::Vector3d error_mps() const { return estimate_mps - truth_mean_mps; }
  /// estimate - reference (NaN unless estimate_valid) [m/s]
  Eigen::Vector3d reference_error_mps() const { return estimate_mps - reference_mps; }
};

/// Instance segmentation against the actors, one frame: a cluster and an evaluated actor
/// match when their pixel sets overlap with IoU > 0.5 (so each has at most one match).
struct InstanceCounts {
  int clusters = 0;          ///< moving clusters reported
  int clusters_matched = 0;  ///< of which match an evaluated actor
  int actors = 0;            ///< evaluated actors (>= min_moving_pixels truly moving pixels)
  int actors_matched = 0;    ///< of which match a cluster

  InstanceCounts& operator+=(const InstanceCounts& o) {
    clusters += o.clusters;
    clusters_matched += o.clusters_matched;
    actors += o.actors;
    actors_matched += o.actors_matched;
    return *this;
  }
};

InstanceCounts count_instances(const core::PixelGroundTruth& gt, const std::vector<std::uint8_t>& valid,
                               const core::MotionEstimate& estimate, const ObjectMatchParams& params = {});

/// One moving actor's pixels inside the Doppler blind band in one frame. A truly moving pixel is
/// in the band when the actor's rigid-body motion at that point, v + omega x (p - c), has a
/// component along the beam below the band (a single scan cannot tell it from the static world):
/// the blind zone of the object's motion. Parts that move on their own (wheels, swinging limbs)
/// have pixels whose own motion is in the band wherever the body is: the front and back of
/// every rolling wheel move up and down, across the beams. Those are counted apart
/// (part_band_*), since no choice of heading puts them in or out of the band.
struct BlindBandActor {
  std::uint32_t actor_id = 0;
  int band_pixels = 0;
  int band_detected = 0;
  int visible_pixels = 0;       ///< truly moving pixels whose body motion is outside the band
  int part_band_pixels = 0;     ///< ... of which their own motion is inside it (wheels, limbs)
  int part_band_detected = 0;
};

/// Actors with truly moving pixels, in increasing id order. band_mps > 0. Throws
/// std::invalid_argument when a pixel's instance is missing from truth.actors.
std::vector<BlindBandActor> blind_band_actors(const core::Scan& scan, const core::PixelGroundTruth& gt,
                                              const core::FrameTruth& truth, const core::MotionEstimate& estimate,
                                              double band_mps);

/// Every actor with a valid pixel in the frame, in increasing id order. Throws
/// std::invalid_argument when an array does not hold one value per pixel, when a pixel's
/// instance is missing from truth.actors, or when a label names a cluster the estimate lacks.
std::vector<ObjectMatch> match_objects(const core::PixelGroundTruth& gt, const std::vector<std::uint8_t>& valid,
                                       const core::FrameTruth& truth, const core::MotionEstimate& estimate,
                                       const ObjectMatchParams& params = {});

}  // namespace fmcw::eval
