#pragma once
// Small pieces the simulator tests share: poses, noise-free parameters, the distance of a
// point on a rolling wheel to the line about which it turns.

#include <Eigen/Geometry>
#include <vector>

#include "fmcw/sim/lidar_simulator.hpp"

namespace fmcw::test {

/// A pose at (x, y, z), yawed about +z [rad].
inline Eigen::Isometry3d at(double x, double y, double z, double yaw = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, z);
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

/// Simulator parameters for a rig with no measurement noise.
inline sim::LidarSimulatorParams noise_free(core::RigModel rig) {
  sim::LidarSimulatorParams p;
  p.rig = std::move(rig);
  p.measurement.range_sigma_m = 0.0;
  p.measurement.velocity_sigma_mps = 0.0;
  return p;
}

/// Distance from p to the nearest of the lines through `contacts` along unit `axle`: a wheel
/// rolling without slip turns about the line where it touches the ground.
inline double distance_to_contact_line(const Eigen::Vector3d& p, const std::vector<Eigen::Vector3d>& contacts,
                                       const Eigen::Vector3d& axle) {
  double nearest = 1e9;
  for (const auto& c : contacts) {
    const Eigen::Vector3d d = p - c;
    nearest = std::min(nearest, (d - d.dot(axle) * axle).norm());
  }
  return nearest;
}

}  // namespace fmcw::test
