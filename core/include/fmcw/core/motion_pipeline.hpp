#pragma once
// Scan -> MotionEstimate: segmentation, ego velocity, per-object velocity, with stage timings.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fmcw/core/ceres_velocity.hpp"
#include "fmcw/core/doppler_segmentation.hpp"
#include "fmcw/core/ego_twist.hpp"
#include "fmcw/core/moving_instances.hpp"
#include "fmcw/core/object_tracker.hpp"
#include "fmcw/core/velocity_lsq.hpp"

namespace fmcw::core {

enum class VelocitySolver { kClosedForm, kCeres };

struct VelocityParams {
  VelocitySolver solver = VelocitySolver::kClosedForm;
  /// num_th^s: cap on static points used for the ego velocity, drawn at random; 0 = all.
  int ego_max_points = 0;
  /// num_th^m: cap on points used per moving cluster (paper: 200); 0 = all.
  int object_max_points = 0;
  double qr_condition_threshold = 1e8;  ///< closed form: above this cond(A^T A), use QR
  CeresVelocityParams ceres;            ///< used when solver == kCeres

  void validate() const;
};

/// How static and moving points are told apart.
enum class MotionApproach {
  kLargestRegionStatic,  ///< Algorithm 1: Doppler regions, the largest one is static
  kRobustEgo,            ///< robust ego twist first; moving = points it does not explain
};

struct MotionPipelineParams {
  std::string method = "fast";  ///< name reported with the results
  MotionApproach approach = MotionApproach::kLargestRegionStatic;
  SegmentationParams segmentation;  ///< kLargestRegionStatic
  VelocityParams velocity;
  EgoTwistParams ego;               ///< kRobustEgo
  /// kRobustEgo with track_objects: the previous frame's twist bounds this one's (TwistPrior),
  /// for frames at most tracking.lifecycle.max_gap_s apart.
  TwistPriorParams ego_prior;
  /// kRobustEgo: a point moves when its ego-compensated Doppler |v + e . V_origin| exceeds this
  /// many standard deviations (sensor noise and the ego estimate's uncertainty along e).
  double moving_sigma = 4.0;
  /// kRobustEgo: the sensor's velocity noise where the static world shows more of it than
  /// ego.noise_sigma_mps. A coherent lidar's precision falls with its signal (with range, on
  /// dark surfaces, at grazing incidence), and a fixed sigma then finds moving pixels in the far
  /// static world, in clusters that become false objects. Per cell of one image row and one band
  /// of range_noise_band_m metres (the last of range_noise_bands open-ended; a row sees about
  /// one surface at one incidence there: the ground, a wall), the spread of its residuals within
  /// the threshold (their median |residual| over a unit normal's, 0.674; every other column
  /// counted), where it exceeds ego.noise_sigma_mps range_noise_margin times, is the sensor's
  /// sigma there; a cell of fewer than range_noise_min_pixels counted pixels takes its band's
  /// over every row. Done only where some band's root mean square residual (every fourth row)
  /// exceeds the margin: on a scan whose noise is the nominal one nothing changes. 0: the
  /// nominal sigma everywhere.
  double range_noise_band_m = 10.0;
  int range_noise_bands = 10;
  int range_noise_min_pixels = 100;
  double range_noise_margin = 1.25;
  InstanceParams instances;         ///< kRobustEgo
  /// Track objects across frames (ObjectTracker): tangential velocity and yaw rate from
  /// several scans, "moving" carried through the Doppler blind band. Frames must then be
  /// processed in time order by one MotionPipeline.
  bool track_objects = false;
  TrackerParams tracking;
  /// kRobustEgo: objects move in the horizontal plane of the rig (v_z = 0). A few degrees of
  /// elevation leave v_z nearly unobservable, and limbs or wheels would leak into it.
  bool planar_objects = true;
  /// kRobustEgo with planar_objects: an untracked object's horizontal velocity direction known
  /// to worse than this is reported as zero, its variance saying it is unknown
  /// (zero_unobserved_direction). Tracks take the fits as they are [m/s].
  double max_weak_sigma_mps = 0.5;
  /// paper and fast: an object velocity whose covariance gives some direction a standard
  /// deviation above this, that has no covariance (3 points or fewer), or whose speed exceeds
  /// 1000 m/s is flagged not valid (flag_meaningless): the published fit is kept, but no one
  /// should act on it [m/s].
  double max_valid_sigma_mps = 10.0;
  /// Every method: when fewer than this fraction of the valid points belong to the static world
  /// (the largest region, or the ego twist's inliers), the scan shows no static world (every
  /// point moving, each its own way) and no ego velocity is reported: kTooFewStaticPoints.
  /// Noise-like Doppler gives chance "worlds" of a few pixels (paper, fast) or about
  /// 2 x inlier threshold / Doppler spread of the points (robust: 0.5 % over +-20 m/s).
  double min_static_fraction = 0.01;
  std::uint64_t seed = 0;  ///< seeds the random subsampling (mixed with the frame index)
  int num_threads = 0;     ///< per-object estimation threads; 0 = OpenMP default, 1 = serial

  void validate() const;

