#pragma once
// Small analytic scenes shared by the core tests.

#include <cmath>

#include "fmcw/core/synthetic_scan.hpp"

namespace fmcw::test {

/// A walled courtyard around the rig, so every beam of the paper rig returns from static
/// surfaces: ground, walls 40 m ahead and 25 m to each side.
inline core::SyntheticSceneParams static_courtyard() {
  core::SyntheticSceneParams p;
  core::SyntheticBox front;
  front.center_m = {41.0, 0.0, 10.0};
  front.half_extent_m = {1.0, 80.0, 30.0};
  core::SyntheticBox left;
  left.center_m = {0.0, 26.0, 10.0};
  left.half_extent_m = {80.0, 1.0, 30.0};
  core::SyntheticBox right = left;
  right.center_m.y() = -26.0;
  p.static_boxes = {front, left, right};
  return p;
}

/// The courtyard with 340 small boxes (0.3 m) 15 m from the front head, 34 azimuths by 10
/// elevations across the paper rig's view, each moving along its beam at 1 to 2.75 m/s, and the
/// ego at 5 m/s: several hundred moving clusters, each apart from the next by static pixels.
inline core::SyntheticSceneParams crowded_courtyard() {
  core::SyntheticSceneParams p = static_courtyard();
  p.ego_velocity_mps = {5.0, 0.0, 0.0};
  p.range_noise_m = 0.025;
  p.velocity_noise_mps = 0.031;
  p.seed = 11;
  const Eigen::Vector3d head(1.4, 0.0, 1.6);
  for (int i = 0; i < 34; ++i) {
    for (int j = 0; j < 10; ++j) {
      const double az = (-55.0 + 110.0 * i / 33.0) * M_PI / 180.0;
      const double el = (-5.0 + 19.0 * j / 9.0) * M_PI / 180.0;
      const Eigen::Vector3d e(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      core::SyntheticBox box;
      box.center_m = head + 15.0 * e;
      box.half_extent_m = Eigen::Vector3d::Constant(0.15);
      box.velocity_mps = (1.0 + 0.25 * ((i + 3 * j) % 8)) * e;
      p.actors.push_back(box);
    }
  }
  return p;
}

/// A car 4.4 m long on a circle of radius r about (cx, 0) at yaw rate w, at time t: it starts
/// at (cx, -r) heading +x.
inline core::SyntheticBox car_on_a_circle(double cx, double r, double w, double t) {
  const double th = -M_PI / 2 + w * t;
  core::SyntheticBox b;
  b.center_m = Eigen::Vector3d(cx + r * std::cos(th), r * std::sin(th), 0.8);
  b.half_extent_m = Eigen::Vector3d(2.2, 0.9, 0.8);
  b.yaw_rad = th + M_PI / 2;
  b.velocity_mps = Eigen::Vector3d(-r * w * std::sin(th), r * w * std::cos(th), 0.0);
  b.yaw_rate_rps = w;
  return b;
}

}  // namespace fmcw::test
