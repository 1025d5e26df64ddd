#pragma once
// What only a simulator knows, per pixel, beside the Scan a sensor delivers.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "fmcw/core/scan.hpp"

namespace fmcw::core {

/// Per-pixel truth, arrays of rows * cols in the Scan's order. Velocities in the rig frame.
struct PixelGroundTruth {
  std::vector<float> range_m;              ///< noise-free range [m]; NaN where no return
  std::vector<float> radial_velocity_mps;  ///< noise-free Doppler (Eq. 6) [m/s]
  std::vector<float> vx_mps, vy_mps, vz_mps;  ///< true surface velocity [m/s] (world motion, rig axes)
  std::vector<std::uint32_t> instance;     ///< 0 = static world, else actor id
  std::vector<std::uint8_t> moving;        ///< 1 where the surface's absolute speed exceeds the threshold
  /// Semantic class id of the surface hit (semantic_classes.hpp; 0 where no return). Empty for
  /// a dataset written before classes were: then the only field that may be missing.
  std::vector<std::uint16_t> semantic_class;

  static PixelGroundTruth make_empty(std::size_t n);
  /// Throws std::invalid_argument when a field does not hold n values.
  void validate(std::size_t n) const;
};

/// The rig's motion at the frame's time.
struct EgoTruth {
  Eigen::Isometry3d T_world_rig = Eigen::Isometry3d::Identity();
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();        ///< of the rig origin, rig axes
  Eigen::Vector3d angular_velocity_rps = Eigen::Vector3d::Zero();  ///< rig axes
};

/// An actor's oriented 3D box at the frame's time: tight around its surface at that instant
/// (limbs and wheels included), its length along the body's heading.
struct BoxTruth {
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();  ///< rig frame
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();    ///< length (along the heading), width, height
  double yaw_rad = 0.0;                                ///< heading about the rig's z axis
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();  ///< of the box centre: world motion in rig axes
  Eigen::Vector3d center_world_m = Eigen::Vector3d::Zero();
  double yaw_world_rad = 0.0;  ///< heading about the world's z axis
  /// The actor's pixels over the pixels whose beams meet the box within range, occluded or not.
  double visible_fraction = 0.0;
  bool truncated = false;  ///< a corner of the box lies outside every head's field of view
};

/// One actor at the frame's time. Velocities are absolute (world motion) expressed in rig axes,
/// as the estimators report them; the reference point is the actor's origin (the centre of its
/// footprint on the ground).
struct ActorTruth {
  std::uint32_t id = 0;
  std::string class_name;
  Eigen::Isometry3d T_world_actor = Eigen::Isometry3d::Identity();
  Eigen::Vector3d position_rig_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_rig_mps = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_rig_rps = Eigen::Vector3d::Zero();
  int pixels = 0;  ///< pixels of this frame that hit the actor
  BoxTruth box;
};

struct FrameTruth {
  double stamp_s = 0.0;
  EgoTruth ego;
  std::vector<ActorTruth> actors;
};

/// One frame: the scan and, for simulated data, its ground truth.
struct Frame {
  Scan scan;
  std::optional<PixelGroundTruth> truth;
  std::optional<FrameTruth> frame_truth;
};

}  // namespace fmcw::core