  /// "robust": the ego twist (velocity and yaw rate) by MSAC over all points, scored by how
  /// much of the view its inliers cover, with a standing test and Huber refinement; moving
  /// points are those the twist does not explain; instances by range and Doppler continuity;
  /// object velocities in closed form with each head's own origin velocity.
  /// "tracked": "robust", then a filter per object across frames (constant turn rate, each
  /// point's Doppler a measurement row): velocity at the object's centre with its yaw rate,
  /// and objects kept "moving" through the blind band.
  /// "paper": Algorithm 1 (stack-based region growing) + Algorithm 2 as published: Ceres,
  /// num_th^s = 1000 (the paper gives no figure; 1000 keeps the Ceres ego solve near a
  /// millisecond), num_th^m = 200.
  /// "fast": the same regions found by union-find labelling, the same least-squares problems in
  /// closed form on every point, gathered in one pass over the image.
  static MotionPipelineParams preset(const std::string& method);
  static std::vector<std::string> preset_names();
  /// The project's default method: "tracked".
  static std::string default_method();
};

struct ClusterEstimate {
  std::int32_t id = 0;    ///< label value in MotionEstimate::labels
  int num_pixels = 0;     ///< pixels in the cluster (before subsampling)
  Eigen::Vector3d centroid_m = Eigen::Vector3d::Zero();  ///< mean position, rig frame [m]
  VelocityEstimate velocity;  ///< absolute velocity in the rig frame (Eq. 22) [m/s]
  /// With tracking: velocity holds the track's velocity at its centre; these say more.
  std::int32_t track_id = 0;  ///< 0 = not tracked
  int track_hits = 0;         ///< frames the track has been updated in
  int carried_pixels = 0;     ///< pixels the track claimed or labelled that one scan labelled static
  double yaw_rate_rps = VelocityEstimate::kNaN;  ///< the track's yaw rate [rad/s]
  Eigen::Vector3d centre_m = Eigen::Vector3d::Constant(VelocityEstimate::kNaN);  ///< box centre, rig frame [m]
  Eigen::Vector3d scan_velocity_mps = Eigen::Vector3d::Constant(VelocityEstimate::kNaN);  ///< the single-scan estimate
};

struct StageTiming {
  double clustering_ms = 0.0;
  double ego_ms = 0.0;
  double objects_ms = 0.0;  ///< object velocities, and tracking when enabled
  double total_ms = 0.0;
};

enum class MotionStatus {
  kOk,
  kNoValidPoints,        ///< the scan has no valid pixel: nothing is estimated
  kTooFewStaticPoints,   ///< fewer than 3 static points or a rank-deficient ego problem:
                         ///< labels are set, no velocity is estimated
};

struct MotionEstimate {
  MotionStatus status = MotionStatus::kOk;
  std::string message;  ///< empty when status is kOk
  std::string method;
  int rows = 0;
  int cols = 0;
  /// Per pixel: Segmentation::kInvalid (-1), kStatic (0), a cluster id (1..), or kUnassigned (-2).
  std::vector<std::int32_t> labels;
  int num_static_pixels = 0;
  VelocityEstimate ego;  ///< the rig's velocity in its own frame, from static points (Eq. 21)
  Eigen::Vector3d ego_angular_velocity_rps = Eigen::Vector3d::Zero();  ///< robust: yaw rate in z
  bool ego_yaw_rate_estimated = false;
  bool ego_standing = false;  ///< robust: the zero-velocity test held
  /// False on an ego-compensated scan (Scan::velocity_frame): ego and its angular velocity are
  /// NaN then, not estimates. Undo the compensation with known ego motion to measure it.
  bool ego_measurable = true;
  std::vector<ClusterEstimate> clusters;
  StageTiming timing;

  bool ok() const { return status == MotionStatus::kOk; }
};

std::string to_string(MotionStatus status);

struct PipelineWorkspace;  // internal to core

/// Buffers the robust methods fill anew each frame, kept from frame to frame so that a sequence
/// does not allocate (and fault in) megabytes per frame. A copy starts with empty buffers.
class PipelineBuffers {
 public:
  PipelineBuffers();
  PipelineBuffers(const PipelineBuffers&);
  PipelineBuffers& operator=(const PipelineBuffers&);
  PipelineBuffers(PipelineBuffers&&) noexcept;
  PipelineBuffers& operator=(PipelineBuffers&&) noexcept;
  ~PipelineBuffers();
  PipelineWorkspace& get() const { return *p_; }

 private:
  std::unique_ptr<PipelineWorkspace> p_;
};

/// Runs the configured method. Throws std::invalid_argument for a malformed scan (sizes, heads,
/// NaN/Inf in valid pixels); a scan with nothing to estimate is a status, not an exception.
class MotionPipeline {
 public:
  explicit MotionPipeline(const MotionPipelineParams& params = MotionPipelineParams::preset(MotionPipelineParams::default_method()));
  MotionEstimate process(const Scan& scan, std::uint64_t frame_index = 0);
  const MotionPipelineParams& params() const { return params_; }

 private:
  MotionEstimate process_in_scan_frame(const Scan& scan, std::uint64_t frame_index);
  MotionEstimate process_robust(const Scan& scan, std::uint64_t frame_index);   // robust_method.cpp
  MotionEstimate process_regions(const Scan& scan, std::uint64_t frame_index);  // region_methods.cpp

  MotionPipelineParams params_;
  DopplerSegmenter segmenter_;
  ObjectTracker tracker_;
  PipelineBuffers buffers_;
  // The last frame's ego twist, for TwistPrior when tracking.
  bool has_last_twist_ = false;
  double last_twist_stamp_s_ = 0.0;
  Eigen::Vector3d last_twist_velocity_ = Eigen::Vector3d::Zero();
  double last_twist_yaw_rate_ = 0.0;
};

}  // namespace fmcw::core
