#pragma once
// Ego motion from Doppler without trusting "the largest region is static": robust estimation
// of the rig's velocity and yaw rate over all valid points.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "fmcw/core/scan.hpp"
#include "fmcw/core/velocity_lsq.hpp"

namespace fmcw::core {

struct EgoTwistParams {
  double noise_sigma_mps = 0.031;       ///< Doppler noise of the sensor [m/s] (Table I)
  double inlier_threshold_mps = 0.1;    ///< RANSAC: |residual| below this is an inlier [m/s]
  int ransac_iterations = 150;          ///< minimal-set hypotheses at most (each new best is refit on its inliers)
  /// Early termination: once the best hypothesis holds inliers in every azimuth column, MSAC
  /// stops after enough minimal sets to have drawn an all-inlier one with this confidence
  /// (from its inlier fraction), but not before min_ransac_iterations.
  double ransac_confidence = 0.999;
  int min_ransac_iterations = 30;
  int sample_points = 3000;             ///< points RANSAC scores hypotheses on (seeded subset)
  /// Also estimate the yaw rate: possible when heads sit at different mount points, since each
  /// head's origin moves at V + omega x r_head. With one mount point it is not observable and
  /// is left at 0.
  bool estimate_yaw_rate = true;
  /// Hypotheses turning faster than this are rejected [rad/s]: with heads at separate mounts a
  /// wild yaw rate could otherwise give each head its own velocity and stitch a passing truck
  /// in one head to the static world in another. Road vehicles stay well below 1 rad/s.
  double max_yaw_rate_rps = 1.5;
  /// Refinement, with the yaw rate estimated: the rig origin's lateral velocity is pulled
  /// towards zero with this standard deviation (a car's rear axle, where the rig origin sits,
  /// does not slide sideways); 0 = no pull. It decides only what the points leave open: with the
  /// static world ahead alone, lateral velocity and yaw rate trade off [m/s].
  double lateral_velocity_sigma_mps = 0.0;
  double huber_k_sigma = 2.0;  ///< refinement: Huber weights beyond k sigma
  int min_inliers = 20;        ///< fewer static-consistent points: no estimate (not a world)
  int refine_iterations = 3;
  /// Standing test: when the zero twist explains the points as well as the best hypothesis
  /// (coverage and inliers within these fractions), the ego is declared standing.
  double standing_coverage_fraction = 0.98;

  void validate() const;
};

/// The rig's twist: V at the rig origin and omega, rig frame. A static point seen from head k
/// has Doppler v = -e . (V + omega x r_k), i.e. the row [e, r_k x e] . [V; omega] = -v.
struct EgoTwistEstimate {
  VelocityEstimate velocity;                  ///< V, with covariance and conditioning
  Eigen::Vector3d angular_velocity_rps = Eigen::Vector3d::Zero();
  double yaw_rate_std_rps = 0.0;              ///< from the covariance; 0 when not estimated
  bool yaw_rate_estimated = false;            ///< false with one mount point, or if disabled
  bool standing = false;                      ///< the zero-velocity test held: V = omega = 0
  int inliers = 0;                            ///< static-consistent points of the final fit
  double inlier_fraction = 0.0;               ///< of the valid points
  bool valid = false;
  /// With a prior whose window held no world: the fit without the window lay further from the
  /// prior than TwistPrior::max_fallback_change_mps (traffic that fills the view, taken for the
  /// world), so the frame has no estimate. What that fit said, for the message:
  bool fallback_rejected = false;
  Eigen::Vector3d rejected_velocity_mps = Eigen::Vector3d::Zero();
  int rejected_inliers = 0;

  /// Velocity of a point fixed to the rig at r (rig frame): V + omega x r.
  Eigen::Vector3d velocity_at(const Eigen::Vector3d& r) const { return velocity.velocity_mps + angular_velocity_rps.cross(r); }
};

/// What the previous frame says about this one's twist: a rig cannot change its velocity or
/// yaw rate by more than its acceleration allows between two frames. Hypotheses outside the
/// window are rejected, and the previous twist is itself a hypothesis. This keeps the ego from
/// jumping to vehicles that together fill most of the view (a bus on one side, a truck on the
/// other, each explained as "static" by a wild yaw rate).
/// How far one frame's twist may move from the previous one's (the window of TwistPrior): by
/// acceleration times the frame gap, plus a margin.
struct TwistPriorParams {
  double accel_mps2 = 8.0;           ///< [m/s^2]
  double velocity_margin_mps = 0.3;  ///< [m/s]
  double yaw_accel_rps2 = 2.0;       ///< [rad/s^2]
  double yaw_rate_margin_rps = 0.1;  ///< [rad/s]
  /// When nothing inside the window finds a world, the frame is estimated afresh; that twist is
  /// taken only if its velocity lies within this many windows of the prior's, else the frame has
  /// no ego velocity (oncoming traffic that fills the view looks static to a rig driving at the
  /// sum of both speeds). 0 takes the fresh twist whatever it says.
  double fallback_max_windows = 3.0;
  /// The last valid twist stays the prior through frames without one (its window growing with
  /// the time since), instead of lapsing after a failed frame or a gap over the tracker's
  /// max_gap_s: one frame of traffic filling the view must not free the next from the bound.
  bool hold_across_failures = true;

  void validate() const;
};

struct TwistPrior {
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();
  double yaw_rate_rps = 0.0;
  double max_velocity_change_mps = 1.0;
  double max_yaw_rate_change_rps = 0.3;
  /// A fresh estimate (the window held no world) further than this from velocity_mps is
  /// rejected [m/s]; 0 = never rejected.
  double max_fallback_change_mps = 0.0;
};

/// MSAC over minimal sets (3 points, or 4 with the yaw rate), each hypothesis scored first by
/// how many azimuth columns of a coarse 24 x 6 grid over the image hold its inliers (the static
/// world shows in nearly every azimuth, a bus beside or across the rig in a band of them), then
/// by how many cells, then by its truncated squared residuals; then Huber IRLS on all valid
/// points. Seeded: reproducible.
/// With a prior, hypotheses outside its window are rejected; when nothing inside the window
/// finds min_inliers points, the estimate starts afresh without the prior, and is rejected
/// (fallback_rejected, not valid) when it lies beyond max_fallback_change_mps of the prior.
EgoTwistEstimate estimate_ego_twist(const Scan& scan, const EgoTwistParams& params, std::uint64_t seed,
                                    const TwistPrior* prior = nullptr);

}  // namespace fmcw::core
