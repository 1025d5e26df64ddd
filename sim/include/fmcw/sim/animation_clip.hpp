#pragma once
// Keyframe clips (glTF 2.0 animation samplers, or assimp's node animations): each animated node
// property is a curve of keys, sampled with its exact time derivative so that the simulator's
// surface velocities stay analytic (never a finite difference).

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace fmcw::sim {

/// glTF 2.0 sampler interpolation (Appendix C of the specification).
enum class Interpolation { kStep, kLinear, kCubicSpline };
const char* to_string(Interpolation interpolation);

/// Keys of one animated property. width 3: translation or scale (x y z); width 4: rotation as a
/// quaternion x y z w (glTF order). kCubicSpline stores three values per key: in-tangent, value,
/// out-tangent (tangents per second, as glTF does).
struct KeyCurve {
  Interpolation interpolation = Interpolation::kLinear;
  int width = 3;
  std::vector<double> times_s;  ///< strictly increasing
  std::vector<double> values;   ///< width (x3 for kCubicSpline) per key

  bool empty() const { return times_s.empty(); }
  /// Throws std::invalid_argument, prefixed by `where`, for: no key, key and value counts that
  /// disagree, non-finite times or values, times not strictly increasing, a zero quaternion.
  void validate(const std::string& where) const;
  /// Value at t and its exact derivative d/dt; before the first key and after the last the
  /// curve holds its end value (derivative 0). A kStep curve holds each key until the next
  /// (derivative 0). For width 3.
  void sample_vector(double t_s, Eigen::Vector3d& value, Eigen::Vector3d& rate) const;
  /// Rotation at t and its angular velocity omega in the parent frame (dR/dt = [omega]x R).
  /// kLinear is glTF's slerp along the shorter arc, so omega is constant over a segment:
  /// axis * angle / segment duration. kCubicSpline is the Hermite spline of the quaternion
  /// components, normalised, as the specification defines it; omega = 2 (q' q*) of the
  /// normalised quaternion's exact derivative. For width 4.
  void sample_rotation(double t_s, Eigen::Quaterniond& value, Eigen::Vector3d& omega) const;
};

/// The animated properties of one node (part). An empty curve leaves that property at rest.
struct NodeTrack {
  int part = -1;  ///< index into MeshAsset::parts
  KeyCurve translation;
  KeyCurve rotation;
  KeyCurve scale;
};

/// A node's rest transform as translation, rotation and scale: L = T R S (glTF's order).
struct NodeTrs {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();
};

struct AnimationClip {
  std::string name;
  double duration_s = 0.0;       ///< the last key of any curve; the clip plays over [0, duration]
  double nominal_speed_mps = 0;  ///< speed the clip was made for (glTF extras.nominal_speed_mps); 0: not given
  std::vector<NodeTrack> tracks;
  /// The local transform L(t) = T R S of track k at clip time t (rest values for the curves it
  /// lacks) and its exact derivative dL/dt, as 4x4 matrices (last row of dL/dt is zero).
  void local_transform(std::size_t track, const NodeTrs& rest, double t_s, Eigen::Matrix4d& L,
                       Eigen::Matrix4d& L_dot) const;
};

/// How an actor plays a clip: its clip time tau(t) and d tau / dt.
struct ClipPlayback {
  enum class Clock { kTime, kDistance };
  Clock clock = Clock::kTime;
  double speed = 1.0;              ///< clip seconds per clock second
  bool loop = true;                ///< wrap tau into [0, duration); else hold the end poses
  double start_s = 0.0;            ///< kTime: scene time the clip starts (it holds its first pose before)
  double offset_s = 0.0;           ///< clip time at the start
  double nominal_speed_mps = 0.0;  ///< kDistance: path speed at which one clock second passes

  /// Clip time and its rate at scene time t, for a body that has travelled distance_m along its
  /// path at speed_mps (both used by kDistance only: tau = offset + speed * distance / nominal,
  /// so the clip's cadence follows the path speed and it rests while the body stands).
  void clip_time(double duration_s, double t_s, double distance_m, double speed_mps, double& tau,
                 double& tau_rate) const;
};

}  // namespace fmcw::sim
