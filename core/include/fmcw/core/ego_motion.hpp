#pragma once
// The rig's own motion from a series of poses (the TUM trajectories real datasets ship), and the
// conversion of a scan's radial velocity between the sensor frame and the ego-compensated frame.

#include <Eigen/Geometry>
#include <vector>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/core/scan.hpp"

namespace fmcw::core {

/// The rig's twist at one instant, in the rig frame.
struct EgoMotion {
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();         ///< of the rig origin [m/s]
  Eigen::Vector3d angular_velocity_rps = Eigen::Vector3d::Zero();  ///< [rad/s]

  /// Velocity of a point fixed to the rig at p_rig (a head's mount): V + omega x p [m/s].
  Eigen::Vector3d point_velocity_mps(const Eigen::Vector3d& p_rig) const {
    return velocity_mps + angular_velocity_rps.cross(p_rig);
  }
};

/// Poses T_world_rig at increasing stamps, as a TUM file lists them (t x y z qx qy qz qw).
struct PoseSeries {
  std::vector<double> stamp_s;                  ///< [s], strictly increasing, finite
  std::vector<Eigen::Vector3d> position_m;      ///< rig origin in the world [m]
  std::vector<Eigen::Quaterniond> orientation;  ///< rig -> world, unit

  /// |q| may differ from 1 by at most this (a TUM file keeps about 6 digits).
  static constexpr double kUnitTolerance = 1e-3;

  std::size_t size() const { return stamp_s.size(); }
  /// core::InputError naming the pose (its index and stamp) for fewer than two poses, arrays of
  /// different lengths, a NaN or Inf, a stamp not after the one before, a non-unit quaternion.
  void validate() const;
  /// The twist at t: positions interpolated linearly and orientations by slerp, differentiated
  /// over one pose interval on each side of t (a central difference at a pose's stamp, exact
  /// for constant velocity and yaw rate; one-sided at the ends). core::InputError when t is
  /// outside [first stamp, last stamp]: no extrapolation.
  EgoMotion ego_motion_at(double t_s) const;
  /// The interpolated pose at t (inside the stamps).
  Eigen::Isometry3d pose_at(double t_s) const;
};

/// Converts a sensor-frame scan to the ego-compensated frame: v += e . V_origin for every valid
/// pixel, with e the unit beam direction from the pixel's head origin (rig frame) and V_origin
/// that origin's velocity (EgoMotion::point_velocity_mps). Throws core::InputError when the scan
/// is already compensated.
void compensate_ego_velocity(Scan& scan, const EgoMotion& ego);
/// The inverse: v -= e . V_origin, back to the raw Doppler of Eq. 6, so that every method
/// (and the ego velocity) works as on a sensor-frame scan. Throws core::InputError when the scan
/// is not compensated.
void uncompensate_ego_velocity(Scan& scan, const EgoMotion& ego);
/// The same for a frame with its truth: the scan as above, and the truth's radial velocity (in
/// the scan's frame, as a dataset writes it) to e . (V_point - V_origin) as well.
void uncompensate_ego_velocity(Frame& frame, const EgoMotion& ego);

}  // namespace fmcw::core
