#pragma once
// Time-parameterised rigid motion of actors and the ego vehicle, with exact time derivatives.

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

namespace fmcw::sim {

/// Velocity of a rigid body in the world frame: linear_mps is the velocity of the body's origin,
/// angular_rps its angular velocity. A point p of the body moves at linear + angular x (p - origin).
struct Twist {
  Eigen::Vector3d linear_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_rps = Eigen::Vector3d::Zero();
};

/// Pose and twist of a body at one instant. The twist is the exact time derivative of the pose:
/// d/dt origin = linear_mps, d/dt R = [angular_rps]x R.
struct MotionState {
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Twist twist;
  /// Path length the body origin has travelled since t = 0 (negative before it for the constant
  /// motions, which have always moved); its time derivative is |twist.linear_mps| [m].
  double distance_m = 0.0;
};

/// Body frame convention: x forward, y left, z up; planar vehicles yaw about world z.
/// Implementations are immutable after construction, so state() may be called from many threads.
class Trajectory {
 public:
  virtual ~Trajectory() = default;
  /// Throws std::invalid_argument for a non-finite time.
  virtual MotionState state(double t_s) const = 0;
};

/// Never moves. The factories below throw std::invalid_argument for non-finite arguments and
/// for a pose whose linear part is not a proper rotation (|R^T R - I| >= 1e-6 or det R <= 0).
std::unique_ptr<Trajectory> make_static_trajectory(const Eigen::Isometry3d& T_world_body);

/// Constant linear velocity (world frame) from the pose at t = 0; orientation fixed.
std::unique_ptr<Trajectory> make_constant_velocity_trajectory(const Eigen::Isometry3d& T_world_body_at_0,
                                                              const Eigen::Vector3d& velocity_world_mps);

/// Planar constant speed and constant yaw rate from the pose at t = 0: the body moves along its
/// own x axis and turns about world z, tracing a circle of radius speed / yaw_rate (a straight
/// line when yaw_rate is 0). Exact closed form; tiny yaw rates use a series instead of dividing
/// by yaw_rate. A negative speed drives backwards; a negative yaw rate turns clockwise (right).
/// If the initial pose is pitched, the body still moves along its own x axis and so climbs or
/// descends along a helix whose horizontal radius is speed * cos(pitch) / yaw_rate.
std::unique_ptr<Trajectory> make_constant_turn_rate_trajectory(const Eigen::Isometry3d& T_world_body_at_0,
                                                               double speed_mps, double yaw_rate_rps);

struct WaypointPath {
  /// World positions of the body origin, >= 2; consecutive points must be distinct (more than
  /// 1 um apart). A later point may revisit an earlier one, e.g. to close a loop.
  std::vector<Eigen::Vector3d> points_m;
  /// Speed at each waypoint [m/s], linearly interpolated along the path by arc length; one value
  /// means constant speed. Speeds must be >= 0 and not all of a segment's ends 0.
  /// A segment with one end at 0 m/s would take infinite time under a speed linear in arc length
  /// (ds/dt = a s never leaves s = 0), so such a segment accelerates (or brakes) uniformly
  /// instead: speed^2 is linear in arc length there, and the segment of length L takes
  /// 2 L / v_other seconds. So a path may start from rest, stop at a waypoint and go on, or end
  /// at rest, with continuous velocity.
  std::vector<double> speeds_mps;
  double start_time_s = 0.0;  ///< before this, the body waits at the first point
  /// Time the body stands still at each waypoint before it goes on [s]: empty (no waits) or one
  /// value per point, each finite and >= 0; a wait > 0 needs the speed 0 at that point (the
  /// body arrives there at rest, so its velocity stays continuous). A wait at the last point
  /// changes nothing: the body rests there anyway.
  std::vector<double> waits_s;
  // From start_time_s on it moves (at the first speed); after the end of the path it stays at
  // the last point, at rest.
};

/// Follows a smooth curve through the waypoints (C1 at least: no heading jumps), heading along
/// the tangent, so vehicles turn with yaw rate = speed x curvature. Pitch and roll stay 0.
/// Throws std::invalid_argument naming the problem (fewer than 2 points, repeated points,
/// speed count mismatch, negative speed).
///
/// The curve is a natural cubic spline (C2, zero curvature at both ends) in x, y and z over the
/// cumulative chord length, re-parameterised by its arc length through a table (64 samples per
/// span, Gauss-Legendre arc lengths, quintic Hermite inverse). The body's x axis is the
/// horizontal tangent; the velocity follows the 3D tangent, so it has a vertical component on
/// slopes. Arc length as a function of time is closed form per span (exponential for a speed
/// linear in arc length, quadratic for uniform acceleration), so state() costs two binary
/// searches and allocates nothing. The returned twist is the exact derivative of the returned
/// pose. Also throws when the spline is (nearly) vertical or doubles back on itself somewhere
/// (horizontal tangent below 5% of the chord rate), where the heading would be undefined.
/// Waypoint indices in messages count from 0.
std::unique_ptr<Trajectory> make_waypoint_trajectory(const WaypointPath& path);

/// One joint of an articulated part: a rotation about a fixed axis of the part's rest frame.
/// Angle(t) = offset + amplitude * sin(2 pi frequency t + phase) + spin_rate * t.
struct JointMotion {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();  ///< unit axis in the part's rest frame
  double offset_rad = 0.0;
  double amplitude_rad = 0.0;
  double frequency_hz = 0.0;
  double phase_rad = 0.0;
  double spin_rate_rps = 0.0;

  double angle_rad(double t_s) const;
  double rate_rps(double t_s) const;  ///< exact derivative of angle_rad
};

/// Procedural walking gait for the project's pedestrian (tools/assets, nodes upper_leg_l/r,
/// lower_leg_l/r, upper_arm_l/r, lower_arm_l/r; positive rotation about local +y swings a limb's
/// lower end backwards). Step frequency and swing amplitudes grow with walking speed; legs swing
/// in antiphase, each arm opposite its leg, knees and elbows flex. Returns (node name, motion)
/// pairs; speed 0 gives a standing pose (all rates 0).
///
/// Stride frequency (one full cycle of one leg) is 0.93 Hz * (speed / 1.4 m/s)^0.35, i.e. a
/// cadence of about 112 steps/min at 1.4 m/s. The hip amplitude makes the leg (0.9 m, hip to
/// sole) span one step: sin(amplitude) = step / (2 * 0.9 m), step = speed / (2 * frequency),
/// about 25 deg at 1.4 m/s, capped at 40 deg. Knees flex backward only (angle in [0, 2 * knee
/// amplitude], peak in early swing); elbows stay flexed (angle < 0). Order: upper_leg_l,
/// lower_leg_l, upper_leg_r, lower_leg_r, upper_arm_l, lower_arm_l, upper_arm_r, lower_arm_r.
/// Throws std::invalid_argument for a negative or non-finite speed.
std::vector<std::pair<std::string, JointMotion>> pedestrian_gait(double speed_mps);

}  // namespace fmcw::sim
