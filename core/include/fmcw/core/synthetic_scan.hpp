#pragma once
// Analytic scenes (a ground plane and oriented boxes) cast exactly, for tests, benchmarks and
// demonstrations without the full simulator. Every quantity is known in closed form.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "fmcw/core/ground_truth.hpp"
#include "fmcw/core/head_model.hpp"

namespace fmcw::core {

/// A box in the rig frame at the scan instant, rotating about its own vertical axis.
struct SyntheticBox {
  Eigen::Vector3d center_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d half_extent_m = Eigen::Vector3d::Constant(0.5);
  double yaw_rad = 0.0;
  Eigen::Vector3d velocity_mps = Eigen::Vector3d::Zero();  ///< of the centre, rig axes
  double yaw_rate_rps = 0.0;                               ///< about the box's vertical axis
  float reflectivity = 0.3f;
};

struct SyntheticSceneParams {
  RigModel rig = RigModel::paper_rig();
  bool ground = true;
  double ground_z_m = 0.0;  ///< ground plane height in the rig frame [m]
  std::vector<SyntheticBox> static_boxes;  ///< part of the static world (instance 0)
  std::vector<SyntheticBox> actors;        ///< actor k has instance k + 1 (may be static)
  Eigen::Vector3d ego_velocity_mps = Eigen::Vector3d::Zero();          ///< rig origin, rig axes
  Eigen::Vector3d ego_angular_velocity_rps = Eigen::Vector3d::Zero();  ///< rig axes
  double range_noise_m = 0.0;       ///< Gaussian sigma [m] (Table I: 0.025)
  double velocity_noise_mps = 0.0;  ///< Gaussian sigma [m/s] (Table I: 0.031)
  double moving_threshold_mps = 0.1;  ///< ground truth "moving" above this absolute speed [m/s]
  std::uint64_t seed = 0;

  void validate() const;
};

/// Casts every beam of the rig. Doppler by Eq. 6 from each head's origin, whose velocity is
/// V_ego + omega x r_mount; surface velocity v + omega_box x (p - c) for boxes, zero for the
/// static world.
Frame render_synthetic_scan(const SyntheticSceneParams& params);

/// The benchmark frame: the paper rig driving at 10 m/s down a street lined with buildings,
/// with num_actors boxes (cars) moving in various directions.
SyntheticSceneParams benchmark_scene(int num_actors, std::uint64_t seed = 1);

}  // namespace fmcw::core
